//! Targets in the world frame: AtGoals, and the poses of a structure goal's objects (each an
//! AtGoal with the structure tolerance, `SpecWorld::placement_targets`).
//!
//! An AtGoal reaches the planner as the learned relation of its object on the marker at its
//! target; the region of that relation may be wider than the goal's tolerance. A step that makes
//! the goal atom of an object hold must also put it within tolerance, or the state it reaches is
//! one the goal cannot be met from without moving the object again: such a candidate is refused,
//! so that the refiner's next sample is tried. The final replay checks every target again.

use std::collections::BTreeSet;

use lamp_abstraction::GroundAtom;
use lamp_spec::AtGoal;
use lamp_world::Scene;

/// An object off its target by more than the goal allows.
#[derive(Clone, Debug, PartialEq)]
pub struct Miss {
    pub object: String,
    /// How far the object is from its target, metres and radians.
    pub distance: f64,
    pub angle: f64,
    pub position_tolerance: f64,
    pub angle_tolerance: f64,
}

impl std::fmt::Display for Miss {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "`{}` is {:.1} mm and {:.1}° from its target (tolerance {:.1} mm and {:.1}°)",
            self.object,
            self.distance * 1000.0,
            self.angle.to_degrees(),
            self.position_tolerance * 1000.0,
            self.angle_tolerance.to_degrees()
        )
    }
}

/// The first target whose goal atom holds in `reached` while its object, resting (not held),
/// is outside the tolerance in `scene`.
pub fn first_miss_where_reached(
    targets: &[AtGoal],
    goal: &BTreeSet<GroundAtom>,
    reached: &BTreeSet<GroundAtom>,
    scene: &Scene,
) -> Option<Miss> {
    targets
        .iter()
        .filter(|target| {
            let arguments = [target.marker_name(), target.object.clone()];
            goal.iter().any(|atom| atom.arguments == arguments && reached.contains(atom))
        })
        .filter(|target| !is_held(scene, &target.object))
        .find_map(|target| miss(target, scene))
}

/// The first target its object misses in `scene`, in goal order.
pub fn first_miss(targets: &[AtGoal], scene: &Scene) -> Option<Miss> {
    targets.iter().find_map(|target| miss(target, scene))
}

fn miss(target: &AtGoal, scene: &Scene) -> Option<Miss> {
    let Some(body) = scene.body_index(&target.object) else {
        return Some(Miss {
            object: target.object.clone(),
            distance: f64::INFINITY,
            angle: f64::INFINITY,
            position_tolerance: target.position_tolerance,
            angle_tolerance: target.angle_tolerance,
        });
    };
    let pose = scene.body_pose(body);
    let distance = (pose.translation.vector - target.pose.translation.vector).norm();
    let angle = pose.rotation.angle_to(&target.pose.rotation);
    (distance > target.position_tolerance || angle > target.angle_tolerance).then(|| Miss {
        object: target.object.clone(),
        distance,
        angle,
        position_tolerance: target.position_tolerance,
        angle_tolerance: target.angle_tolerance,
    })
}

fn is_held(scene: &Scene, object: &str) -> bool {
    let Some(body) = scene.body_index(object) else { return false };
    (0..scene.robots().len()).any(|robot| scene.held(robot).is_some_and(|held| held.body == body))
}

#[cfg(test)]
mod tests {
    use super::*;
    use lamp_geometry::{Pose, Shape, Vec3};
    use lamp_world::Body;

    fn scene_with_glass_at(x: f64) -> Scene {
        let mut scene = Scene::new();
        let glass = Body {
            name: "glass1".into(),
            type_name: "glass".into(),
            movable: true,
            world: false,
            parts: vec![(
                Pose::identity(),
                Shape::Box { half_extents: Vec3::new(0.04, 0.04, 0.1) },
            )],
        };
        scene.add_body(glass, Pose::translation(x, 0.0, 0.0)).expect("a body");
        scene
    }

    fn target(position_tolerance: f64) -> AtGoal {
        AtGoal {
            object: "glass1".into(),
            pose: Pose::identity(),
            position_tolerance,
            angle_tolerance: 0.1,
            marker_type: "place".into(),
        }
    }

    fn atom(predicate: &str) -> GroundAtom {
        GroundAtom {
            predicate: predicate.into(),
            arguments: vec!["goal_glass1".into(), "glass1".into()],
        }
    }

    #[test]
    fn an_object_outside_its_tolerance_misses_by_how_much() {
        let scene = scene_with_glass_at(0.03);
        assert_eq!(first_miss(&[target(0.05)], &scene), None);
        let miss = first_miss(&[target(0.02)], &scene).expect("3 cm is more than 2 cm");
        assert!((miss.distance - 0.03).abs() < 1e-12 && miss.angle.abs() < 1e-12);
        assert_eq!(
            miss.to_string(),
            "`glass1` is 30.0 mm and 0.0° from its target (tolerance 20.0 mm and 5.7°)"
        );
    }

    #[test]
    fn a_step_is_judged_only_where_the_goal_atom_of_the_target_holds() {
        let scene = scene_with_glass_at(0.03);
        let goal = BTreeSet::from([atom("place_glass_1")]);
        let elsewhere = BTreeSet::from([atom("place_glass_0")]);
        assert_eq!(first_miss_where_reached(&[target(0.02)], &goal, &elsewhere, &scene), None);
        let on = goal.clone();
        assert!(first_miss_where_reached(&[target(0.02)], &goal, &on, &scene).is_some());
    }
}
