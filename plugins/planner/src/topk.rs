//! Top-k planning by iterated forbidding.
//!
//! Plans are distinct as sequences of ground actions and loop-free (no state is visited twice).
//! The first plan is the one plain greedy best-first search finds; each later plan is the first
//! plan that search finds when every plan already returned is forbidden (through the plan trie of
//! [`crate::SearchSpace`]). Plans therefore come in discovery order, not sorted by length. When a
//! search exhausts its space, no further distinct loop-free plan exists, and the call is
//! [`Status::Solved`] with fewer than `k` plans (or [`Status::Unsolvable`] with none).

use crate::search::{SearchEnd, SearchSpace};
use crate::task::{GroundTask, GroundingVerdict};
use crate::{Budget, PlannerOutput, Status, Unsolvable, named_plan};

/// Up to `k` distinct loop-free plans for `task` within `budget` (shared by all `k` searches).
#[must_use]
pub fn top_k(task: &GroundTask, k: usize, budget: &Budget) -> PlannerOutput {
    top_k_until(task, k, budget, &|| false)
}

/// [`top_k`] that also ends, as out of budget, once `stop` says so.
#[must_use]
pub fn top_k_until(
    task: &GroundTask,
    k: usize,
    budget: &Budget,
    stop: &dyn Fn() -> bool,
) -> PlannerOutput {
    let mut space = SearchSpace::new(task);
    if let GroundingVerdict::GoalUnreachable { literal } = &task.verdict {
        return PlannerOutput {
            status: Status::Unsolvable(Unsolvable::GoalUnreachable { literal: literal.clone() }),
            plans: Vec::new(),
            statistics: space.statistics(),
        };
    }
    let mut plans = Vec::new();
    let mut status = Status::Solved;
    while plans.len() < k {
        match space.search_until(budget, stop) {
            SearchEnd::Found(operators) => {
                space.forbid(&operators);
                plans.push(named_plan(task, &operators));
            }
            SearchEnd::Exhausted => {
                if plans.is_empty() {
                    status = Status::Unsolvable(Unsolvable::SearchSpaceExhausted);
                }
                break;
            }
            SearchEnd::OutOfBudget => {
                status = Status::BudgetExhausted;
                break;
            }
        }
    }
    PlannerOutput { status, plans, statistics: space.statistics() }
}
