//! Releases the vocabulary cannot describe: a demonstration is learned from only up to them.
//!
//! An object let go of comes to rest on, or against, what is around it. When it rests against
//! another movable object of a pair the learner relates, and the abstract state at the release
//! holds no relation between the two, the model cannot say what holds the object up: an action
//! induced from that placement would put the object there with nothing under it, and a plan
//! would let go of it in mid-air (the paper's Keva failure, most often from few demonstrations,
//! where a rare way of resting is in no region). Such a demonstration is kept only up to the
//! grasp of that object, as a demonstration cut short there: what came before is described
//! faithfully, and nothing is learned from the placement or what follows it.

use std::collections::{BTreeMap, BTreeSet};

use crate::abstraction::Fact;
use crate::capacity::ShapeOracle;
use crate::config::TypePair;
use crate::demo::{Demonstration, Role};

/// A demonstration kept only up to a grasp, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UndescribedRest {
    /// The demonstration's id.
    pub demonstration: String,
    /// The step at which the object was let go of (the last step, for a demonstration cut short
    /// while holding it).
    pub release: usize,
    /// The object let go of.
    pub object: String,
    /// The object it came to rest against, with no relation between them.
    pub against: String,
    /// The steps kept: up to and including the first step of the grasp.
    pub kept_steps: usize,
}

/// The first release of `demonstration` whose object rests against a movable object it has no
/// relation to in `states` (within `tolerance`), and the number of steps to keep.
///
/// `related` holds the type pairs the learner relates (with regions or not), either way round;
/// pairs whose shapes `shapes` does not know are not judged.
pub(crate) fn first_undescribed_rest(
    demonstration: &Demonstration,
    states: &[BTreeSet<Fact>],
    related: &BTreeSet<TypePair>,
    shapes: &dyn ShapeOracle,
    tolerance: f64,
) -> Option<UndescribedRest> {
    let participants = &demonstration.participants;
    let movable = |index: usize| participants[index].role == Role::Object { movable: true };
    let relates = |a: usize, b: usize| {
        let pair = |primary: usize, secondary: usize| TypePair {
            primary: participants[primary].type_name.clone(),
            secondary: participants[secondary].type_name.clone(),
        };
        related.contains(&pair(a, b)) || related.contains(&pair(b, a))
    };
    // Each hold is judged where it ends: at the release, or at the last step of a demonstration
    // cut short while holding (as if let go of there; one cut on the way down touches nothing).
    let judge = |object: usize, since: usize, step: usize| {
        let state = states.get(step)?;
        let other = (0..participants.len()).find(|&other| {
            other != object
                && movable(other)
                && relates(object, other)
                && !related_in(state, object, other)
                && touches(demonstration, step, other, object, shapes, tolerance)
        })?;
        Some(UndescribedRest {
            demonstration: demonstration.id.clone(),
            release: step,
            object: participants[object].name.clone(),
            against: participants[other].name.clone(),
            kept_steps: since + 1,
        })
    };
    // The step each current hold began, by object.
    let mut held_since: BTreeMap<usize, usize> = BTreeMap::new();
    for (step, snapshot) in demonstration.steps.iter().enumerate() {
        let held: BTreeSet<usize> = snapshot.held.iter().map(|&(_, object)| object).collect();
        for &object in &held {
            held_since.entry(object).or_insert(step);
        }
        let released: Vec<(usize, usize)> = held_since
            .iter()
            .filter(|(object, _)| !held.contains(object))
            .map(|(&object, &since)| (object, since))
            .collect();
        for (object, since) in released {
            held_since.remove(&object);
            if let Some(rest) = judge(object, since, step) {
                return Some(rest);
            }
        }
    }
    let last = demonstration.steps.len().checked_sub(1)?;
    held_since.into_iter().find_map(|(object, since)| judge(object, since, last))
}

/// Whether some region relates the two objects, either way round.
fn related_in(state: &BTreeSet<Fact>, a: usize, b: usize) -> bool {
    state.iter().any(|fact| match *fact {
        Fact::Relation { region, primary, secondary, .. } => {
            region > 0 && ((primary, secondary) == (a, b) || (primary, secondary) == (b, a))
        }
        Fact::Clear { .. } | Fact::Nowhere { .. } => false,
    })
}

