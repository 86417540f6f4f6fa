//! The grounded task: integer-indexed facts and operators, the initial state and the goal.
//!
//! Facts are the fluent ground atoms reachable in the delete relaxation, numbered in order of
//! (predicate name, argument names). Operators are numbered in order of (action position in the
//! domain, argument names). Static atoms (of predicates no action changes) are compiled away.

use std::fmt;

/// Index of a fact in [`GroundTask::facts`].
pub type FactId = u32;
/// Index of an operator in [`GroundTask::operators`].
pub type OperatorId = u32;

/// A ground atom by name.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GroundAtom {
    pub predicate: String,
    pub arguments: Vec<String>,
}

impl fmt::Display for GroundAtom {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}", self.predicate)?;
        for argument in &self.arguments {
            write!(f, " {argument}")?;
        }
        write!(f, ")")
    }
}

/// A ground action: the schema's name and arguments, and its conditions and effects on facts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Operator {
    pub action: String,
    pub arguments: Vec<String>,
    /// Facts that must hold (sorted, deduplicated).
    pub precondition: Vec<FactId>,
    /// Facts that must not hold (sorted, deduplicated).
    pub negative_precondition: Vec<FactId>,
    /// Facts made true (sorted; applied after the deletes).
    pub add: Vec<FactId>,
    /// Facts made false (sorted).
    pub delete: Vec<FactId>,
}

impl fmt::Display for Operator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}", self.action)?;
        for argument in &self.arguments {
            write!(f, " {argument}")?;
        }
        write!(f, ")")
    }
}

/// Why grounding already proves the task unsolvable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GroundingVerdict {
    /// The search has something to do.
    Open,
    /// A goal literal can never hold: a positive goal atom unreachable in the delete relaxation, or
    /// a static goal literal false in the initial state.
    GoalUnreachable { literal: String },
}

/// A grounded STRIPS task.
#[derive(Clone, Debug)]
pub struct GroundTask {
    pub facts: Vec<GroundAtom>,
    pub operators: Vec<Operator>,
    /// Facts true initially (sorted).
    pub initial: Vec<FactId>,
    /// Facts the goal requires (sorted).
    pub goal: Vec<FactId>,
    /// Facts the goal forbids (sorted).
    pub negative_goal: Vec<FactId>,
    pub verdict: GroundingVerdict,
}

impl GroundTask {
    /// Number of facts.
    #[must_use]
    pub fn fact_count(&self) -> usize {
        self.facts.len()
    }
}
