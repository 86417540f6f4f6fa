//! What a controller executes of a solution: every motion between two grasp changes as a
//! `trajectory_msgs/msg/JointTrajectory` of the timed steps, and every grasp and release as a
//! `control_msgs/msg/GripperCommand`. lamp-trajectory writes them beside the viewers' channels;
//! `docs/formats.md` ("Channels for controllers") describes them.

use lamp_geometry::{CollisionShape, Pose, intersects};
use lamp_robot::{CoordinateKind, GRIPPER_GROUP, LinkId, Robot};
use lamp_trajectory::{
    BASE_TRAJECTORY_TOPIC, GRIPPER_COMMAND_TOPIC, GripperCommand, JOINT_TRAJECTORY_TOPIC,
    JointTrajectoryMessage, StandardChannels, StandardStep, Step, Trajectory, TrajectoryPoint,
    TrajectoryTopic,
};
use nalgebra::{Translation3, UnitQuaternion, Vector3};

use crate::error::WorldError;
use crate::from_spec::SpecWorld;

/// The command position of a gripper without finger joints (a magnet, a suction cup) when it
/// takes hold: on.
pub const HOLD_ON: f64 = 1.0;
/// The command position of a gripper without finger joints when it lets go: off.
pub const HOLD_OFF: f64 = 0.0;

/// The motions of `steps`: the first and last index of every run of two or more steps with no
/// grasp change between consecutive ones, in order. These are the runs `time_steps` times from
/// rest to rest, each a collision-checked path between two grasp changes (or the start or end).
pub fn motion_segments(steps: &[Step]) -> Vec<(usize, usize)> {
    let mut segments = Vec::new();
    let mut start = 0;
    for index in 1..=steps.len() {
        let grasp_change = index == steps.len() || steps[index - 1].grasp_changes_to(&steps[index]);
        if grasp_change {
            if index - 1 > start {
                segments.push((start, index - 1));
            }
            start = index;
        }
    }
    segments
}

/// One robot's topics for a controller, as indices into the writer's topic lists.
struct RobotTopics<'a> {
    robot: &'a Robot,
    /// Per trajectory topic of the robot: its index and the coordinates it moves.
    trajectories: Vec<(usize, Vec<usize>)>,
    /// The first gripper topic of the robot; its grippers follow in order.
    first_gripper: usize,
    /// The robot's finger coordinates (its `gripper` joint group), driven by gripper commands.
    fingers: Vec<usize>,
}

