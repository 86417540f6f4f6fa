//! Demonstrations from ordinary ROS 2 bags: `/tf` (and `/tf_static`), `/joint_states` and a
//! `std_msgs/msg/String` topic naming the held frame become the same [`Trajectory`] a native
//! lamp file holds, given a mapping from tf frames to the spec's objects and robot.
//!
//! A mapped object whose frame has no transform anywhere in the bag is absent: the demonstration
//! has no body for it ([`Ros2Bag::absent`]); [`BagTally`] refuses a frame that no bag of a source
//! records. The robot's frame, its joints and its held topic are required.
//!
//! The resampling rule, which `docs/demonstrations.md` repeats: one step per `/tf` message, at
//! its log time, from the first `/tf` message at which every mapped frame the bag records is
//! known; at a step,
//! every frame's transform is the latest one received up to and including that message
//! (`/tf_static` ones count from the start), the joint values are the latest `/joint_states`
//! message logged at or before the step's time, and the held frame the latest message of the held
//! topic logged at or before it (a robot frame `P/ROOT` whose last part is the robot's root link
//! reads joint `J` as `P/J` when the bag has that name). A mapped frame's world pose is its transforms composed up to the
//! root of its tree, which must be the same for every mapped frame. With a grasp joint instead of a
//! held topic, the gripper holds nothing while the joint's value is at or above the closing value;
//! at the step the joint closes, it takes the movable object whose origin is nearest the gripper
//! link within the robot's grab distance (none if there is none), and keeps it until it opens.

use std::collections::{BTreeMap, BTreeSet};

use lamp_robot::{LinkId, Robot};
pub use lamp_spec::{FrameObject, FrameRobot, GraspJoint, Ros2Mapping};
use lamp_trajectory::{
    BagTfMessage, BodyDescription, RobotDescription, RobotState, StandardRecording, Step,
    Trajectory, TrajectoryError, TrajectoryHeader, read_standard_channels,
};
use nalgebra::Isometry3;

/// The largest distance a mapped frame may move between two consecutive steps: 0.5 m.
/// Robots and the objects they carry move a few centimetres between messages at recording rates
/// (10 to 100 Hz); a frame that moves further is a tracking glitch or a wrong mapping.
pub const MAX_FRAME_JUMP: f64 = 0.5;

/// How far past its URDF limits a recorded joint value may be (rad or m): a real arm's encoders
/// read a little beyond the limits its model states, never a tenth of a radian or 5 cm.
pub const JOINT_LIMIT_SLACK: f64 = 0.05;

/// The largest magnitude of a joint value without limits (a continuous joint, rad): beyond 2³²
/// an `f64` no longer resolves a micro-radian, so the value says nothing about the angle.
pub const MAX_UNLIMITED_JOINT: f64 = 4_294_967_296.0;

/// The most transforms a mapped frame's chain up to the root of its tree may have. Robots' tf
/// trees are a few dozen frames deep, so a longer chain is a broken recording; the cap also bounds
/// the work of resolving every mapped frame at every message.
pub const MAX_TREE_DEPTH: usize = 1000;

/// The robot a mapping's robot is in the spec: its model and gripper.
#[derive(Debug, Clone)]
pub struct MappedRobot<'a> {
    pub model: &'a Robot,
    /// The name the gripper is listed under (the spec's gripper part type), if it has one.
    pub gripper: Option<String>,
    /// How grasps are detected from a gripper joint, when the mapping names one.
    pub grasp: Option<JointGrasp>,
}

/// A mapping's grasp joint with what detecting grasps from it takes from the spec.
#[derive(Debug, Clone)]
pub struct JointGrasp {
    /// The joint's name on `/joint_states` and the value below which it is closed.
    pub joint: GraspJoint,
    /// The link whose origin is measured to the objects': the gripper part's link.
    pub gripper_link: LinkId,
    /// The robot's grab distance (metres, inclusive).
    pub grab_distance: (f64, f64),
    /// Per mapped object, whether the robot may hold it (its type is movable).
    pub holdable: Vec<bool>,
}

