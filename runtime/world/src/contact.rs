//! Holding by contact. A gripper without finger joints (a magnet, a suction cup) holds only what
//! it touches: before it takes hold it comes straight to the object, to within [`CONTACT_GAP`],
//! and a hold it makes is one only at that gap ([`Scene::gripper_gap`]). A gripper with fingers
//! closes them instead ([`crate::finger_path`]).

use lamp_geometry::{BodyId, Pose, closest_points, distance, intersects};
use lamp_robot::{ALL_GROUP, IkConfig, Robot};
use nalgebra::Translation3;

use crate::error::WorldError;
use crate::ik::LinkGoal;
use crate::motion::{MotionConfig, densify};
use crate::scene::Scene;
use crate::straight::straight_line;

/// The farthest a contact gripper may be from what it holds (metres): a magnet or a suction cup
/// further away than a millimetre holds nothing.
pub const CONTACT_GAP: f64 = 0.001;

/// The longest straight approach to contact (metres). A gripper farther from the object than
/// this has not been brought to a grasp: that is a motion to plan, not the last approach.
pub const MAX_CONTACT_APPROACH: f64 = 0.03;

/// Where an approach aims to stop (metres): well inside [`CONTACT_GAP`] whatever the inverse
/// kinematics' last rounding, and apart, since touching counts as a collision.
const APPROACH_GAP: f64 = 0.0003;

/// How close to the aimed pose the approach's last state must put the gripper link (metres,
/// radians): a tenth of the room between [`APPROACH_GAP`] and touching or [`CONTACT_GAP`].
const APPROACH_POSITION_TOLERANCE: f64 = 2e-5;
const APPROACH_ORIENTATION_TOLERANCE: f64 = 1e-4;

impl Scene {
    /// Whether robot `robot` holds by contact: it has a gripper, and the gripper has no fingers.
    pub fn holds_by_contact(&self, robot: usize) -> bool {
        self.robots
            .get(robot)
            .is_some_and(|state| state.gripper.is_some() && state.open_fingers.is_empty())
    }

    /// The distance between robot `robot`'s gripper (its link and every link below it) and body
    /// `body`, the robot at its current configuration: 0 when they touch or overlap. `None` when
    /// the robot has no gripper or either has no shape.
    pub fn gripper_gap(&self, robot: usize, body: usize) -> Option<f64> {
        let q = &self.robots.get(robot)?.q;
        self.nearest_gripper_point(robot, body, q).map(|nearest| nearest.gap)
    }

    /// How far the gripper is from `body` with the robot at `q`, and which way (when they are
    /// apart by at most [`MAX_CONTACT_APPROACH`]).
    fn nearest_gripper_point(&self, robot: usize, body: usize, q: &[f64]) -> Option<Nearest> {
        let state = self.robots.get(robot)?;
        state.gripper.as_ref()?;
        let object = self.collision.shape(BodyId(body))?;
        let object_pose = self.body_pose(body);
        let model = &state.robot;
        let mut poses = vec![Pose::identity(); model.link_count()];
        model.forward_kinematics(q, &mut poses);
        let mut nearest: Option<Nearest> = None;
        for (index, (link, shape)) in state.links.iter().enumerate() {
            if !state.touches_held[index] {
                continue;
            }
            let pose = &poses[*link];
            let found = if intersects(shape, pose, object, &object_pose) {
                Nearest { gap: 0.0, towards: None }
            } else {
                let gap = distance(shape, pose, object, &object_pose);
                let towards =
                    closest_points(shape, pose, object, &object_pose, MAX_CONTACT_APPROACH)
                        .map(|(on_link, on_object)| on_object - on_link);
                Nearest { gap, towards }
            };
            if nearest.as_ref().is_none_or(|best| found.gap < best.gap) {
                nearest = Some(found);
            }
        }
        nearest
    }
}

/// The nearest gap between a gripper and an object, and the way from the gripper's nearest
/// point to the object's (world frame; `None` when they touch, overlap, or are farther apart
/// than [`MAX_CONTACT_APPROACH`]).
struct Nearest {
    gap: f64,
    towards: Option<nalgebra::Vector3<f64>>,
}

