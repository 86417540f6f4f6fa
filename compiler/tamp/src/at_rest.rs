//! The physics check of a finished solution: its final scene, simulated under gravity with
//! lamp-physics, must stay put, every object within 5 mm and 3° of where the replay leaves it.
//!
//! What is simulated: every body with geometry. Static bodies (the floor, tables, walls, any
//! body a robot may not carry) are fixed; movable bodies are free. The robots are not simulated:
//! no valid state lets a link touch a body, so a robot holds nothing up, and its parked arm is
//! not an obstacle anything could fall onto within the thresholds. An object still held at the
//! end is left out (the solver's goal makes every gripper that starts empty end empty, so this
//! only happens when a problem says otherwise). Markers have no geometry and are ignored.
//!
//! Before the simulation each object is lowered onto what it rests on (lamp-physics closes the
//! resting gaps the world leaves under it): the drift is judged from there, and how far the
//! object went down is its sink, what a robot's structure ends below the solution's poses.

use lamp_physics::{PhysicsBody, SIMULATED_SECONDS, simulate};
use lamp_world::{RESTING_GAP, Scene};

use crate::error::SolveError;
use crate::summary::Sink;

/// Fails with [`SolveError::Unstable`], naming the first object (in scene order) that moves
/// more than 5 mm or turns more than 3° in two simulated seconds; `step` is the trajectory step
/// the scene follows, if it is not the final one. At rest, returns the object that sinks
/// farthest onto what it rests on (the first in scene order among equals), if any sinks.
pub fn check_at_rest(scene: &Scene, step: Option<usize>) -> Result<Option<Sink>, SolveError> {
    let held: Vec<usize> =
        (0..scene.robots().len()).filter_map(|robot| scene.held(robot)).map(|h| h.body).collect();
    let bodies: Vec<PhysicsBody<'_>> = scene
        .bodies()
        .iter()
        .enumerate()
        .filter(|(index, body)| !body.is_marker() && !held.contains(index))
        .map(|(index, body)| PhysicsBody {
            name: &body.name,
            parts: &body.parts,
            pose: scene.body_pose(index),
            fixed: !body.movable,
        })
        .collect();
    let drifts = simulate(&bodies, RESTING_GAP).map_err(|error| SolveError::InvalidSolution {
        step: 0,
        reason: format!("the physics check cannot simulate the final scene: {error}"),
    })?;
    if let Some(drift) = drifts.iter().find(|drift| !drift.at_rest()) {
        return Err(SolveError::Unstable {
            object: drift.name.clone(),
            shift: drift.shift,
            turn: drift.turn,
            seconds: SIMULATED_SECONDS,
            step,
        });
    }
    let deepest = drifts
        .into_iter()
        .filter(|drift| drift.sink > 0.0)
        .reduce(|deepest, drift| if drift.sink > deepest.sink { drift } else { deepest });
    Ok(deepest.map(|drift| Sink { object: drift.name, metres: drift.sink }))
}

#[cfg(test)]
mod tests {
    use lamp_geometry::{Pose, Shape, Vec3};
    use lamp_world::Body;

    use super::*;

    fn body(name: &str, movable: bool, shape: Shape, at_z: f64) -> (Body, Pose) {
        let parts = vec![(Pose::translation(0.0, 0.0, at_z), shape)];
        let body =
            Body { name: name.into(), type_name: name.into(), movable, world: !movable, parts };
        (body, Pose::identity())
    }

    /// A table (top at z = 0.75, edge at x = 0.45), a can standing on it at `can_x` 1 mm above
    /// the top, and a marker floating in the air.
    fn scene(can_x: f64) -> Scene {
        let mut scene = Scene::new();
        let top = Shape::Box { half_extents: Vec3::new(0.45, 0.45, 0.025) };
        let (table, at) = body("table", false, top, 0.725);
        scene.add_body(table, at).expect("a table");
        let cylinder = Shape::Cylinder { radius: 0.0325, half_height: 0.075 };
        let (can, _) = body("can", true, cylinder, 0.075);
        scene.add_body(can, Pose::translation(can_x, 0.0, 0.751)).expect("a can");
        let marker = Body {
            name: "target".into(),
            type_name: "place".into(),
            movable: false,
            world: false,
            parts: Vec::new(),
        };
        scene.add_body(marker, Pose::translation(0.0, 0.0, 2.0)).expect("a marker");
        scene
    }

    #[test]
    fn a_can_on_the_table_and_a_marker_in_the_air_are_at_rest() {
        let sink = check_at_rest(&scene(0.2), None).expect("at rest").expect("the can sinks");
        assert_eq!(sink.object, "can");
        assert!((sink.metres - 0.001).abs() < 1e-6, "{sink:?}");
    }

    #[test]
    fn a_can_over_the_edge_is_named_with_how_far_it_went() {
        match check_at_rest(&scene(0.47), None) {
            Err(SolveError::Unstable { object, shift, turn, seconds, .. }) => {
                assert_eq!(object, "can");
                assert!(shift > lamp_physics::MAX_SHIFT || turn > lamp_physics::MAX_TURN);
                assert_eq!(seconds, SIMULATED_SECONDS);
            }
            other => panic!("expected Unstable, got {:?}", other.err()),
        }
    }

    /// Checked after a release, the message says which step left the scene so.
    #[test]
    fn a_scene_after_a_release_is_named_by_its_step() {
        let message = check_at_rest(&scene(0.47), Some(7)).expect_err("unstable").to_string();
        assert!(
            message.starts_with(
                "`can` does not stay where the solution leaves it after what is let go of at step 7:"
            ),
            "{message}"
        );
        let last = check_at_rest(&scene(0.47), None).expect_err("unstable").to_string();
        assert!(last.starts_with("`can` does not stay where the solution leaves it:"), "{last}");
    }
}