/// The spec robot of `mapping`'s robot, with its gripper and grasp joint resolved.
pub fn mapped_robot<'a>(
    world: &'a lamp_world::SpecWorld,
    mapping: &Ros2Mapping,
) -> Result<Option<MappedRobot<'a>>, lamp_world::WorldError> {
    let Some(mapped) = &mapping.robot else { return Ok(None) };
    let spec = world.spec();
    let unknown = |what: &'static str, name: &str| lamp_world::WorldError::UnknownName {
        what,
        name: name.to_string(),
    };
    let model = world.robots.get(&mapped.robot).ok_or_else(|| unknown("robot", &mapped.robot))?;
    let spec_robot = spec.robot(&mapped.robot).ok_or_else(|| unknown("robot", &mapped.robot))?;
    let part = spec_robot.gripper_part();
    let gripper = part.map(|part| part.type_name.clone());
    let grasp = match &mapped.grasp_joint {
        None => None,
        Some(joint) => {
            // The checker requires a part and a grab distance for a grasp joint.
            let part = part.ok_or_else(|| unknown("gripper part of robot", &mapped.robot))?;
            let gripper_link =
                model.link_id(&part.link).ok_or_else(|| unknown("gripper link", &part.link))?;
            let grab_distance = spec_robot
                .grab_distance
                .ok_or_else(|| unknown("grab distance of robot", &mapped.robot))?;
            let holdable = mapping
                .objects
                .iter()
                .map(|object| {
                    spec.object_type(&object.type_name)
                        .is_some_and(|t| t.mobility == lamp_spec::Mobility::Movable)
                })
                .collect();
            Some(JointGrasp { joint: joint.clone(), gripper_link, grab_distance, holdable })
        }
    };
    Ok(Some(MappedRobot { model, gripper, grasp }))
}

/// Why a bag could not be read as a demonstration.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum Ros2Error {
    /// The bag's records or standard messages could not be read.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Read(#[from] TrajectoryError),

    /// The bag has no `/tf` message.
    #[error("{file} has no `/tf` message")]
    #[diagnostic(
        code(lamp::ros2::no_tf),
        help("A demonstration bag records the frames' poses on `/tf` (tf2_msgs/msg/TFMessage).")
    )]
    NoTf { file: String },

    /// A mapped frame never appears, or never joins the tree of the other mapped frames.
    #[error("{file}: frame `{frame}` {reason}")]
    #[diagnostic(
        code(lamp::ros2::missing_frame),
        help("Check the frame names of the mapping against the bag's `/tf` and `/tf_static`.")
    )]
    MissingFrame { file: String, frame: String, reason: String },

    /// A mapped frame moves further between two steps than any recording rate allows.
    #[error(
        "{file}, at {time_nanoseconds} ns: frame `{frame}` jumps {distance:.3} m since the previous step"
    )]
    #[diagnostic(
        code(lamp::ros2::jump),
        help(
            "A frame may move at most 0.5 m between two `/tf` messages; check the tracking or the mapping."
        )
    )]
    Jump { file: String, frame: String, time_nanoseconds: u64, distance: f64 },

    /// A mapped frame's chain of parents on `/tf` and `/tf_static` comes back to a frame it
    /// passed: it has no root, so no world pose.
    #[error(
        "{file}, at {time_nanoseconds} ns: frame `{frame}` has no root on `/tf`: its parents form the cycle {cycle}"
    )]
    #[diagnostic(
        code(lamp::ros2::tf_cycle),
        help(
            "In a tf tree every frame has one parent and the chain of parents ends at a root (such as `world`): find the transform in the cycle whose parent and child are swapped or misnamed, and record it the right way round."
        )
    )]
    TfCycle { file: String, frame: String, time_nanoseconds: u64, cycle: String },

    /// A mapped frame's chain of parents is longer than [`MAX_TREE_DEPTH`].
    #[error(
        "{file}, at {time_nanoseconds} ns: frame `{frame}` is more than {max_depth} transforms below the root of its tf tree (its chain passes `{deepest}`)"
    )]
    #[diagnostic(
        code(lamp::ros2::tf_depth),
        help(
            "A frame's chain of parents may have at most {max_depth} transforms; publish the mapped frame's pose in a frame nearer the root, or map a frame higher in the tree."
        )
    )]
    TfTooDeep {
        file: String,
        frame: String,
        time_nanoseconds: u64,
        max_depth: usize,
        /// The frame the chain had reached when the limit was hit.
        deepest: String,
    },

    /// Message times go backwards.
    #[error("{file}: {reason}")]
    #[diagnostic(
        code(lamp::ros2::timing),
        help("Log `/tf` messages in time order, with each frame's stamps never decreasing.")
    )]
    Timing { file: String, reason: String },

    /// The held topic names a frame the mapping does not list.
    #[error(
        "{file}, at {time_nanoseconds} ns: the gripper holds frame `{frame}`, which the mapping does not list"
    )]
    #[diagnostic(
        code(lamp::ros2::held),
        help("Map every frame the robot may hold to an object, or check the held topic.")
    )]
    UnknownHeld { file: String, frame: String, time_nanoseconds: u64 },

    /// The held topic names a mapped frame that the bag never records.
    #[error(
        "{file}, at {time_nanoseconds} ns: the gripper holds frame `{frame}`, which has no transform on `/tf` or `/tf_static` in this bag"
    )]
    #[diagnostic(
        code(lamp::ros2::held_absent),
        help(
            "An object the robot holds must have its pose on `/tf` from the first step: record its frame, or check the held topic."
        )
    )]
    HeldAbsent { file: String, frame: String, time_nanoseconds: u64 },

    /// A mapped object's frame is in none of the bags of its source: most likely a misspelt
    /// frame, since an object absent from every demonstration is learned nothing about.
    #[error(
        "frame `{frame}` of object `{object}` has no transform on `/tf` or `/tf_static` in any of the {bags} bag(s) of `{pattern}`"
    )]
    #[diagnostic(
        code(lamp::ros2::frame_in_no_bag),
        help(
            "An object whose frame a bag lacks is absent from that demonstration, but a frame no bag records is most likely misspelt: check `{frame}` against the frames the bags publish, or remove the object from the mapping."
        )
    )]
    FrameInNoBag { pattern: String, object: String, frame: String, bags: usize },

    /// The mapping's held topic is not in the bag.
    #[error("{file} has no topic `{topic}`, the mapping's held topic; its topics are: {topics}")]
    #[diagnostic(
        code(lamp::ros2::held_topic),
        help(
            "Record which frame the gripper holds on the held topic (std_msgs/msg/String), or correct the topic's name in the mapping."
        )
    )]
    NoHeldTopic { file: String, topic: String, topics: String },

    /// A joint value no robot could have: far outside the joint's limits.
    #[error(
        "{file}, at {time_nanoseconds} ns: joint `{joint}` of robot `{robot}` is at {} on `/joint_states`, outside its limits [{}, {}]",
        lamp_spec::limits::number(*.value),
        lamp_spec::limits::number(*.lower),
        lamp_spec::limits::number(*.upper)
    )]
    #[diagnostic(
        code(lamp::ros2::joint_range),
        help(
            "Check the joint's units (radians, metres) and the URDF's limits; a value may pass a limit by at most 0.05."
        )
    )]
    JointOutOfRange {
        file: String,
        robot: String,
        joint: String,
        value: f64,
        lower: f64,
        upper: f64,
        time_nanoseconds: u64,
    },

    /// A joint of the robot has no value in `/joint_states`.
    #[error(
        "{file}: joint `{joint}` of robot `{robot}` has no value on `/joint_states` by the first step"
    )]
    #[diagnostic(
        code(lamp::ros2::joint),
        help("Record the robot's joint states on `/joint_states` under the URDF's joint names.")
    )]
    MissingJoint { file: String, robot: String, joint: String },
}