/// The states robot `robot` passes through (the current configuration first, at the checking
/// resolution of `config`) as its contact gripper comes straight to body `body`: the gripper link
/// translates, without turning, along the line between the nearest points of the gripper and the
/// object until they are [`APPROACH_GAP`] apart. The arm moves and the mount stays, unless the
/// gripper hangs on the mount alone (a free-flying gripper), which then moves. One state, the
/// current one, when the gripper is already within [`CONTACT_GAP`].
///
/// # Errors
/// [`WorldError::Contact`] when the gripper touches or overlaps the object already, is farther
/// than [`MAX_CONTACT_APPROACH`], or cannot make the straight move (out of reach, or it would
/// touch something on the way); [`WorldError::UnknownName`] for no such robot or body.
pub fn contact_approach(
    scene: &Scene,
    robot: usize,
    body: usize,
    config: &MotionConfig,
) -> Result<Vec<Vec<f64>>, WorldError> {
    let Some(state) = scene.robots().get(robot) else {
        return Err(WorldError::UnknownName { what: "robot", name: robot.to_string() });
    };
    let Some(object) = scene.bodies().get(body) else {
        return Err(WorldError::UnknownName { what: "body", name: body.to_string() });
    };
    let fail = |reason: String| WorldError::Contact {
        robot: state.name.clone(),
        object: object.name.clone(),
        reason,
    };
    let start = state.configuration().to_vec();
    let Some(gripper) = state.gripper() else {
        return Err(fail("the robot has no gripper".to_string()));
    };
    let Some(nearest) = scene.nearest_gripper_point(robot, body, &start) else {
        return Err(fail("the object has no shape to touch".to_string()));
    };
    if nearest.gap <= 0.0 {
        return Err(fail("the gripper already touches it".to_string()));
    }
    if nearest.gap <= CONTACT_GAP {
        return Ok(vec![start]);
    }
    let Some(towards) = nearest.towards.filter(|_| nearest.gap <= MAX_CONTACT_APPROACH) else {
        return Err(fail(format!(
            "the gripper is {:.1} mm from it, more than the {:.0} mm a last approach may cover",
            nearest.gap * 1e3,
            MAX_CONTACT_APPROACH * 1e3
        )));
    };
    let model = state.robot();
    let link_pose = model.link_pose(&start, gripper.link);
    let step = towards * ((nearest.gap - APPROACH_GAP) / nearest.gap);
    let target = Translation3::from(step) * link_pose;
    let group = approach_group(model, gripper.link);
    let ik = IkConfig {
        position_tolerance: APPROACH_POSITION_TOLERANCE,
        orientation_tolerance: APPROACH_ORIENTATION_TOLERANCE,
        ..IkConfig::new()
    };
    let goal = LinkGoal { robot, group, link: Some(gripper.link), target: &target, start: &start };
    let line = straight_line(scene, &goal, config, &ik)
        .map_err(|error| fail(format!("the straight approach fails: {error}")))?;
    let states = densify(model, &line, config).map_err(|error| fail(error.to_string()))?;
    let arrived = states.last().unwrap_or(&start);
    match scene.nearest_gripper_point(robot, body, arrived).map(|nearest| nearest.gap) {
        Some(gap) if gap > 0.0 && gap <= CONTACT_GAP => Ok(states),
        Some(gap) => Err(fail(format!(
            "the approach ends {:.2} mm from it, not within the {:.0} mm a hold by contact needs",
            gap * 1e3,
            CONTACT_GAP * 1e3
        ))),
        None => Err(fail("the object has no shape to touch".to_string())),
    }
}

/// The joint group a contact approach moves: the smallest that holds every coordinate of the
/// joints between the mount and the gripper link, or the whole robot when there are none (a
/// gripper on a floating mount).
fn approach_group(model: &Robot, gripper_link: lamp_robot::LinkId) -> &str {
    let chain: Vec<usize> = model
        .chain(gripper_link)
        .iter()
        .filter_map(|&link| model.parent_joint_name(link))
        .filter_map(|joint| model.joint_coordinates(joint).ok())
        .flatten()
        .collect();
    if chain.is_empty() {
        return ALL_GROUP;
    }
    let mut groups: Vec<_> = model
        .groups()
        .filter(|group| chain.iter().all(|coordinate| group.coordinates.contains(coordinate)))
        .collect();
    groups.sort_by_key(|group| (group.coordinates.len(), group.name.clone()));
    groups.first().map_or(ALL_GROUP, |group| group.name.as_str())
}
