//! Plans as sequences of ground actions by name, and their text form (one `(action arg ...)` per
//! line, the format Fast Downward writes to `sas_plan`; lines starting with `;` are comments).

use std::fmt;

use thiserror::Error;

/// One step of a plan: an action schema and the objects bound to its parameters, in order.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct PlanStep {
    pub action: String,
    pub arguments: Vec<String>,
}

impl fmt::Display for PlanStep {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}", self.action)?;
        for argument in &self.arguments {
            write!(f, " {argument}")?;
        }
        write!(f, ")")
    }
}

/// A sequential plan.
#[derive(Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Plan {
    pub steps: Vec<PlanStep>,
}

impl Plan {
    /// Number of steps.
    #[must_use]
    pub fn len(&self) -> usize {
        self.steps.len()
    }

    /// Whether the plan has no step (the goal holds initially).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }

    /// Reads the text form; names are lowered (PDDL names are case-insensitive).
    ///
    /// # Errors
    /// [`PlanParseError`] naming the first line that is not `(name arg ...)`.
    pub fn parse(text: &str) -> Result<Self, PlanParseError> {
        let mut steps = Vec::new();
        for (index, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with(';') {
                continue;
            }
            let inner = line
                .strip_prefix('(')
                .and_then(|rest| rest.strip_suffix(')'))
                .ok_or_else(|| PlanParseError { line: index + 1, text: line.to_owned() })?;
            let mut words = inner.split_whitespace().map(str::to_ascii_lowercase);
            let action = words
                .next()
                .ok_or_else(|| PlanParseError { line: index + 1, text: line.to_owned() })?;
            steps.push(PlanStep { action, arguments: words.collect() });
        }
        Ok(Self { steps })
    }
}

impl fmt::Display for Plan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for step in &self.steps {
            writeln!(f, "{step}")?;
        }
        Ok(())
    }
}

/// A line of a plan file that is not a step.
#[derive(Clone, Debug, PartialEq, Eq, Error, miette::Diagnostic)]
#[error("plan line {line} is not `(action argument ...)`: {text}")]
#[diagnostic(code(lamp::plan::syntax))]
pub struct PlanParseError {
    pub line: usize,
    pub text: String,
}