/// The values a joint may be recorded at (before [`JOINT_LIMIT_SLACK`]): its limits, or for a
/// continuous joint, which a driver reports unwrapped, any angle an `f64` still resolves.
fn recordable_range(coordinate: &lamp_robot::Coordinate) -> (f64, f64) {
    let unlimited = coordinate.kind == lamp_robot::CoordinateKind::WrappedAngle
        || !coordinate.lower.is_finite()
        || !coordinate.upper.is_finite();
    if unlimited {
        (-MAX_UNLIMITED_JOINT, MAX_UNLIMITED_JOINT)
    } else {
        (coordinate.lower, coordinate.upper)
    }
}

/// A bag read as a demonstration: the trajectory, whose bodies are the mapped objects present in
/// the bag, and which mapped objects it lacks.
#[derive(Debug, Clone)]
pub struct Ros2Bag {
    pub trajectory: Trajectory,
    /// The indices in the mapping's `objects` of the objects whose frame has no transform on
    /// `/tf` or `/tf_static` anywhere in the bag, ascending: the demonstration has no body for them.
    pub absent: Vec<usize>,
}

/// Reads the bag `bytes` (named `file` in errors) as a demonstration of `domain` with `mapping`;
/// the trajectory of [`ros2_bag`].
pub fn ros2_trajectory(
    bytes: &[u8],
    file: &str,
    domain: &str,
    mapping: &Ros2Mapping,
    robot: Option<&MappedRobot<'_>>,
) -> Result<Trajectory, Ros2Error> {
    ros2_bag(bytes, file, domain, mapping, robot).map(|bag| bag.trajectory)
}

