//! Inverse kinematics that only accepts collision-free solutions: the robot crate's solver
//! (damped least squares with random restarts) with the scene as its acceptance test.

use lamp_geometry::Pose;
use lamp_robot::{IkConfig, IkError, IkGoal, LinkId, solve_ik};
use rand_chacha::ChaCha8Rng;

use crate::checking::Contact;
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

/// Where a move of a scene's robot takes one of its links: robot `robot` (an index into the
/// scene's robots) places `link` (default: its gripper link) at `target`, changing only the
/// coordinates of `group`, from the configuration `start` (the seed of [`reach`], the first
/// state of [`straight_line`](crate::straight_line)).
#[derive(Debug, Clone, Copy)]
pub struct LinkGoal<'a> {
    pub robot: usize,
    pub group: &'a str,
    pub link: Option<LinkId>,
    pub target: &'a Pose,
    pub start: &'a [f64],
}

/// A configuration that meets `goal`, valid in the scene (carrying what it holds).
pub fn reach(
    scene: &Scene,
    goal: &LinkGoal<'_>,
    config: &IkConfig,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<f64>, ReachError> {
    reach_observed(scene, goal, config, rng, &mut |_| {})
}

/// [`reach`], telling `refused` why each configuration that met the target was refused (the
/// first contact the scene finds), so that a caller can say what stood in the way.
pub fn reach_observed(
    scene: &Scene,
    goal: &LinkGoal<'_>,
    config: &IkConfig,
    rng: &mut ChaCha8Rng,
    refused: &mut dyn FnMut(Contact),
) -> Result<Vec<f64>, ReachError> {
    let LinkGoal { robot, group, link, target, start: seed } = *goal;
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
    let mut accept = |q: &[f64]| match scene.first_contact(robot, q) {
        None => true,
        Some(contact) => {
            refused(contact);
            false
        }
    };
    let goal = IkGoal { robot: model, group: joint_group, link, target, seed };
    Ok(solve_ik(&goal, config, rng, &mut accept)?)
}