/// Adds to `channels` and `values` (one per step of `trajectory`, a solution stamped by
/// [`crate::time_steps`]) the channels a controller executes:
///
/// - per robot, on `/lamp/joint_trajectory` (`/<robot>/lamp/joint_trajectory` when the file has
///   several robots), its URDF joints' coordinates but the fingers, and on
///   `/lamp/base_trajectory` its mount's coordinates (a mobile base's `base_x`, `base_y`,
///   `base_yaw`; a free-flying gripper's position and rotation vector), each topic only when
///   the robot has such coordinates: one `JointTrajectory` at the first step of every
///   [`motion_segments`] segment in which they move, one point per step of the segment, the
///   positions as recorded, the time from the segment's first stamp, and as velocity the mean of
///   the average velocities (displacement over time) of the pieces before and after the step,
///   zero at both ends, where the robot is at rest;
/// - per gripper, on `/lamp/gripper_command` (prefixed like the held topic), one
///   `GripperCommand` where the gripper starts to close or open: at a grasp, the last step
///   before the change (the fingers close after it, onto the held object), with the position at
///   which the first finger touches the object ([`grasp_position`]; its lower limit, closed,
///   when that is not known); at a release, the first step of the run just before the change in
///   which only the fingers move (they open while the object is still held; the step before the
///   change when they do not move), with the position the first finger has when it lets go, the
///   open value it returned to; for a gripper without finger joints (a magnet), [`HOLD_ON`] at a
///   grasp and [`HOLD_OFF`] at a release, at the step before the change. `max_effort` is 0: lamp
///   models no grip force. A motion ([`motion_segments`]) may begin with the fingers closing or
///   end with them opening; the arm's trajectory holds its joints still meanwhile.
pub fn execution_channels(
    world: &SpecWorld,
    trajectory: &Trajectory,
    channels: &mut StandardChannels,
    values: &mut [StandardStep],
) -> Result<(), WorldError> {
    let header = &trajectory.header;
    let steps = &trajectory.steps;
    if values.len() != steps.len() {
        return Err(WorldError::Timing {
            step: values.len().min(steps.len()),
            reason: format!("{} steps but {} sets of channel values", steps.len(), values.len()),
        });
    }
    let counts = |step: &Step| {
        step.robots.len() == header.robots.len()
            && step.robots.iter().zip(&header.robots).all(|(state, robot)| {
                state.held.len() == robot.grippers.len()
                    && state.held.iter().flatten().all(|body| *body < step.body_poses.len())
            })
    };
    if let Some(step) = steps.iter().position(|step| !counts(step)) {
        return Err(WorldError::Timing {
            step,
            reason: "its robots, grippers or held bodies differ from the header's".to_string(),
        });
    }
    let several = header.robots.len() > 1;
    let topic = |robot: &str, name: &str| match several {
        true => format!("/{robot}{name}"),
        false => name.to_string(),
    };
    let mut robots = Vec::new();
    for description in &header.robots {
        let unknown = || WorldError::UnknownName { what: "robot", name: description.name.clone() };
        let robot = world.robots.get(&description.name).ok_or_else(unknown)?;
        let names = robot.coordinate_names();
        let mount = robot.mount().coordinate_count();
        let fingers = robot.group(GRIPPER_GROUP).map(|group| group.coordinates.clone());
        let fingers = fingers.unwrap_or_default();
        let joints: Vec<usize> = (mount..robot.dof()).filter(|c| !fingers.contains(c)).collect();
        let mut trajectories = Vec::new();
        let groups =
            [(JOINT_TRAJECTORY_TOPIC, joints), (BASE_TRAJECTORY_TOPIC, (0..mount).collect())];
        for (name, coordinates) in groups {
            if coordinates.is_empty() {
                continue;
            }
            trajectories.push((channels.trajectory_topics.len(), coordinates.clone()));
            channels.trajectory_topics.push(TrajectoryTopic {
                topic: topic(&description.name, name),
                joints: coordinates.iter().map(|c| names[*c].clone()).collect(),
            });
        }
        let first_gripper = channels.gripper_topics.len();
        for gripper in &description.grippers {
            channels.gripper_topics.push(match description.grippers.len() > 1 {
                false => topic(&description.name, GRIPPER_COMMAND_TOPIC),
                true => format!("/{}{GRIPPER_COMMAND_TOPIC}/{gripper}", description.name),
            });
        }
        robots.push(RobotTopics { robot, trajectories, first_gripper, fingers });
    }

    for (first, last) in motion_segments(steps) {
        for (index, topics) in robots.iter().enumerate() {
            let states = || steps[first..=last].iter().map(|step| &step.robots[index]);
            let velocities = segment_velocities(topics.robot, steps, index, first, last)?;
            for (topic, coordinates) in &topics.trajectories {
                let start = &steps[first].robots[index].positions;
                let moves = states()
                    .any(|state| coordinates.iter().any(|c| state.positions[*c] != start[*c]));
                if !moves {
                    continue;
                }
                let points = states()
                    .zip(&steps[first..=last])
                    .zip(&velocities)
                    .map(|((state, step), velocity)| TrajectoryPoint {
                        positions: coordinates.iter().map(|c| state.positions[*c]).collect(),
                        velocities: coordinates.iter().map(|c| velocity[*c]).collect(),
                        time_from_start_nanoseconds: step
                            .time_nanoseconds
                            .saturating_sub(steps[first].time_nanoseconds),
                    })
                    .collect();
                values[first].trajectories.push(JointTrajectoryMessage { topic: *topic, points });
            }
        }
    }

    for index in 1..steps.len() {
        let (before, after) = (&steps[index - 1], &steps[index]);
        for (robot, topics) in robots.iter().enumerate() {
            let held = before.robots[robot].held.iter().zip(&after.robots[robot].held);
            for (gripper, (was, is)) in held.enumerate() {
                if was == is {
                    continue;
                }
                let position = match (topics.fingers.first(), is) {
                    (Some(finger), Some(body)) => {
                        let q = &before.robots[robot].positions;
                        let object = header.bodies.get(*body).and_then(|body| {
                            let parts = world.type_parts.get(&body.type_name)?;
                            CollisionShape::compound(parts).ok()
                        });
                        let pose = after.body_poses.get(*body);
                        let touching = object.zip(pose).and_then(|(object, pose)| {
                            grasp_position(topics.robot, *finger, q, &object, pose)
                                .map(|stop| stop.position)
                        });
                        touching.unwrap_or(topics.robot.coordinates()[*finger].lower)
                    }
                    (Some(finger), None) => after.robots[robot].positions[*finger],
                    (None, Some(_)) => HOLD_ON,
                    (None, None) => HOLD_OFF,
                };
                // A release's fingers open before it (the solver records the opening while
                // the object is still held): the command goes where they start to.
                let mut at = index - 1;
                if is.is_none() && !topics.fingers.is_empty() {
                    while at > 0 && only_fingers_move(&steps[at - 1], &steps[at], robot, topics) {
                        at -= 1;
                    }
                }
                values[at].gripper_commands.push(GripperCommand {
                    topic: topics.first_gripper + gripper,
                    position,
                    max_effort: 0.0,
                });
            }
        }
    }
    Ok(())
}

