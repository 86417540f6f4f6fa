//! Where a held object comes down into several regions at once, the recording may show it entering them one
//! recorded step apart: a Jenga block lowered across two blocks and onto its marker enters the marker's region a
//! few millimetres before the blocks' (the regions' tops differ), and a logger at 50 Hz records each entry.
//! The state in between is one the object only passes through on its way down, never one a plan can stop in:
//! an action "across the two blocks but not on its marker" is one no refinement can produce, because the
//! placement the demonstrations show puts the block in both.
//!
//! So the learner takes such a run of entries as one change. Consecutive changes of a demonstration are one
//! placement when each of them only adds relations (region k ≥ 1) of one object, held by a robot part before
//! and after, to objects that are not robot parts, and deletes nothing but those pairs' "in no region" atoms
//! and the clear and nowhere atoms that go with them. A change that takes the object out of a region, or moves
//! a robot part, or another object, ends the run.

use std::collections::BTreeSet;

use crate::abstraction::Fact;
use crate::demo::Participant;
use crate::relations::PairVocabulary;

/// Each change of `states` as the indices of the state before it and the state after it, consecutive entries
/// of one held object taken as one change (from the state before the first to the state after the last).
pub(crate) fn changes(
    vocabulary: &[PairVocabulary],
    participants: &[Participant],
    states: &[BTreeSet<Fact>],
) -> Vec<(usize, usize)> {
    let steps: Vec<(usize, usize)> = (1..states.len())
        .filter(|&step| states[step] != states[step - 1])
        .map(|step| (step - 1, step))
        .collect();
    let mut merged = Vec::with_capacity(steps.len());
    let mut index = 0;
    while index < steps.len() {
        let (pre, mut post) = steps[index];
        index += 1;
        if let Some(object) = entry_of_held(vocabulary, participants, &states[pre], &states[post]) {
            while let Some(&(_, next)) = steps.get(index) {
                if entry_of_held(vocabulary, participants, &states[post], &states[next])
                    != Some(object)
                {
                    break;
                }
                post = next;
                index += 1;
            }
        }
        merged.push((pre, post));
    }
    merged
}

