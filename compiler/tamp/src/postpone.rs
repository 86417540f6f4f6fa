//! Postponing the carry of an object that nothing holds up yet where its plan lets go of it.
//!
//! A goal may leave the order of two placements open where the learned relations do not relate
//! the two objects: when the demonstrations show too few walls standing on a floor for a relation
//! between them to be learned, a plan may set a wall down before its floor. The release refuses
//! that (the wall would drop onto the table), and every candidate of the step is refused the same
//! way, since the wall is let go of where the step before put it. Backtracking can only sample
//! other poses of the same region, all of them in the air, until the plan's budget runs out.
//!
//! So the steps that carry the object (the run of consecutive steps that name it, around the
//! refused one) move past the steps after them, to the first point from which the reordered rest
//! of the plan still runs to the goal in the learned domain, and the refinement goes on from where
//! the carry began. The domain's preconditions decide where a carry may go: never into another
//! object's carry while the gripper holds that one. An order already tried is not tried again, so
//! two carries that each find no support cannot swap back and forth.

use std::collections::{BTreeSet, HashMap};
use std::ops::RangeInclusive;

use lamp_abstraction::GroundAtom;
use lamp_plugin_api::GroundedAction;

/// A plan's steps from some point on, as tried: the step texts, `(name args…)`.
pub type Order = Vec<String>;

/// The plan with a carry moved later.
#[derive(Debug, Clone, PartialEq)]
pub struct Postponed {
    /// The first step that changed: where the carry began.
    pub from: usize,
    /// The whole plan, reordered.
    pub actions: Vec<GroundedAction>,
}

/// The carry of `object` around step `at`: the consecutive steps that name it. `None` when step
/// `at` does not name it.
pub fn carry(actions: &[GroundedAction], at: usize, object: &str) -> Option<RangeInclusive<usize>> {
    let names = |step: usize| actions[step].arguments.iter().any(|argument| argument == object);
    if at >= actions.len() || !names(at) {
        return None;
    }
    let first = (0..at).rev().take_while(|&step| names(step)).last().unwrap_or(at);
    let last = (at + 1..actions.len()).take_while(|&step| names(step)).last().unwrap_or(at);
    Some(first..=last)
}

/// Moves `carry` (steps of `actions`) past the fewest steps after it such that the plan from
/// the carry's first step runs from `state`, the abstract state before it, to `goal`, and the
/// order from there is not in `tried`. `None` when no such point exists.
///
/// The steps the carry moves past run from `state` in their own order whatever the point, so
/// their state grows one step at a time, and a step that cannot run before the carry ends the
/// search: it cannot run there for any later point either.
pub fn postpone(
    actions: &[GroundedAction],
    carry: RangeInclusive<usize>,
    state: &BTreeSet<GroundAtom>,
    goal: &BTreeSet<GroundAtom>,
    tried: &BTreeSet<(usize, Order)>,
) -> Option<Postponed> {
    let (from, to) = carry.into_inner();
    let table = AtomTable::new(state, goal, &actions[from..]);
    // Indexed from `from`: the steps the search moves and runs.
    let steps: Vec<IndexedStep> = actions[from..].iter().map(|a| table.step(a)).collect();
    let goal: Vec<usize> = goal.iter().map(|atom| table.index_of(atom)).collect();
    // The carry is steps 0..=last of `steps`.
    let last = to - from;
    let mut passed = table.bits(state);
    for past in last + 1..steps.len() {
        if !steps[past].run(&mut passed) {
            return None;
        }
        let mut after = passed.clone();
        let runs = (0..=last).chain(past + 1..steps.len()).all(|i| steps[i].run(&mut after))
            && goal.iter().all(|&atom| after[atom]);
        if !runs {
            continue;
        }
        let past = from + past;
        let carried = &actions[from..=to];
        let mut reordered = Vec::with_capacity(actions.len());
        reordered.extend_from_slice(&actions[..from]);
        reordered.extend_from_slice(&actions[to + 1..=past]);
        reordered.extend_from_slice(carried);
        reordered.extend_from_slice(&actions[past + 1..]);
        if !tried.contains(&(from, order(&reordered[from..]))) {
            return Some(Postponed { from, actions: reordered });
        }
    }
    None
}

