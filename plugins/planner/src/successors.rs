//! The operators applicable in a state, without testing every operator.
//!
//! Each operator is filed under one of its preconditions, its key; an operator can only be
//! applicable where its key holds, so only the operators filed under the state's true facts are
//! tested. The key is the precondition false in the initial state (such facts tend to hold in few
//! states: "this block is held") that the fewest operators share, or, when every precondition holds
//! initially, the one the fewest operators share. On learned stacking domains this tests a few
//! percent of the operators per expansion instead of all of them.

use crate::state::State;
use crate::task::{GroundTask, OperatorId};

/// Operators filed under their key precondition, and those without preconditions.
#[derive(Debug)]
pub struct Successors {
    by_key: Vec<Vec<OperatorId>>,
    unconditional: Vec<OperatorId>,
}

impl Successors {
    /// The index of `task`'s operators.
    #[must_use]
    pub fn new(task: &GroundTask) -> Self {
        let mut sharing = vec![0_usize; task.fact_count()];
        for operator in &task.operators {
            for &fact in &operator.precondition {
                sharing[fact as usize] += 1;
            }
        }
        let initial = State::from_facts(task.fact_count(), &task.initial);
        let mut by_key = vec![Vec::new(); task.fact_count()];
        let mut unconditional = Vec::new();
        for (id, operator) in (0..).zip(&task.operators) {
            let key = operator
                .precondition
                .iter()
                .min_by_key(|&&fact| (initial.holds(fact), sharing[fact as usize], fact));
            match key {
                Some(&fact) => by_key[fact as usize].push(id),
                None => unconditional.push(id),
            }
        }
        Self { by_key, unconditional }
    }

    /// The operators applicable in `state`, in increasing id order.
    #[must_use]
    pub fn applicable(&self, task: &GroundTask, state: &State) -> Vec<OperatorId> {
        let mut found: Vec<OperatorId> = state
            .facts()
            .into_iter()
            .flat_map(|fact| &self.by_key[fact as usize])
            .chain(&self.unconditional)
            .copied()
            .filter(|&id| state.applicable(&task.operators[id as usize]))
            .collect();
        found.sort_unstable();
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::task::{GroundAtom, GroundingVerdict, Operator};

    fn operator(pre: &[u32], not: &[u32]) -> Operator {
        Operator {
            action: "a".into(),
            arguments: Vec::new(),
            precondition: pre.to_vec(),
            negative_precondition: not.to_vec(),
            add: vec![3],
            delete: Vec::new(),
        }
    }

    /// The index finds exactly the operators a test of every operator finds, in id order.
    #[test]
    fn the_index_finds_what_testing_every_operator_finds() {
        let task = GroundTask {
            facts: (0..4)
                .map(|k| GroundAtom { predicate: format!("f{k}"), arguments: Vec::new() })
                .collect(),
            operators: vec![
                operator(&[0, 1], &[]),
                operator(&[], &[2]),
                operator(&[1], &[]),
                operator(&[2, 0], &[]),
                operator(&[], &[]),
                operator(&[0], &[3]),
            ],
            initial: vec![0],
            goal: vec![3],
            negative_goal: Vec::new(),
            verdict: GroundingVerdict::Open,
        };
        let successors = Successors::new(&task);
        for facts in [vec![], vec![0], vec![0, 1], vec![1, 2], vec![0, 1, 2, 3], vec![0, 2]] {
            let state = State::from_facts(4, &facts);
            let every: Vec<OperatorId> = (0..)
                .zip(&task.operators)
                .filter(|(_, operator)| state.applicable(operator))
                .map(|(id, _)| id)
                .collect();
            assert_eq!(successors.applicable(&task, &state), every, "in {facts:?}");
        }
    }
}