/// The held object whose regions alone the change from `pre` to `post` adds, if the change is such an entry.
fn entry_of_held(
    vocabulary: &[PairVocabulary],
    participants: &[Participant],
    pre: &BTreeSet<Fact>,
    post: &BTreeSet<Fact>,
) -> Option<usize> {
    let is_robot = |object: usize| participants[object].role.is_robot_part();
    // Whether a robot part holds the object (a region of the part with the held flag).
    let held = |object: usize, state: &BTreeSet<Fact>| {
        state.iter().any(|fact| match *fact {
            Fact::Relation { pair, region, primary, secondary } => {
                secondary == object
                    && region >= 1
                    && is_robot(primary)
                    && vocabulary[pair].region_flags.get(region - 1) == Some(&1)
            }
            _ => false,
        })
    };
    // The object is the one every added relation names, with an object that is not a robot part (of two
    // movable objects, either may be the relation's primary).
    let added: Vec<Fact> = post.difference(pre).copied().collect();
    let mut candidates: Option<BTreeSet<usize>> = None;
    for fact in &added {
        match *fact {
            Fact::Relation { region, primary, secondary, .. }
                if region >= 1 && !is_robot(primary) && !is_robot(secondary) =>
            {
                let named = BTreeSet::from([primary, secondary]);
                candidates = Some(match candidates {
                    None => named,
                    Some(before) => before.intersection(&named).copied().collect(),
                });
            }
            Fact::Clear { .. } | Fact::Nowhere { .. } => {}
            _ => return None,
        }
    }
    let candidates = candidates?;
    // Of two blocks entering each other's regions, the one held is the one placed.
    let object = candidates.into_iter().find(|&object| held(object, pre) && held(object, post))?;
    let partner = |primary: usize, secondary: usize| {
        if primary == object {
            Some(secondary)
        } else if secondary == object {
            Some(primary)
        } else {
            None
        }
    };
    let entered: BTreeSet<(usize, usize)> = added
        .iter()
        .filter_map(|fact| match *fact {
            Fact::Relation { pair, primary, secondary, .. } => {
                Some((pair, partner(primary, secondary)?))
            }
            _ => None,
        })
        .collect();
    for fact in pre.difference(post) {
        match *fact {
            Fact::Relation { pair, region: 0, primary, secondary }
                if partner(primary, secondary)
                    .is_some_and(|other| entered.contains(&(pair, other))) => {}
            Fact::Clear { .. } | Fact::Nowhere { .. } => {}
            _ => return None,
        }
    }
    Some(object)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::TypePair;
    use crate::demo::Role;

    /// A gripper (0) holds a block (1) and lowers it across another block (2) and onto its marker (3).
    fn setting() -> (Vec<PairVocabulary>, Vec<Participant>) {
        let vocabulary = vec![
            PairVocabulary {
                pair: TypePair::new("gripper", "block"),
                region_flags: vec![1],
                clear: vec![true],
                nowhere: vec![false],
            },
            PairVocabulary {
                pair: TypePair::new("block", "block"),
                region_flags: vec![0],
                clear: vec![true],
                nowhere: vec![false],
            },
            PairVocabulary {
                pair: TypePair::new("loc", "block"),
                region_flags: vec![0],
                clear: vec![true],
                nowhere: vec![false],
            },
        ];
        let participant = |name: &str, type_name: &str, role: Role| Participant {
            name: name.into(),
            type_name: type_name.into(),
            role,
        };
        let participants = vec![
            participant("gripper", "gripper", Role::RobotPart { gripper: true }),
            participant("b1", "block", Role::Object { movable: true }),
            participant("b2", "block", Role::Object { movable: true }),
            participant("l1", "loc", Role::Object { movable: false }),
        ];
        (vocabulary, participants)
    }

    fn state(held: bool, across: bool, on_marker: bool) -> BTreeSet<Fact> {
        let relation =
            |pair, region, primary| Fact::Relation { pair, region, primary, secondary: 1 };
        let mut facts = BTreeSet::from([
            relation(0, usize::from(held), 0),
            relation(1, usize::from(across), 2),
            relation(2, usize::from(on_marker), 3),
        ]);
        if !on_marker {
            facts.insert(Fact::Clear { pair: 2, region: 1, object: 3 });
        }
        facts
    }

    #[test]
    fn entries_of_a_held_object_one_step_apart_are_one_change() {
        let (vocabulary, participants) = setting();
        // Lowered onto the marker, then across the block a step later, held all along, then let go.
        let states = [
            state(true, false, false),
            state(true, false, false),
            state(true, false, true),
            state(true, true, true),
            state(true, true, true),
            state(false, true, true),
        ];
        assert_eq!(changes(&vocabulary, &participants, &states), [(1, 3), (4, 5)]);
    }

    #[test]
    fn a_release_a_departure_or_a_state_left_again_ends_the_run() {
        let (vocabulary, participants) = setting();
        // Onto the marker, let go there, then across (a change of the held flag in between).
        let released = [
            state(true, false, false),
            state(true, false, true),
            state(false, false, true),
            state(false, true, true),
        ];
        assert_eq!(changes(&vocabulary, &participants, &released), [(0, 1), (1, 2), (2, 3)]);
        // Onto the marker and off it again while held: leaving is not an entry.
        let passed =
            [state(true, false, false), state(true, false, true), state(true, false, false)];
        assert_eq!(changes(&vocabulary, &participants, &passed), [(0, 1), (1, 2)]);
        // Not held: a block pushed onto the marker and across it is two changes.
        let pushed =
            [state(false, false, false), state(false, false, true), state(false, true, true)];
        assert_eq!(changes(&vocabulary, &participants, &pushed), [(0, 1), (1, 2)]);
    }

    #[test]
    fn a_demonstration_without_changes_has_none() {
        let (vocabulary, participants) = setting();
        let still = [state(true, false, false), state(true, false, false)];
        assert!(changes(&vocabulary, &participants, &still).is_empty());
    }
}
