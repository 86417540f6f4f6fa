//! Inverse kinematics that only accepts collision-free solutions: the robot crate's solver
//! (damped least squares with random restarts) with the scene as its acceptance test.

use std::cell::RefCell;

use lamp_geometry::{BodyId, Pose};
use lamp_robot::{IkConfig, IkError, IkGoal, JointGroup, LinkId, solve_ik_screened};
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
    let refused = RefCell::new(refused);
    let tolerance = Tolerance::of(config);
    let mut target_possible =
        || match in_the_way_at(scene, robot, joint_group, link, target, seed, tolerance) {
            None => true,
            Some(contact) => {
                (refused.borrow_mut())(contact);
                false
            }
        };
    let mut accept = |q: &[f64]| match scene.first_contact(robot, q) {
        None => true,
        Some(contact) => {
            (refused.borrow_mut())(contact);
            false
        }
    };
    let goal = IkGoal { robot: model, group: joint_group, link, target, seed };
    Ok(solve_ik_screened(&goal, config, rng, &mut target_possible, &mut accept)?)
}

/// How far from its target a configuration the IK accepts may leave the link.
#[derive(Clone, Copy)]
struct Tolerance {
    position: f64,
    orientation: f64,
}

impl Tolerance {
    fn of(config: &IkConfig) -> Tolerance {
        Tolerance { position: config.position_tolerance, orientation: config.orientation_tolerance }
    }

    /// The farthest a point `radius` from the link's origin can be from where it would be at
    /// the target, plus [`SCREEN_SLACK`].
    fn displacement(&self, radius: f64) -> f64 {
        self.position + self.orientation * radius + SCREEN_SLACK
    }
}

/// Room left for the depth parry computes for an overlap (GJK and EPA converge to far less).
const SCREEN_SLACK: f64 = 1e-4;

/// What stands in the way of `link` at `target` whatever the coordinates of `group` are: a part
/// that moves rigidly with the link while only those coordinates change (the link itself, the
/// links beyond it whose joints are outside the group, such as fingers at their values in
/// `seed`, and the object the gripper holds) overlapping a body of the scene deeper than a
/// configuration meeting the target within `tolerance` can move it. Every such configuration
/// then touches that body, and the scene would refuse it. `None` when nothing is known to be in
/// the way.
fn in_the_way_at(
    scene: &Scene,
    robot: usize,
    group: &JointGroup,
    link: LinkId,
    target: &Pose,
    seed: &[f64],
    tolerance: Tolerance,
) -> Option<Contact> {
    let state = scene.robots.get(robot)?;
    let model = &state.robot;
    let mut poses = vec![Pose::identity(); model.link_count()];
    model.forward_kinematics(seed, &mut poses);
    let link_from_seed = poses[link].inverse();
    let rigid = |part: LinkId| -> Option<Pose> {
        let chain = model.chain(part);
        let at = chain.iter().position(|&on_chain| on_chain == link)?;
        let moves_apart = chain[at + 1..].iter().any(|&beyond| {
            model.parent_joint_name(beyond).is_some_and(|joint| {
                model
                    .joint_coordinates(joint)
                    .is_ok_and(|own| own.iter().any(|c| group.coordinates.contains(c)))
            })
        });
        (!moves_apart).then(|| link_from_seed * poses[part])
    };
    let reach_of = |shape: &lamp_geometry::CollisionShape, in_link: &Pose| {
        let aabb = shape.aabb(in_link);
        let farthest = aabb.mins.coords.abs().sup(&aabb.maxs.coords.abs());
        farthest.norm()
    };
    for (part, shape) in &state.links {
        let Some(in_link) = rigid(*part) else { continue };
        let depth = tolerance.displacement(reach_of(shape, &in_link));
        let placed = target * in_link;
        if let Some(body) =
            scene.collision.first_overlap_deeper_than(shape, &placed, depth, |_| false)
        {
            return Some(Contact::LinkBody {
                link: model.link_name(*part).to_string(),
                body: scene.bodies[body.0].name.clone(),
            });
        }
    }
    let gripper = state.gripper.as_ref()?;
    let held = gripper.held?;
    let shape = scene.collision.shape(BodyId(held.body))?;
    let in_link = rigid(gripper.link)? * held.grasp;
    let depth = tolerance.displacement(reach_of(shape, &in_link));
    let skip = |id: BodyId| id.0 == held.body;
    let body =
        scene.collision.first_overlap_deeper_than(shape, &(target * in_link), depth, skip)?;
    Some(Contact::HeldBody {
        held: scene.bodies[held.body].name.clone(),
        body: scene.bodies[body.0].name.clone(),
    })
}
