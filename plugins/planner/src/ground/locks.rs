//! Operators that would lose a goal for good, recognised while their parameters are bound.
//!
//! A goal atom g, false initially, is *locked* by a fact f when every action that adds g needs f
//! and deletes it, and no action adds f. Such a fact is used up by the first achiever of g, so an
//! operator that needs f and deletes it without adding g is in no plan: before g is first
//! achieved it would leave g out of reach, and after that it cannot apply. A learned domain has
//! such locks wherever one object is put on a marker that takes one object ever: the goal
//! "block 3 on its marker" locks the marker's `clear` fact, and every operator that would put
//! another block there is dropped. Without this, each placement action grounds once per marker
//! and object, n² times more than it can be used.
//!
//! The test runs on partial bindings, so that a join stops as soon as a binding is known to be
//! locked out; the search's own lost-goal test (`lost_goals`) still guards what grounding cannot
//! see.

use std::collections::{HashMap, HashSet};

use super::{Key, LiftedAction, LiftedAtom, Slot, UNBOUND, equalities_hold, instantiate};

/// The locks of one grounding.
pub(super) struct GoalLocks {
    /// A lock fact and the goal atoms it locks.
    goals_of: HashMap<Key, Vec<Key>>,
    /// Per action (in domain order): the positive preconditions it deletes whose predicate no
    /// action adds.
    consumed: Vec<Vec<LiftedAtom>>,
}

impl GoalLocks {
    /// The locks of `goals` (positive goal atoms) under `actions`, from the `initial` state.
    pub(super) fn new(
        actions: &[LiftedAction],
        predicates: usize,
        goals: &[Key],
        initial: &HashSet<Key>,
    ) -> Self {
        let mut added = vec![false; predicates];
        for action in actions {
            for atom in &action.add {
                if let Some(flag) = added.get_mut(atom.predicate as usize) {
                    *flag = true;
                }
            }
        }
        let consumed: Vec<Vec<LiftedAtom>> = actions
            .iter()
            .map(|action| {
                action
                    .positive
                    .iter()
                    .filter(|atom| !added.get(atom.predicate as usize).copied().unwrap_or(true))
                    .filter(|atom| action.delete.contains(atom))
                    .cloned()
                    .collect()
            })
            .collect();
        let mut goals_of: HashMap<Key, Vec<Key>> = HashMap::new();
        for goal in goals {
            if initial.contains(goal) {
                continue;
            }
            for fact in locks_of(goal, actions, &consumed) {
                goals_of.entry(fact).or_default().push(goal.clone());
            }
        }
        GoalLocks { goals_of, consumed }
    }

    /// Whether any binding extending `binding` (parameters still unbound are [`UNBOUND`]) of
    /// the action at `index` is proven to lose a goal for good.
    pub(super) fn prunes(&self, index: usize, action: &LiftedAction, binding: &[u32]) -> bool {
        if self.goals_of.is_empty() {
            return false;
        }
        self.consumed[index].iter().any(|atom| {
            // Asked at every node of a join: most atoms are not bound yet, and are answered
            // before a key is built.
            let bound = atom.slots.iter().all(|slot| match *slot {
                Slot::Parameter(index) => binding.get(index).is_some_and(|&v| v != UNBOUND),
                Slot::Object(object) => object != UNBOUND,
            });
            if !bound {
                return false;
            }
            let fact = instantiate(atom, binding);
            let Some(goals) = self.goals_of.get(&fact) else { return false };
            goals.iter().any(|goal| {
                action.add.iter().filter(|added| added.predicate == goal[0]).all(|added| {
                    let key = instantiate(added, binding);
                    // An add effect not yet bound may still turn out to be the goal.
                    !key.contains(&UNBOUND) && key != *goal
                })
            })
        })
    }
}

/// The facts every achiever of `goal` consumes, ground by the achiever's match with it; none
/// when an achiever consumes none, or when nothing achieves the goal (grounding reports that).
fn locks_of(goal: &Key, actions: &[LiftedAction], consumed: &[Vec<LiftedAtom>]) -> Vec<Key> {
    let mut common: Option<Vec<Key>> = None;
    for (action, consumed) in actions.iter().zip(consumed) {
        for added in action.add.iter().filter(|added| added.predicate == goal[0]) {
            let Some(binding) = match_goal(action, added, goal) else { continue };
            let facts: Vec<Key> = consumed
                .iter()
                .map(|atom| instantiate(atom, &binding))
                .filter(|fact| !fact.contains(&UNBOUND))
                .collect();
            common = Some(match common {
                None => facts,
                Some(before) => before.into_iter().filter(|fact| facts.contains(fact)).collect(),
            });
            if common.as_ref().is_some_and(Vec::is_empty) {
                return Vec::new();
            }
        }
    }
    common.unwrap_or_default()
}

/// The partial binding under which `added`, an add effect of `action`, is `goal`: `None` when
/// no binding is (a constant differs, a parameter would take two objects or one of the wrong
/// type, an equality constraint fails).
fn match_goal(action: &LiftedAction, added: &LiftedAtom, goal: &Key) -> Option<Vec<u32>> {
    let mut binding = vec![UNBOUND; action.candidates.len()];
    for (slot, &value) in added.slots.iter().zip(&goal[1..]) {
        match *slot {
            Slot::Object(object) if object != value => return None,
            Slot::Object(_) => {}
            Slot::Parameter(index) => {
                let bound = binding.get_mut(index)?;
                if *bound == UNBOUND {
                    action.candidates[index].binary_search(&value).ok()?;
                    *bound = value;
                } else if *bound != value {
                    return None;
                }
            }
        }
    }
    equalities_hold(action, &binding).then_some(binding)
}