/// Reads the bag `bytes` (named `file` in errors) as a demonstration of `domain` with `mapping`.
/// A mapped object whose frame has no transform anywhere in the bag is absent: the
/// demonstration has no body for it, and [`Ros2Bag::absent`] names it. The robot's frame, its
/// joints and its held topic are required.
pub fn ros2_bag(
    bytes: &[u8],
    file: &str,
    domain: &str,
    mapping: &Ros2Mapping,
    robot: Option<&MappedRobot<'_>>,
) -> Result<Ros2Bag, Ros2Error> {
    let held_topic = mapping.robot.as_ref().and_then(|robot| robot.held_topic.as_deref());
    let recording = read_standard_channels(bytes, file, held_topic.as_slice())?;
    let held_messages = held_messages(&recording, file, held_topic)?;
    let recorded: BTreeSet<&str> = recording
        .tf_static
        .iter()
        .chain(&recording.tf)
        .flat_map(|message| &message.transforms)
        .map(|transform| transform.frame.as_str())
        .collect();
    let absent: Vec<usize> = (mapping.objects.iter().enumerate())
        .filter(|(_, object)| !recorded.contains(object.frame.as_str()))
        .map(|(index, _)| index)
        .collect();
    if let Some((time, frame)) = held_messages
        .iter()
        .find(|(_, frame)| absent.iter().any(|&index| mapping.objects[index].frame == *frame))
    {
        return Err(Ros2Error::HeldAbsent {
            file: file.to_string(),
            frame: frame.clone(),
            time_nanoseconds: *time,
        });
    }
    let present_mapping;
    let present_robot;
    let (mapping, robot) = if absent.is_empty() {
        (mapping, robot)
    } else {
        let present = |index: &usize| absent.binary_search(index).is_err();
        present_mapping = Ros2Mapping {
            objects: (mapping.objects.iter().enumerate())
                .filter(|(index, _)| present(index))
                .map(|(_, object)| object.clone())
                .collect(),
            robot: mapping.robot.clone(),
        };
        present_robot = robot.map(|robot| {
            let mut robot = robot.clone();
            if let Some(grasp) = &mut robot.grasp {
                grasp.holdable = (grasp.holdable.iter().enumerate())
                    .filter(|(index, _)| present(index))
                    .map(|(_, holdable)| *holdable)
                    .collect();
            }
            robot
        });
        (&present_mapping, present_robot.as_ref())
    };
    let (header, joints) = header_and_joints(domain, mapping, robot);
    let mut reader = BagReader::new(file, mapping, robot, &recording, held_messages, joints);
    let mut steps: Vec<Step> = Vec::new();
    for message in &recording.tf {
        if let Some(step) = reader.step(message)? {
            steps.push(step);
        }
    }
    if steps.is_empty() {
        return Err(reader.missing_frame());
    }
    // Step times start at zero, as in a native file.
    let start = steps[0].time_nanoseconds;
    for step in &mut steps {
        step.time_nanoseconds -= start;
    }
    Ok(Ros2Bag { trajectory: Trajectory { header, steps }, absent })
}

/// What the bags of one `files … as ros2 { … }` source lacked: how many were read, and how many
/// of them had no transform for each mapped object's frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BagTally {
    /// The bags read.
    pub bags: usize,
    /// Per mapped object, in the mapping's order: how many bags lacked it.
    pub absent: Vec<usize>,
}

impl BagTally {
    /// No bag read yet of a source with `mapping`.
    pub fn new(mapping: &Ros2Mapping) -> Self {
        BagTally { bags: 0, absent: vec![0; mapping.objects.len()] }
    }

    /// Counts one bag read with the mapping, which lacked the objects `absent`
    /// ([`Ros2Bag::absent`]).
    pub fn add(&mut self, absent: &[usize]) {
        self.bags += 1;
        for &index in absent {
            if let Some(count) = self.absent.get_mut(index) {
                *count += 1;
            }
        }
    }

    /// Refuses a mapped object that every bag read lacks (the first in the mapping's order),
    /// once at least one bag was read; `pattern` is the source's, for the message.
    pub fn check(&self, pattern: &str, mapping: &Ros2Mapping) -> Result<(), Ros2Error> {
        let in_no_bag = (mapping.objects.iter().zip(&self.absent))
            .find(|(_, absent)| self.bags > 0 && **absent == self.bags);
        match in_no_bag {
            Some((object, _)) => Err(Ros2Error::FrameInNoBag {
                pattern: pattern.to_string(),
                object: object.name.clone(),
                frame: object.frame.clone(),
                bags: self.bags,
            }),
            None => Ok(()),
        }
    }

