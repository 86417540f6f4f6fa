//! Straight-line moves of a link in Cartesian space: the approach to a grasp and the retreat
//! from a placement, where the fingers straddle an object and any other way in or out is a
//! narrow passage that a sampling planner finds only by luck.
//!
//! The link's pose is interpolated (position linearly, orientation by slerp) at the checking
//! resolution; each pose is solved by inverse kinematics seeded with the previous solution and
//! no restarts, so that the arm stays on one branch; a solution that jumps, or an edge between
//! two solutions that touches anything, ends the move with an error saying how far it got.

use lamp_robot::{IkConfig, IkError, IkGoal, solve_ik};
use lamp_rrt::{MAX_EDGE_STEPS, Space};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::ik::LinkGoal;
use crate::motion::{MotionConfig, MotionError, RobotSpace, edge_steps};
use crate::scene::Scene;

/// A solution may move no coordinate by more than this many checking resolutions from the one
/// before: more means the solver jumped to another branch, which is no straight move.
const MAX_STEP_RESOLUTIONS: usize = 10;

/// Why a straight-line move could not be made.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum StraightLineError {
    #[error(transparent)]
    #[diagnostic(transparent)]
    Setup(#[from] MotionError),
    #[error("robot `{robot}` has no gripper link to move")]
    #[diagnostic(code(lamp::motion::no_gripper))]
    NoGripper { robot: String },
    #[error("the straight move is out of reach {percent:.0} % of the way: {source}")]
    #[diagnostic(
        code(lamp::motion::straight_unreachable),
        help("the line leaves the arm's workspace; move the base closer or shorten the move")
    )]
    Unreachable {
        percent: f64,
        #[source]
        source: IkError,
    },
    #[error("the straight move needs the arm to jump {percent:.0} % of the way (a singularity)")]
    #[diagnostic(code(lamp::motion::straight_jump))]
    Jump { percent: f64 },
    #[error("the straight move touches something {percent:.0} % of the way: {contact}")]
    #[diagnostic(code(lamp::motion::straight_collision))]
    Collision { percent: f64, contact: String },
}

/// Configurations of `goal.group` that move `goal.link` (default: the robot's gripper link) from
/// where it is in `goal.start` to `goal.target` along a straight line, starting with
/// `goal.start`; consecutive ones are
/// joined by collision-free edges at the checking resolution of `motion`. `ik` gives the
/// tolerances at `target`; on the way, the solver's default tolerances (1 mm, 0.01 rad) keep the
/// link that close to the line. Its restarts are not used.
pub fn straight_line(
    scene: &Scene,
    goal: &LinkGoal<'_>,
    motion: &MotionConfig,
    ik: &IkConfig,
) -> Result<Vec<Vec<f64>>, StraightLineError> {
    let LinkGoal { robot, group, link, target, start } = *goal;
    let space = RobotSpace::new(scene, robot, group, start, start, motion)?;
    let state = &scene.robots()[robot];
    let model = state.robot();
    let joint_group = model.group(group).ok_or_else(|| MotionError::UnknownGroup {
        robot: state.name.clone(),
        group: group.to_string(),
    })?;
    let Some(link) = link.or(state.gripper().map(|gripper| gripper.link)) else {
        return Err(StraightLineError::NoGripper { robot: state.name.clone() });
    };
    let from = model.link_pose(start, link);
    let distance = (target.translation.vector - from.translation.vector).norm();
    let angle = from.rotation.angle_to(&target.rotation);
    let count = (distance / motion.linear_resolution).max(angle / motion.angular_resolution).ceil();
    if count.is_nan() || count > MAX_EDGE_STEPS as f64 {
        let distance = format!("{distance:.3} m and {angle:.3} rad");
        let limit = MAX_EDGE_STEPS;
        return Err(MotionError::TooManySteps { distance, steps: count, limit }.into());
    }
    // Whole, and at most MAX_EDGE_STEPS.
    let count = count.max(1.0) as usize;
    let on_the_way = IkConfig { restarts: 0, max_iterations: ik.max_iterations, ..IkConfig::new() };
    let at_the_end = IkConfig { restarts: 0, ..ik.clone() };
    // With no restarts the solver draws nothing; it still takes a generator.
    let mut unused = ChaCha8Rng::seed_from_u64(0);
    let mut path = vec![start.to_vec()];
    for i in 1..=count {
        let t = i as f64 / count as f64;
        let percent = 100.0 * t;
        let pose = from.lerp_slerp(target, t);
        let previous = path.last().expect("the path starts with `start`");
        let config = if i == count { &at_the_end } else { &on_the_way };
        let goal = IkGoal { robot: model, group: joint_group, link, target: &pose, seed: previous };
        let q = solve_ik(&goal, config, &mut unused, &mut |_| true)
            .map_err(|source| StraightLineError::Unreachable { percent, source })?;
        let steps =
            edge_steps(model, previous, &q, motion.linear_resolution, motion.angular_resolution);
        if steps > MAX_STEP_RESOLUTIONS {
            return Err(StraightLineError::Jump { percent });
        }
        if !space.is_valid(&q) || !space.edge_is_valid(previous, &q) {
            let contact = first_contact_along(scene, robot, previous, &q, motion)
                .unwrap_or_else(|| "a contact".to_string());
            return Err(StraightLineError::Collision { percent, contact });
        }
        path.push(q);
    }
    Ok(path)
}

/// The first contact on the edge from `a` to `b` at the checking resolution, for the message.
fn first_contact_along(
    scene: &Scene,
    robot: usize,
    a: &[f64],
    b: &[f64],
    motion: &MotionConfig,
) -> Option<String> {
    let model = scene.robots()[robot].robot();
    let steps = edge_steps(model, a, b, motion.linear_resolution, motion.angular_resolution);
    let mut q = a.to_vec();
    (1..=steps).find_map(|i| {
        model.interpolate(a, b, i as f64 / steps as f64, &mut q);
        scene.first_contact(robot, &q).map(|contact| contact.to_string())
    })
}
