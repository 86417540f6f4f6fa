//! Inverse kinematics that only accepts collision-free solutions: the robot crate's solver
//! (damped least squares with random restarts) with the scene as its acceptance test.

use lamp_geometry::Pose;
use lamp_robot::{IkConfig, IkError, LinkId, solve_ik};
use rand_chacha::ChaCha8Rng;

use crate::motion::MotionError;
use crate::scene::Scene;

/// Why a collision-free IK solution could not be found.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum ReachError {
    #[error(transparent)]
    #[diagnostic(transparent)]
    Setup(#[from] MotionError),
    #[error("robot `{robot}` has no gripper link to place")]
    #[diagnostic(code(lamp::ik::no_gripper))]
    NoGripper { robot: String },
    #[error(transparent)]
    #[diagnostic(transparent)]
    Ik(#[from] IkError),
}

/// A configuration of robot `robot` placing `link` (default: its gripper link) at `target`,
/// changing only the coordinates of `group`, valid in the scene (carrying what it holds).
#[allow(clippy::too_many_arguments)] // mirrors lamp_robot::solve_ik plus the scene
pub fn reach(
    scene: &Scene,
    robot: usize,
    group: &str,
    link: Option<LinkId>,
    target: &Pose,
    seed: &[f64],
    config: &IkConfig,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<f64>, ReachError> {
    let state = scene.robots.get(robot).ok_or(MotionError::UnknownRobot { robot })?;
    let model = &state.robot;
    let joint_group = model.group(group).ok_or_else(|| MotionError::UnknownGroup {
        robot: state.name.clone(),
        group: group.to_string(),
    })?;
    let link = match link.or(state.gripper.as_ref().map(|g| g.link)) {
        Some(link) => link,
        None => return Err(ReachError::NoGripper { robot: state.name.clone() }),
    };
    let mut accept = |q: &[f64]| scene.is_valid(robot, q);
    Ok(solve_ik(model, joint_group, link, target, seed, config, rng, &mut accept)?)
}