    /// The mapped objects some bags lacked, with how many, in the mapping's order.
    pub fn absences<'m>(&self, mapping: &'m Ros2Mapping) -> Vec<(&'m FrameObject, usize)> {
        (mapping.objects.iter().zip(&self.absent))
            .filter(|(_, absent)| **absent > 0)
            .map(|(object, absent)| (object, *absent))
            .collect()
    }
}

/// The messages of the held topic, after checking that the bag has `/tf` and that topic.
fn held_messages<'r>(
    recording: &'r StandardRecording,
    file: &str,
    held_topic: Option<&str>,
) -> Result<&'r [(u64, String)], Ros2Error> {
    if recording.tf.is_empty() {
        return Err(Ros2Error::NoTf { file: file.to_string() });
    }
    if let Some(topic) = held_topic.filter(|topic| !recording.topics.contains(*topic)) {
        let topics: Vec<&str> = recording.topics.iter().map(String::as_str).collect();
        return Err(Ros2Error::NoHeldTopic {
            file: file.to_string(),
            topic: topic.to_string(),
            topics: topics.join(", "),
        });
    }
    Ok(held_topic.map(|topic| recording.strings[topic].as_slice()).unwrap_or(&[]))
}

/// The trajectory's header, and the robot's joints with one coordinate: (URDF name, coordinate
/// index).
fn header_and_joints<'a>(
    domain: &str,
    mapping: &Ros2Mapping,
    robot: Option<&MappedRobot<'a>>,
) -> (TrajectoryHeader, Vec<(&'a str, usize)>) {
    let mut header = TrajectoryHeader {
        domain: domain.to_string(),
        seed: 0,
        provenance: [("source".to_string(), "ros2".to_string())].into(),
        bodies: mapping
            .objects
            .iter()
            .map(|object| BodyDescription {
                name: object.name.clone(),
                type_name: object.type_name.clone(),
            })
            .collect(),
        robots: vec![],
    };
    let mut joints: Vec<(&str, usize)> = Vec::new();
    if let (Some(mapped), Some(robot)) = (&mapping.robot, robot) {
        header.robots.push(RobotDescription {
            name: mapped.robot.clone(),
            coordinates: robot.model.coordinate_names().to_vec(),
            grippers: robot.gripper.iter().cloned().collect(),
        });
        for link in 0..robot.model.link_count() {
            let Some(joint) = robot.model.parent_joint_name(link) else { continue };
            if let Ok([coordinate]) = robot.model.joint_coordinates(joint).as_deref() {
                joints.push((joint, *coordinate));
            }
        }
    }
    (header, joints)
}

/// Each mapped frame's pose in the root of its tree, and that root.
type FramePoses<'a> = Vec<(Isometry3<f64>, &'a str)>;

/// A bag read `/tf` message by `/tf` message: the frame tree, the latest joint values and held
/// frame, and what the checks between steps remember.
struct BagReader<'a> {
    file: &'a str,
    mapping: &'a Ros2Mapping,
    robot: Option<&'a MappedRobot<'a>>,
    recording: &'a StandardRecording,
    held_messages: &'a [(u64, String)],
    /// The robot's joints with one coordinate: (URDF name, coordinate index).
    joints: Vec<(&'a str, usize)>,
    /// The mapped objects' frames, then the robot's base frame.
    frames: Vec<&'a str>,
    frame_index: BTreeMap<&'a str, usize>,
    /// Each joint's name with the robot's prefix, made once: the lookup runs for every joint at
    /// every step.
    prefixed: BTreeMap<&'a str, String>,
    /// Frame → (parent, pose in the parent, stamp), updated message by message.
    tree: BTreeMap<&'a str, (&'a str, Isometry3<f64>, u64)>,
    previous_log_time: Option<u64>,
    root: Option<String>,
    next_joint_state: usize,
    next_held: usize,
    joint_values: BTreeMap<&'a str, f64>,
    held: Option<usize>,
    /// Whether the grasp joint was closed at the previous step (none before the first).
    was_closed: Option<bool>,
    previous_positions: Vec<nalgebra::Vector3<f64>>,
}