/// Every atom the search can meet, numbered, so that a state is a vector of flags: the search
/// copies a state at every point it tries and runs up to the whole rest of the plan from it, and
/// with states as sets of atoms (each a predicate and argument strings) that copying and the
/// lookups of every precondition were most of a 149-step Keva solve's time.
struct AtomTable<'a> {
    index: HashMap<(&'a str, &'a [String]), usize>,
}

/// An action's atoms as numbers of an [`AtomTable`].
struct IndexedStep {
    preconditions: Vec<usize>,
    negative_preconditions: Vec<usize>,
    delete_effects: Vec<usize>,
    add_effects: Vec<usize>,
}

impl<'a> AtomTable<'a> {
    fn new(
        state: &'a BTreeSet<GroundAtom>,
        goal: &'a BTreeSet<GroundAtom>,
        actions: &'a [GroundedAction],
    ) -> AtomTable<'a> {
        let mut index = HashMap::new();
        let mut add = |predicate: &'a str, arguments: &'a [String]| {
            let next = index.len();
            index.entry((predicate, arguments)).or_insert(next);
        };
        for atom in state.iter().chain(goal) {
            add(&atom.predicate, &atom.arguments);
        }
        for action in actions {
            for atom in action
                .preconditions
                .iter()
                .chain(&action.negative_preconditions)
                .chain(&action.delete_effects)
                .chain(&action.add_effects)
            {
                add(&atom.predicate, &atom.arguments);
            }
        }
        AtomTable { index }
    }

    fn index_of(&self, atom: &GroundAtom) -> usize {
        self.index[&(atom.predicate.as_str(), atom.arguments.as_slice())]
    }

    fn indices(&self, atoms: &[lamp_plugin_api::GroundAtom]) -> Vec<usize> {
        atoms
            .iter()
            .map(|atom| self.index[&(atom.predicate.as_str(), atom.arguments.as_slice())])
            .collect()
    }

    fn step(&self, action: &GroundedAction) -> IndexedStep {
        IndexedStep {
            preconditions: self.indices(&action.preconditions),
            negative_preconditions: self.indices(&action.negative_preconditions),
            delete_effects: self.indices(&action.delete_effects),
            add_effects: self.indices(&action.add_effects),
        }
    }

    /// `state` as flags: true for the atoms it holds.
    fn bits(&self, state: &BTreeSet<GroundAtom>) -> Vec<bool> {
        let mut bits = vec![false; self.index.len()];
        for atom in state {
            bits[self.index_of(atom)] = true;
        }
        bits
    }
}

impl IndexedStep {
    /// Applies the step to `state` (deletes, then adds, as `crate::ground::progress` does) when
    /// its preconditions hold and its negated ones do not, and says whether it did; `state` is
    /// unchanged when they do not.
    fn run(&self, state: &mut [bool]) -> bool {
        if !self.preconditions.iter().all(|&atom| state[atom])
            || self.negative_preconditions.iter().any(|&atom| state[atom])
        {
            return false;
        }
        for &atom in &self.delete_effects {
            state[atom] = false;
        }
        for &atom in &self.add_effects {
            state[atom] = true;
        }
        true
    }
}