fn touches(
    demonstration: &Demonstration,
    step: usize,
    primary: usize,
    secondary: usize,
    shapes: &dyn ShapeOracle,
    tolerance: f64,
) -> bool {
    let poses = &demonstration.steps[step].poses;
    let relative = poses[primary].inverse() * poses[secondary];
    let participants = &demonstration.participants;
    shapes
        .gap(&participants[primary].type_name, &participants[secondary].type_name, &relative)
        .is_some_and(|gap| gap <= tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::{Participant, Pose, Snapshot};

    /// Unit cubes of type `block`, frame at the centre; every other type has no known shape.
    struct Cubes;

    impl ShapeOracle for Cubes {
        fn two_fit(&self, _: &str, _: &[Pose]) -> Option<bool> {
            None
        }

        fn gap(&self, primary: &str, secondary: &str, relative: &Pose) -> Option<f64> {
            (primary == "block" && secondary == "block").then(|| {
                let t = relative.translation.vector;
                let outside = |d: f64| (d.abs() - 1.0).max(0.0);
                (outside(t.x).powi(2) + outside(t.y).powi(2) + outside(t.z).powi(2)).sqrt()
            })
        }
    }

    fn participant(name: &str, type_name: &str, role: Role) -> Participant {
        Participant { name: name.into(), type_name: type_name.into(), role }
    }

    /// A hand carries `b2` from beside `b1` onto it (steps 1–2) and lets go at step 3.
    fn stacking() -> Demonstration {
        let block = Role::Object { movable: true };
        let participants = vec![
            participant("hand", "gripper", Role::RobotPart { gripper: true }),
            participant("b1", "block", block),
            participant("b2", "block", block),
        ];
        let at = |x: f64, z: f64| Pose::translation(x, 0.0, z);
        let step = |b2: Pose, held: bool| Snapshot {
            poses: vec![b2, at(0.0, 0.0), b2],
            held: if held { vec![(0, 2)] } else { Vec::new() },
        };
        Demonstration {
            id: "stack".into(),
            participants,
            steps: vec![
                step(at(3.0, 0.0), false),
                step(at(3.0, 0.0), true),
                step(at(0.0, 1.001), true),
                step(at(0.0, 1.001), false),
                step(at(0.0, 1.001), false),
            ],
        }
    }

    fn blocks() -> BTreeSet<TypePair> {
        [TypePair { primary: "block".into(), secondary: "block".into() }].into()
    }

    #[test]
    fn a_block_let_go_of_on_another_with_no_relation_keeps_the_steps_up_to_its_grasp() {
        let demonstration = stacking();
        let states = vec![BTreeSet::new(); 5];
        let rest = first_undescribed_rest(&demonstration, &states, &blocks(), &Cubes, 0.005);
        let expected = UndescribedRest {
            demonstration: "stack".into(),
            release: 3,
            object: "b2".into(),
            against: "b1".into(),
            kept_steps: 2,
        };
        assert_eq!(rest, Some(expected));
    }

    #[test]
    fn a_demonstration_cut_short_holding_the_block_on_the_other_is_judged_at_its_end() {
        let mut demonstration = stacking();
        demonstration.steps.truncate(3);
        let states = vec![BTreeSet::new(); 3];
        let rest = first_undescribed_rest(&demonstration, &states, &blocks(), &Cubes, 0.005)
            .expect("judged at the last step");
        assert_eq!((rest.release, rest.kept_steps), (2, 2));
        demonstration.steps.truncate(2);
        assert_eq!(first_undescribed_rest(&demonstration, &states, &blocks(), &Cubes, 0.005), None);
    }

    #[test]
    fn a_relation_either_way_round_describes_the_rest() {
        let demonstration = stacking();
        for (primary, secondary) in [(1, 2), (2, 1)] {
            let mut states = vec![BTreeSet::new(); 5];
            states[3].insert(Fact::Relation { pair: 0, region: 1, primary, secondary });
            let rest = first_undescribed_rest(&demonstration, &states, &blocks(), &Cubes, 0.005);
            assert_eq!(rest, None, "related as {primary} → {secondary}");
        }
        // "In none of the regions" describes nothing.
        let mut states = vec![BTreeSet::new(); 5];
        states[3].insert(Fact::Relation { pair: 0, region: 0, primary: 1, secondary: 2 });
        let rest = first_undescribed_rest(&demonstration, &states, &blocks(), &Cubes, 0.005);
        assert!(rest.is_some());
    }

    #[test]
    fn apart_ignored_or_of_unknown_shape_it_is_not_judged() {
        let states = vec![BTreeSet::new(); 5];
        let mut apart = stacking();
        for step in &mut apart.steps[2..] {
            step.poses[2] = Pose::translation(0.0, 0.0, 1.02);
            step.poses[0] = step.poses[2];
        }
        assert_eq!(first_undescribed_rest(&apart, &states, &blocks(), &Cubes, 0.005), None);
        let ignored = BTreeSet::new();
        assert_eq!(first_undescribed_rest(&stacking(), &states, &ignored, &Cubes, 0.005), None);
        let shapeless = crate::capacity::NoShapes;
        assert_eq!(
            first_undescribed_rest(&stacking(), &states, &blocks(), &shapeless, 0.005),
            None
        );
    }
}