impl<'a> BagReader<'a> {
    fn new(
        file: &'a str,
        mapping: &'a Ros2Mapping,
        robot: Option<&'a MappedRobot<'a>>,
        recording: &'a StandardRecording,
        held_messages: &'a [(u64, String)],
        joints: Vec<(&'a str, usize)>,
    ) -> BagReader<'a> {
        let mut tree = BTreeMap::new();
        for message in &recording.tf_static {
            for transform in &message.transforms {
                tree.insert(
                    transform.frame.as_str(),
                    (transform.parent.as_str(), transform.pose, 0),
                );
            }
        }
        let mut frames: Vec<&str> =
            mapping.objects.iter().map(|object| object.frame.as_str()).collect();
        if let Some(robot) = &mapping.robot {
            frames.push(&robot.base_frame);
        }
        // With several robots in one bag, each robot's frames and joints carry its prefix, as
        // lamp writes them (`fetch/base_link`, `fetch/shoulder_pan_joint`): a robot frame
        // `P/ROOT`, where ROOT is the robot's root link, reads its joints as `P/JOINT`, else by
        // their bare names.
        let prefix = match (&mapping.robot, robot) {
            (Some(mapped), Some(robot)) => mapped
                .base_frame
                .strip_suffix(robot.model.link_name(0))
                .filter(|prefix| prefix.ends_with('/'))
                .unwrap_or(""),
            _ => "",
        };
        let grasp_joint =
            robot.and_then(|robot| robot.grasp.as_ref()).map(|g| g.joint.joint.as_str());
        let prefixed = joints
            .iter()
            .map(|(joint, _)| *joint)
            .chain(grasp_joint)
            .map(|joint| (joint, format!("{prefix}{joint}")))
            .collect();
        let frame_index = mapping
            .objects
            .iter()
            .enumerate()
            .map(|(index, o)| (o.frame.as_str(), index))
            .collect();
        BagReader {
            file,
            mapping,
            robot,
            recording,
            held_messages,
            joints,
            frames,
            frame_index,
            prefixed,
            tree,
            previous_log_time: None,
            root: None,
            next_joint_state: 0,
            next_held: 0,
            joint_values: BTreeMap::new(),
            held: None,
            was_closed: None,
            previous_positions: Vec::new(),
        }
    }

    /// The step at `message`, or none while a mapped frame is still unknown.
    fn step(&mut self, message: &'a BagTfMessage) -> Result<Option<Step>, Ros2Error> {
        let time = message.log_time;
        self.update_tree(message)?;
        self.catch_up(time)?;
        let Some(poses) = self.mapped_poses(time)? else { return Ok(None) };
        self.check_roots(&poses)?;
        self.check_jumps(&poses, time)?;
        let body_poses: Vec<Isometry3<f64>> =
            poses.iter().take(self.mapping.objects.len()).map(|(pose, _)| *pose).collect();
        let robots = self.robot_states(&poses, &body_poses, time)?;
        Ok(Some(Step { time_nanoseconds: time, body_poses, robots }))
    }

    /// Takes in `message`'s transforms, refusing log times or stamps that go back.
    fn update_tree(&mut self, message: &'a BagTfMessage) -> Result<(), Ros2Error> {
        let time = message.log_time;
        if let Some(previous) = self.previous_log_time.filter(|previous| time < *previous) {
            return Err(Ros2Error::Timing {
                file: self.file.to_string(),
                reason: format!("a `/tf` message at {time} ns follows one at {previous} ns"),
            });
        }
        self.previous_log_time = Some(time);
        for transform in &message.transforms {
            if let Some((_, _, stamp)) = self.tree.get(transform.frame.as_str())
                && transform.stamp_nanoseconds < *stamp
            {
                return Err(Ros2Error::Timing {
                    file: self.file.to_string(),
                    reason: format!(
                        "the stamp of frame `{}` goes back from {stamp} ns to {} ns",
                        transform.frame, transform.stamp_nanoseconds
                    ),
                });
            }
            self.tree.insert(
                &transform.frame,
                (&transform.parent, transform.pose, transform.stamp_nanoseconds),
            );
        }
        Ok(())
    }

    /// Takes in the joint states and held frames logged up to `time`.
    fn catch_up(&mut self, time: u64) -> Result<(), Ros2Error> {
        let recording = self.recording;
        while let Some(state) =
            recording.joint_states.get(self.next_joint_state).filter(|s| s.log_time <= time)
        {
            for (name, value) in state.names.iter().zip(&state.positions) {
                self.joint_values.insert(name, *value);
            }
            self.next_joint_state += 1;
        }
        while let Some((_, text)) =
            self.held_messages.get(self.next_held).filter(|(t, _)| *t <= time)
        {
            self.held = match text.as_str() {
                "" => None,
                frame => {
                    Some(*self.frame_index.get(frame).ok_or_else(|| Ros2Error::UnknownHeld {
                        file: self.file.to_string(),
                        frame: frame.to_string(),
                        time_nanoseconds: time,
                    })?)
                }
            };
            self.next_held += 1;
        }
        Ok(())
    }