/// Whether from `before` to `after` robot `robot` moves its finger coordinates and nothing else,
/// no other robot moves and no grasp changes.
fn only_fingers_move(before: &Step, after: &Step, robot: usize, topics: &RobotTopics<'_>) -> bool {
    let same_elsewhere = before.robots.iter().zip(&after.robots).enumerate().all(|(k, (a, b))| {
        a.held == b.held
            && (k == robot
                || a.positions.iter().zip(&b.positions).all(|(x, y)| x.to_bits() == y.to_bits()))
    });
    let (a, b) = (&before.robots[robot].positions, &after.robots[robot].positions);
    let moved: Vec<usize> = (0..a.len().min(b.len())).filter(|&c| a[c] != b[c]).collect();
    same_elsewhere && !moved.is_empty() && moved.iter().all(|c| topics.fingers.contains(c))
}

/// The position of the prismatic finger joint `finger` at which the finger, closing from its
/// open limit with the rest of the robot at `q`, first touches `object` at `pose` (world frame):
/// where the finger's inner face (its collision geometry's nearest point along the direction
/// the finger opens) meets the object's farthest point along that direction. Both are measured
/// by bounding boxes in a frame whose x axis is that direction, exact along it; where the object
/// is turned so that its farthest point lies beside the face, the finger closes on, by
/// bisection with the exact collision test, until it touches (within 1 nm), or to its lower
/// limit when it closes past the object ([`FingerStop::touches`] false: the object is not
/// between the fingers). Clamped to the joint's limits. `None` when the finger is not a
/// prismatic joint with collision geometry.
pub fn grasp_position(
    robot: &Robot,
    finger: usize,
    q: &[f64],
    object: &CollisionShape,
    pose: &Pose,
) -> Option<FingerStop> {
    let coordinate = robot.coordinates().get(finger)?;
    if coordinate.kind != CoordinateKind::Linear || q.len() != robot.dof() {
        return None;
    }
    let link: LinkId = (1..robot.link_count())
        .find(|link| robot.parent_joint_name(*link) == Some(coordinate.name.as_str()))?;
    let parts: Vec<(Pose, lamp_geometry::Shape)> = robot
        .collision_geometry()
        .iter()
        .filter(|geometry| geometry.link == link)
        .map(|geometry| (geometry.origin, geometry.shape.clone()))
        .collect();
    if parts.is_empty() {
        return None;
    }
    let shape = CollisionShape::compound(&parts).ok()?;
    let (lower, upper) = (coordinate.lower, coordinate.upper);
    let at = |value: f64| {
        let mut moved = q.to_vec();
        moved[finger] = value;
        robot.link_pose(&moved, link)
    };
    // The direction the finger opens in, and how far it goes per unit of the joint.
    let step = (upper - lower).min(1.0);
    if step.is_nan() || step <= 0.0 {
        return None;
    }
    let (closed, opened) = (at(lower), at(lower + step));
    let travel: Vector3<f64> = opened.translation.vector - closed.translation.vector;
    let rate = travel.norm() / step;
    let direction = travel.try_normalize(1e-12)?;
    let turn = UnitQuaternion::rotation_between(&Vector3::x(), &direction).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI)
    });
    let frame = Pose::from_parts(Translation3::identity(), turn).inverse();
    let face = shape.aabb(&(frame * closed)).mins.x;
    let reach = object.aabb(&(frame * pose)).maxs.x;
    let value = lower + (reach - face) / rate;
    if !value.is_finite() {
        return None;
    }
    // The boxes are exact along the direction, not across it: where the object is turned in the
    // gripper, its farthest point may lie beside the finger's face, which then stops short of it.
    // The contact is then found by bisection between there (free) and the closed limit.
    let value = value.clamp(lower, upper);
    let touches = |value: f64| intersects(&shape, &at(value), object, pose);
    if touches(value) {
        return Some(FingerStop { position: value, touches: true });
    }
    if !touches(lower) {
        return Some(FingerStop { position: lower, touches: false });
    }
    let (mut free, mut touching) = (value, lower);
    for _ in 0..TOUCH_ITERATIONS {
        if (free - touching) * rate <= TOUCH_GAP {
            break;
        }
        let middle = 0.5 * (free + touching);
        if touches(middle) {
            touching = middle;
        } else {
            free = middle;
        }
    }
    Some(FingerStop { position: free, touches: true })
}

