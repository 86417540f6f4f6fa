//! A cheap dead-end test: a goal literal lost for good.
//!
//! A fact that no operator adds stays false once false, and one that no operator deletes stays true
//! once true. An operator that needs such a fact the other way round is disabled for good. A goal
//! fact that is false, and whose every achiever is disabled for good, can never hold again; nor can
//! a forbidden goal fact that is true and that no operator deletes. Either proves a dead end.
//!
//! The FF relaxation finds the first kind too, but it explores every operator to do so; on learned
//! stacking domains most successors of a placement are such dead ends (a block put on the wrong
//! marker is on a marker for good, and the blocks that were to go across it can no longer), and
//! this test settles each by looking at the achievers of the goal facts alone. It also sees the
//! negative preconditions the relaxation ignores.

use crate::state::State;
use crate::task::{FactId, GroundTask, OperatorId};

/// The goal facts' achievers and, per operator, the conditions that can never become true again
/// once false.
#[derive(Debug)]
pub struct LostGoals {
    /// Each goal fact with the operators that add it.
    achievers: Vec<(FactId, Vec<OperatorId>)>,
    /// Forbidden goal facts that no operator deletes.
    stuck_forbidden: Vec<FactId>,
    /// Per goal achiever: `(fact, needed value)` for each precondition on a fact that cannot
    /// change back (empty for the other operators).
    locks: Vec<Vec<(FactId, bool)>>,
}

impl LostGoals {
    /// The test for `task`.
    #[must_use]
    pub fn new(task: &GroundTask) -> Self {
        let mut added = vec![false; task.fact_count()];
        let mut deleted = vec![false; task.fact_count()];
        let mut achievers: Vec<(FactId, Vec<OperatorId>)> =
            task.goal.iter().map(|&fact| (fact, Vec::new())).collect();
        for (id, operator) in (0..).zip(&task.operators) {
            for &fact in &operator.add {
                added[fact as usize] = true;
                if let Ok(index) = task.goal.binary_search(&fact) {
                    achievers[index].1.push(id);
                }
            }
            for &fact in &operator.delete {
                deleted[fact as usize] = true;
            }
        }
        // Only achievers of goal facts are ever asked; the others keep no locks.
        let mut locks = vec![Vec::new(); task.operators.len()];
        for &operator in achievers.iter().flat_map(|(_, operators)| operators) {
            let definition = &task.operators[operator as usize];
            let positive = definition.precondition.iter().filter(|&&f| !added[f as usize]);
            let negative =
                definition.negative_precondition.iter().filter(|&&f| !deleted[f as usize]);
            locks[operator as usize] = positive
                .map(|&fact| (fact, true))
                .chain(negative.map(|&fact| (fact, false)))
                .collect();
        }
        let stuck_forbidden =
            task.negative_goal.iter().copied().filter(|&fact| !deleted[fact as usize]).collect();
        Self { achievers, stuck_forbidden, locks }
    }

    /// Whether some goal literal can never hold again from `state`.
    #[must_use]
    pub fn any_lost(&self, state: &State) -> bool {
        let disabled = |operator: OperatorId| {
            self.locks[operator as usize].iter().any(|&(fact, needed)| state.holds(fact) != needed)
        };
        self.stuck_forbidden.iter().any(|&fact| state.holds(fact))
            || self.achievers.iter().any(|(fact, achievers)| {
                !state.holds(*fact) && achievers.iter().all(|&operator| disabled(operator))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::task::{GroundAtom, GroundingVerdict, Operator};

    fn operator(
        name: &str,
        pre: &[FactId],
        not: &[FactId],
        add: &[FactId],
        del: &[FactId],
    ) -> Operator {
        Operator {
            action: name.to_string(),
            arguments: Vec::new(),
            precondition: pre.to_vec(),
            negative_precondition: not.to_vec(),
            add: add.to_vec(),
            delete: del.to_vec(),
        }
    }

    /// Facts: 0 = b3 on no marker, 1 = b3 on its marker, 2 = b3 across b1, 3 = b1 on a marker.
    /// Putting b3 on its marker alone (`mark`) loses "across" for good: `across` needs b3 on no
    /// marker, which nothing makes true again.
    fn stacking() -> GroundTask {
        GroundTask {
            facts: (0..4)
                .map(|k| GroundAtom { predicate: format!("f{k}"), arguments: Vec::new() })
                .collect(),
            operators: vec![
                operator("mark", &[0], &[], &[1], &[0]),
                operator("across", &[0, 3], &[], &[1, 2], &[0]),
                operator("base", &[], &[], &[3], &[]),
            ],
            initial: vec![0],
            goal: vec![1, 2],
            negative_goal: Vec::new(),
            verdict: GroundingVerdict::Open,
        }
    }

    #[test]
    fn a_goal_whose_achievers_need_a_fact_gone_for_good_is_lost() {
        let task = stacking();
        let lost = LostGoals::new(&task);
        let initial = State::from_facts(4, &[0]);
        assert!(!lost.any_lost(&initial));
        let marked = initial.apply(&task.operators[0]);
        assert!(lost.any_lost(&marked), "b3 on its marker can no longer go across b1");
        // Across, then the goal: nothing is lost where the goal holds.
        let based = initial.apply(&task.operators[2]);
        assert!(!lost.any_lost(&based));
        assert!(!lost.any_lost(&based.apply(&task.operators[1])));
    }

    #[test]
    fn negative_conditions_and_goals_on_facts_never_deleted_lock_too() {
        let mut task = stacking();
        // `across` now also needs fact 3 false, and nothing deletes fact 3.
        task.operators[1].precondition = vec![0];
        task.operators[1].negative_precondition = vec![3];
        let lost = LostGoals::new(&task);
        let initial = State::from_facts(4, &[0]);
        assert!(!lost.any_lost(&initial));
        assert!(lost.any_lost(&initial.apply(&task.operators[2])));

        task.negative_goal = vec![3];
        task.goal = vec![1];
        let lost = LostGoals::new(&task);
        assert!(!lost.any_lost(&initial));
        assert!(lost.any_lost(&initial.apply(&task.operators[2])), "fact 3 holds for good");
    }
}