    /// Every mapped frame's pose in the root of its tree, with that root; none while a frame is
    /// still unknown (steps start once every mapped frame is known).
    fn mapped_poses(&self, time: u64) -> Result<Option<FramePoses<'a>>, Ros2Error> {
        let mut poses = Vec::with_capacity(self.frames.len());
        for frame in &self.frames {
            match world_pose(&self.tree, frame) {
                Ok((pose, frame_root)) => poses.push((pose, frame_root)),
                Err(TreeGap::Unknown) => return Ok(None),
                Err(TreeGap::Cycle(cycle)) => {
                    return Err(Ros2Error::TfCycle {
                        file: self.file.to_string(),
                        frame: frame.to_string(),
                        time_nanoseconds: time,
                        cycle: cycle
                            .iter()
                            .chain(cycle.first())
                            .map(|frame| format!("`{frame}`"))
                            .collect::<Vec<_>>()
                            .join(" → "),
                    });
                }
                Err(TreeGap::TooDeep(deepest)) => {
                    return Err(Ros2Error::TfTooDeep {
                        file: self.file.to_string(),
                        frame: frame.to_string(),
                        time_nanoseconds: time,
                        max_depth: MAX_TREE_DEPTH,
                        deepest: deepest.to_string(),
                    });
                }
            }
        }
        Ok(Some(poses))
    }

    /// Refuses mapped frames in different trees.
    fn check_roots(&mut self, poses: &[(Isometry3<f64>, &str)]) -> Result<(), Ros2Error> {
        for (frame, (_, frame_root)) in self.frames.iter().zip(poses) {
            let expected = self.root.get_or_insert_with(|| frame_root.to_string());
            if frame_root != expected {
                return Err(Ros2Error::MissingFrame {
                    file: self.file.to_string(),
                    frame: frame.to_string(),
                    reason: format!(
                        "is in the tree of `{frame_root}`, not in that of `{expected}` with the other frames"
                    ),
                });
            }
        }
        Ok(())
    }

    /// Refuses a mapped frame that moves more than [`MAX_FRAME_JUMP`] since the last step.
    fn check_jumps(
        &mut self,
        poses: &[(Isometry3<f64>, &str)],
        time: u64,
    ) -> Result<(), Ros2Error> {
        let positions: Vec<_> = poses.iter().map(|(pose, _)| pose.translation.vector).collect();
        for ((frame, position), before) in
            self.frames.iter().zip(&positions).zip(&self.previous_positions)
        {
            let distance = (position - before).norm();
            if distance > MAX_FRAME_JUMP {
                return Err(Ros2Error::Jump {
                    file: self.file.to_string(),
                    frame: frame.to_string(),
                    time_nanoseconds: time,
                    distance,
                });
            }
        }
        self.previous_positions = positions;
        Ok(())
    }

    /// The robot's state at this step (none without a robot): its configuration from the base
    /// frame and the joint values, and what it holds.
    fn robot_states(
        &mut self,
        poses: &[(Isometry3<f64>, &str)],
        body_poses: &[Isometry3<f64>],
        time: u64,
    ) -> Result<Vec<RobotState>, Ros2Error> {
        let (Some(mapped), Some(robot)) = (&self.mapping.robot, self.robot) else {
            return Ok(Vec::new());
        };
        let missing = |joint: &str| Ros2Error::MissingJoint {
            file: self.file.to_string(),
            robot: mapped.robot.clone(),
            joint: joint.to_string(),
        };
        let mut q = robot.model.neutral_configuration();
        let base = poses[self.mapping.objects.len()].0;
        robot.model.mount().write_coordinates(&base, &mut q);
        for (joint, coordinate) in &self.joints {
            let value = self.joint_value(joint).ok_or_else(|| missing(joint))?;
            let (lower, upper) = recordable_range(&robot.model.coordinates()[*coordinate]);
            if !(lower - JOINT_LIMIT_SLACK..=upper + JOINT_LIMIT_SLACK).contains(&value) {
                return Err(Ros2Error::JointOutOfRange {
                    file: self.file.to_string(),
                    robot: mapped.robot.clone(),
                    joint: joint.to_string(),
                    value,
                    lower,
                    upper,
                    time_nanoseconds: time,
                });
            }
            q[*coordinate] = value;
        }
        if let Some(grasp) = &robot.grasp {
            let joint = grasp.joint.joint.as_str();
            let value = self.joint_value(joint).ok_or_else(|| missing(joint))?;
            let closed = value < grasp.joint.closed_below;
            if !closed {
                self.held = None;
            } else if self.was_closed != Some(true) {
                self.held = grasped_object(grasp, robot.model, &q, body_poses);
            }
            self.was_closed = Some(closed);
        }
        let held = robot.gripper.iter().map(|_| self.held).collect();
        Ok(vec![RobotState { positions: q, held }])
    }

    /// A joint's latest value, under the robot's prefix or else its bare name.
    fn joint_value(&self, joint: &str) -> Option<f64> {
        let named = self.prefixed.get(joint).and_then(|name| self.joint_values.get(name.as_str()));
        named.or_else(|| self.joint_values.get(joint)).copied()
    }

    /// The error of a bag in which the mapped frames are never all known: the first frame that
    /// is still missing.
    fn missing_frame(&self) -> Ros2Error {
        let missing = self
            .frames
            .iter()
            .find(|frame| world_pose(&self.tree, frame).is_err())
            .map_or_else(String::new, |frame| frame.to_string());
        Ros2Error::MissingFrame {
            file: self.file.to_string(),
            frame: missing,
            reason: "never appears on `/tf` or `/tf_static`".to_string(),
        }
    }
}