/// The order of `actions`, for [`postpone`]'s `tried`.
pub fn order(actions: &[GroundedAction]) -> Order {
    actions.iter().map(|action| crate::ground::call_text(&action.name, &action.arguments)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn atom(predicate: &str, arguments: &[&str]) -> GroundAtom {
        GroundAtom {
            predicate: predicate.to_string(),
            arguments: arguments.iter().map(|a| a.to_string()).collect(),
        }
    }

    /// The same atom as an action carries it.
    fn wire(predicate: &str, arguments: &[&str]) -> lamp_plugin_api::GroundAtom {
        let GroundAtom { predicate, arguments } = atom(predicate, arguments);
        lamp_plugin_api::GroundAtom { predicate, arguments }
    }

    /// Taking up `object` needs a free hand; setting it down needs it held and frees the hand.
    fn take_and_put(object: &str) -> [GroundedAction; 2] {
        let take = GroundedAction {
            name: "take".into(),
            arguments: vec!["hand".into(), object.into()],
            preconditions: vec![wire("free", &["hand"]), wire("loose", &[object])],
            negative_preconditions: Vec::new(),
            add_effects: vec![wire("holds", &["hand", object])],
            delete_effects: vec![wire("free", &["hand"]), wire("loose", &[object])],
        };
        let put = GroundedAction {
            name: "put".into(),
            arguments: vec!["hand".into(), object.into()],
            preconditions: vec![wire("holds", &["hand", object])],
            negative_preconditions: Vec::new(),
            add_effects: vec![wire("free", &["hand"]), wire("placed", &[object])],
            delete_effects: vec![wire("holds", &["hand", object])],
        };
        [take, put]
    }

    fn plan(objects: &[&str]) -> Vec<GroundedAction> {
        objects.iter().flat_map(|object| take_and_put(object)).collect()
    }

    fn start(objects: &[&str]) -> BTreeSet<GroundAtom> {
        let mut state: BTreeSet<GroundAtom> =
            objects.iter().map(|object| atom("loose", &[object])).collect();
        state.insert(atom("free", &["hand"]));
        state
    }

    fn goal(objects: &[&str]) -> BTreeSet<GroundAtom> {
        objects.iter().map(|object| atom("placed", &[object])).collect()
    }

    fn objects_in_order(actions: &[GroundedAction]) -> Vec<&str> {
        actions.iter().step_by(2).map(|action| action.arguments[1].as_str()).collect()
    }

    #[test]
    fn a_carry_moves_past_the_next_carry_and_not_into_it() {
        let objects = ["wall", "floor", "roof"];
        let actions = plan(&objects);
        // The wall's release, step 2 (index 1), found nothing below it.
        let wall = carry(&actions, 1, "wall").unwrap();
        assert_eq!(wall, 0..=1);
        let tried = BTreeSet::new();
        let postponed =
            postpone(&actions, wall, &start(&objects), &goal(&objects), &tried).unwrap();
        assert_eq!(postponed.from, 0);
        // Past one step, the hand would take the wall while holding the floor.
        assert_eq!(objects_in_order(&postponed.actions), ["floor", "wall", "roof"]);
    }

    #[test]
    fn an_order_already_tried_is_skipped_and_the_last_carry_has_nowhere_to_go() {
        let objects = ["wall", "floor", "roof"];
        let actions = plan(&objects);
        let state = start(&objects);
        let mut tried = BTreeSet::new();
        let once = postpone(&actions, 0..=1, &state, &goal(&objects), &tried).unwrap();
        tried.insert((0, order(&once.actions)));
        let twice = postpone(&actions, 0..=1, &state, &goal(&objects), &tried).unwrap();
        assert_eq!(objects_in_order(&twice.actions), ["floor", "roof", "wall"]);
        // The roof's carry is the plan's last: there is nothing to move it past.
        assert_eq!(carry(&actions, 5, "roof"), Some(4..=5));
        assert_eq!(postpone(&actions, 4..=5, &state, &goal(&objects), &tried), None);
        // A step that does not name the object is no carry of it.
        assert_eq!(carry(&actions, 2, "wall"), None);
    }

    #[test]
    fn a_carry_the_rest_of_the_plan_needs_first_stays() {
        // The floor may only be taken once the wall is placed (its precondition): moving the wall
        // past the floor's carry would break the plan.
        let objects = ["wall", "floor"];
        let mut actions = plan(&objects);
        actions[2].preconditions.push(wire("placed", &["wall"]));
        let tried = BTreeSet::new();
        assert_eq!(postpone(&actions, 0..=1, &start(&objects), &goal(&objects), &tried), None);
    }
}