/// Where a closing finger stops ([`grasp_position`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FingerStop {
    /// The finger joint's position.
    pub position: f64,
    /// Whether the finger touches the object there; false when it closes past it to its lower
    /// limit, the object not being between the fingers.
    pub touches: bool,
}

/// How close (metres) [`grasp_position`] brings a finger to the object it closes onto, and at
/// most how many halvings it takes to get there.
const TOUCH_GAP: f64 = 1e-9;
const TOUCH_ITERATIONS: usize = 64;

/// Per step of the segment `first..=last`, every coordinate's velocity: the mean of the pieces'
/// average velocities before and after the step (a piece of zero time counts as at rest), zero
/// at both ends. Each piece's average keeps the velocity limits (`time_steps`), so the mean does.
fn segment_velocities(
    robot: &Robot,
    steps: &[Step],
    index: usize,
    first: usize,
    last: usize,
) -> Result<Vec<Vec<f64>>, WorldError> {
    let dof = robot.dof();
    let mut pieces = Vec::with_capacity(last - first);
    for k in first..last {
        let (from, to) = (&steps[k], &steps[k + 1]);
        let mut piece = vec![0.0; dof];
        let (a, b) = (&from.robots[index].positions, &to.robots[index].positions);
        if a.len() != dof || b.len() != dof {
            return Err(WorldError::Configuration {
                robot: robot.name().to_string(),
                reason: format!("step {k} has {} coordinates, the robot {dof}", a.len()),
            });
        }
        robot.displacement(a, b, &mut piece);
        let seconds = to.time_nanoseconds.saturating_sub(from.time_nanoseconds) as f64 * 1e-9;
        for value in &mut piece {
            *value = if seconds > 0.0 { *value / seconds } else { 0.0 };
        }
        pieces.push(piece);
    }
    let mut velocities = vec![vec![0.0; dof]; last - first + 1];
    for k in 1..last - first {
        for c in 0..dof {
            velocities[k][c] = 0.5 * (pieces[k - 1][c] + pieces[k][c]);
        }
    }
    Ok(velocities)
}