/// The movable object whose origin is nearest the gripper link at configuration `q`, within the
/// grab distance; the first in mapping order on a tie.
fn grasped_object(
    grasp: &JointGrasp,
    model: &Robot,
    q: &[f64],
    body_poses: &[Isometry3<f64>],
) -> Option<usize> {
    let gripper = model.link_pose(q, grasp.gripper_link).translation.vector;
    let (low, high) = grasp.grab_distance;
    let mut nearest: Option<(usize, f64)> = None;
    for (index, (pose, holdable)) in body_poses.iter().zip(&grasp.holdable).enumerate() {
        let distance = (pose.translation.vector - gripper).norm();
        if *holdable
            && (low..=high).contains(&distance)
            && nearest.is_none_or(|(_, best)| distance < best)
        {
            nearest = Some((index, distance));
        }
    }
    nearest.map(|(index, _)| index)
}

/// Why a frame has no pose in the root of its tree.
#[derive(Debug, PartialEq, Eq)]
enum TreeGap<'a> {
    /// The frame has no transform yet.
    Unknown,
    /// Its chain of parents comes back to a frame it passed: these frames, in chain order.
    Cycle(Vec<&'a str>),
    /// Its chain is longer than [`MAX_TREE_DEPTH`]; the frame the chain had reached.
    TooDeep(&'a str),
}

/// The pose of `frame` in the root of its tree and that root's name, or why it has none.
fn world_pose<'a>(
    tree: &BTreeMap<&'a str, (&'a str, Isometry3<f64>, u64)>,
    frame: &'a str,
) -> Result<(Isometry3<f64>, &'a str), TreeGap<'a>> {
    let (mut parent, mut pose, _) = *tree.get(frame).ok_or(TreeGap::Unknown)?;
    for _ in 0..MAX_TREE_DEPTH {
        match tree.get(parent) {
            Some((grandparent, local, _)) => {
                pose = local * pose;
                parent = grandparent;
            }
            None => return Ok((pose, parent)),
        }
    }
    Err(chain_gap(tree, frame))
}

/// Why the chain of `frame`, known to pass [`MAX_TREE_DEPTH`] transforms, has no root: the cycle
/// it runs into, or the frame it had reached at the limit. Walked only once a chain is too long,
/// so that the common case costs no bookkeeping.
fn chain_gap<'a>(
    tree: &BTreeMap<&'a str, (&'a str, Isometry3<f64>, u64)>,
    frame: &'a str,
) -> TreeGap<'a> {
    let mut chain: Vec<&'a str> = vec![frame];
    let mut position: BTreeMap<&'a str, usize> = BTreeMap::from([(frame, 0)]);
    let mut current = frame;
    for _ in 0..MAX_TREE_DEPTH {
        let Some((parent, _, _)) = tree.get(current) else { break };
        if let Some(&start) = position.get(parent) {
            return TreeGap::Cycle(chain.split_off(start));
        }
        position.insert(parent, chain.len());
        chain.push(parent);
        current = parent;
    }
    TreeGap::TooDeep(current)
}
