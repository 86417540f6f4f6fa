//! The fingers of a gripper that takes hold or lets go: after a grab they close onto the held
//! object, each to the position at which its inner face touches it ([`grasp_position`]); before
//! a release they open back to the values the robot was added with (the spec's named
//! configuration). A gripper without finger joints (a magnet, a suction cup) moves nothing.

use lamp_geometry::BodyId;

use crate::error::WorldError;
use crate::execution::grasp_position;
use crate::motion::{MotionConfig, densify};
use crate::scene::Scene;

/// Which way the fingers move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FingerMove {
    /// Onto the held object.
    Close,
    /// Back to the open values.
    Open,
}

/// The states robot `robot` passes through (the current configuration first, at the checking
/// resolution of `config`) when its fingers close onto the object it holds or open from it; only
/// the finger coordinates (the robot's `gripper` joint group) change, each towards its own
/// target (a right finger's axis may be mirrored), so the held object does not move. Every state
/// is checked with [`Scene::first_contact`]: the fingers may touch what they hold (a held object
/// is no body of the scene's collision checks, and its gripper's links are exempt from the held
/// object's), nothing else. One state, the current one, when the gripper has no fingers.
///
/// # Errors
/// [`WorldError::Fingers`] when the robot holds nothing or a state touches something (the
/// contact and the state's index named); [`WorldError::UnknownName`] for no such robot.
pub fn finger_path(
    scene: &Scene,
    robot: usize,
    movement: FingerMove,
    config: &MotionConfig,
) -> Result<Vec<Vec<f64>>, WorldError> {
    let Some(state) = scene.robots().get(robot) else {
        return Err(WorldError::UnknownName { what: "robot", name: robot.to_string() });
    };
    let start = state.configuration().to_vec();
    if state.open_fingers().is_empty() {
        return Ok(vec![start]);
    }
    let action = match movement {
        FingerMove::Close => "close",
        FingerMove::Open => "open",
    };
    let fail = |reason: String| WorldError::Fingers { robot: state.name.clone(), action, reason };
    let held = scene.held(robot).ok_or_else(|| fail("it holds nothing".to_string()))?;
    let model = state.robot();
    let mut goal = start.clone();
    match movement {
        FingerMove::Close => {
            let object = scene.collision.shape(BodyId(held.body)).ok_or_else(|| {
                fail(format!("`{}` has no shape", scene.bodies()[held.body].name))
            })?;
            let pose = scene.body_pose(held.body);
            for &(finger, _) in state.open_fingers() {
                let Some(stop) = grasp_position(model, finger, &start, object, &pose) else {
                    continue;
                };
                // A finger that closes past the object holds nothing: the grasp is not one a
                // real gripper could carry the object with.
                if !stop.touches {
                    return Err(fail(format!(
                        "`{}` closes past `{}` without touching it: the object is not between \
                         the fingers",
                        model.coordinates()[finger].name,
                        scene.bodies()[held.body].name
                    )));
                }
                goal[finger] = stop.position;
            }
        }
        FingerMove::Open => {
            for &(finger, open) in state.open_fingers() {
                goal[finger] = open;
            }
        }
    }
    let mut states =
        densify(model, &[start.clone(), goal], config).map_err(|error| fail(error.to_string()))?;
    // Interpolation rounds the coordinates that do not move; keep them exactly, so that the
    // gripper link, and the held object with it, stays where it is to the last bit.
    for q in &mut states {
        for (index, value) in q.iter_mut().enumerate() {
            if !state.open_fingers().iter().any(|(finger, _)| *finger == index) {
                *value = start[index];
            }
        }
    }
    for (index, q) in states.iter().enumerate() {
        if let Some(contact) = scene.first_contact(robot, q) {
            return Err(fail(format!("at its state {index} of {}, {contact}", states.len())));
        }
    }
    Ok(states)
}
