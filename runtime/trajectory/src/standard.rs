//! The standard ROS 2 and Foxglove channels a file may carry beside `/lamp/world`, so that
//! Foxglove's 3D panel and RViz show the scene: `/tf`, `/tf_static`, `/joint_states`,
//! `/robot_description`, object primitives as a `foxglove.SceneUpdate` and the plan step.
//!
//! The values are supplied by the caller (this crate knows no kinematics): the frames' world
//! poses per step, the joint values, the robots' URDF text and the objects' shapes. `/lamp/world`
//! stays the source of truth; the reader ignores these channels. `docs/formats.md` specifies
//! them.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use nalgebra::Isometry3;

use crate::cdr::CdrWriter;
use crate::codec::{MAXIMUM_TIME_NANOSECONDS, StepProblem, check_pose, split_time};
use crate::schema::{header_dependencies, quaternion_dependency, ros_dependency, xyz_dependency};

/// The topic of the per-step transforms (`tf2_msgs/msg/TFMessage`).
pub const TF_TOPIC: &str = "/tf";
/// The topic of the fixed transforms, written once at time zero.
pub const TF_STATIC_TOPIC: &str = "/tf_static";
/// The topic of the per-step joint values (`sensor_msgs/msg/JointState`).
pub const JOINT_STATES_TOPIC: &str = "/joint_states";
/// The topic of a file's only robot's URDF text (`std_msgs/msg/String`), written once at time
/// zero; with several robots each has `/<robot>/robot_description`.
pub const ROBOT_DESCRIPTION_TOPIC: &str = "/robot_description";
/// The topic of the objects' primitives (`foxglove.SceneUpdate` in JSON), written once.
pub const SCENE_TOPIC: &str = "/lamp/scene";
/// The topic of the plan step being executed (`std_msgs/msg/String`), written when it changes.
pub const STEP_LABEL_TOPIC: &str = "/lamp/step";
/// The topic of a solution's straight last approaches into contact (`std_msgs/msg/String`, a
/// JSON object each), written at the step where each begins.
pub const APPROACH_TOPIC: &str = "/lamp/approach";
/// The topic of the frame a file's only robot's gripper holds (`std_msgs/msg/String`, empty when
/// it holds nothing), written at the first step and when it changes; with several robots each
/// has `/<robot>/lamp/held`.
pub const HELD_TOPIC: &str = "/lamp/held";

/// The topic of a file's only robot's joint motions (`trajectory_msgs/msg/JointTrajectory`), one
/// message at the start of every motion between two grasp changes; with several robots each has
/// `/<robot>/lamp/joint_trajectory`.
pub const JOINT_TRAJECTORY_TOPIC: &str = "/lamp/joint_trajectory";
/// The topic of a file's only robot's mount motions (a mobile base's or a free-flying gripper's
/// coordinates, as a `trajectory_msgs/msg/JointTrajectory`); with several robots each has
/// `/<robot>/lamp/base_trajectory`.
pub const BASE_TRAJECTORY_TOPIC: &str = "/lamp/base_trajectory";
/// The topic of a file's only robot's gripper commands (`control_msgs/msg/GripperCommand`), one
/// at every grasp and every release; with several robots each has
/// `/<robot>/lamp/gripper_command`.
pub const GRIPPER_COMMAND_TOPIC: &str = "/lamp/gripper_command";

/// The ROS 2 type of `/tf` and `/tf_static`.
pub const TF_SCHEMA_NAME: &str = "tf2_msgs/msg/TFMessage";
/// The ROS 2 type of `/joint_states`.
pub const JOINT_STATE_SCHEMA_NAME: &str = "sensor_msgs/msg/JointState";
/// The ROS 2 type of the joint and base trajectory topics.
pub const JOINT_TRAJECTORY_SCHEMA_NAME: &str = "trajectory_msgs/msg/JointTrajectory";
/// The ROS 2 type of the gripper command topics: the goal of a `control_msgs/action/GripperCommand`.
pub const GRIPPER_COMMAND_SCHEMA_NAME: &str = "control_msgs/msg/GripperCommand";
/// The ROS 2 type of `/robot_description` and `/lamp/step`.
pub const STRING_SCHEMA_NAME: &str = "std_msgs/msg/String";
/// The Foxglove schema of `/lamp/scene`, which Foxglove recognises by this name.
pub const SCENE_SCHEMA_NAME: &str = "foxglove.SceneUpdate";
/// The MCAP schema encoding of `/lamp/scene`.
pub const SCENE_SCHEMA_ENCODING: &str = "jsonschema";
/// The MCAP message encoding of `/lamp/scene`.
pub const SCENE_MESSAGE_ENCODING: &str = "json";

/// `tf2_msgs/msg/TFMessage` with its dependencies, in the form rosbag2 writes.
pub const TF_SCHEMA: &str = concat!(
    "geometry_msgs/TransformStamped[] transforms\n",
    ros_dependency!(
        "geometry_msgs/TransformStamped",
        "std_msgs/Header header\nstring child_frame_id\nTransform transform\n"
    ),
    header_dependencies!(),
    ros_dependency!("geometry_msgs/Transform", "Vector3 translation\nQuaternion rotation\n"),
    xyz_dependency!("geometry_msgs/Vector3"),
    quaternion_dependency!(),
);

/// `sensor_msgs/msg/JointState` with its dependencies, in the form rosbag2 writes.
pub const JOINT_STATE_SCHEMA: &str = concat!(
    "std_msgs/Header header\n",
    "string[] name\n",
    "float64[] position\n",
    "float64[] velocity\n",
    "float64[] effort\n",
    header_dependencies!(),
);

/// `trajectory_msgs/msg/JointTrajectory` with its dependencies, in the form rosbag2 writes.
pub const JOINT_TRAJECTORY_SCHEMA: &str = concat!(
    "std_msgs/Header header\n",
    "string[] joint_names\n",
    "JointTrajectoryPoint[] points\n",
    header_dependencies!(),
    ros_dependency!(
        "trajectory_msgs/JointTrajectoryPoint",
        "float64[] positions\nfloat64[] velocities\nfloat64[] accelerations\nfloat64[] effort\n\
         builtin_interfaces/Duration time_from_start\n"
    ),
    ros_dependency!("builtin_interfaces/Duration", "int32 sec\nuint32 nanosec\n"),
);

/// `control_msgs/msg/GripperCommand`.
pub const GRIPPER_COMMAND_SCHEMA: &str = "float64 position\nfloat64 max_effort\n";

/// `std_msgs/msg/String`.
pub const STRING_SCHEMA: &str = "string data\n";

/// The JSON schema of the `foxglove.SceneUpdate` messages lamp writes: the published schema's
/// fields that lamp fills (entities with cubes, spheres, cylinders and triangle lists), so that
/// the schema record stays small; every message also satisfies Foxglove's full schema.
pub const SCENE_SCHEMA: &str = r##"{"title":"foxglove.SceneUpdate","type":"object","$defs":{"time":{"type":"object","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer","minimum":0,"maximum":999999999}},"required":["sec","nsec"]},"vector3":{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]},"pose":{"type":"object","properties":{"position":{"$ref":"#/$defs/vector3"},"orientation":{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},"w":{"type":"number"}},"required":["x","y","z","w"]}},"required":["position","orientation"]},"color":{"type":"object","properties":{"r":{"type":"number"},"g":{"type":"number"},"b":{"type":"number"},"a":{"type":"number"}},"required":["r","g","b","a"]},"sized":{"type":"object","properties":{"pose":{"$ref":"#/$defs/pose"},"size":{"$ref":"#/$defs/vector3"},"color":{"$ref":"#/$defs/color"},"bottom_scale":{"type":"number"},"top_scale":{"type":"number"}},"required":["pose","size","color"]},"triangles":{"type":"object","properties":{"pose":{"$ref":"#/$defs/pose"},"points":{"type":"array","items":{"$ref":"#/$defs/vector3"}},"color":{"$ref":"#/$defs/color"},"colors":{"type":"array"},"indices":{"type":"array","items":{"type":"integer","minimum":0}}},"required":["pose","points","color","colors","indices"]}},"properties":{"deletions":{"type":"array"},"entities":{"type":"array","items":{"type":"object","properties":{"timestamp":{"$ref":"#/$defs/time"},"frame_id":{"type":"string"},"id":{"type":"string"},"lifetime":{"$ref":"#/$defs/time"},"frame_locked":{"type":"boolean"},"metadata":{"type":"array","items":{"type":"object","properties":{"key":{"type":"string"},"value":{"type":"string"}},"required":["key","value"]}},"arrows":{"type":"array"},"cubes":{"type":"array","items":{"$ref":"#/$defs/sized"}},"spheres":{"type":"array","items":{"$ref":"#/$defs/sized"}},"cylinders":{"type":"array","items":{"$ref":"#/$defs/sized"}},"lines":{"type":"array"},"triangles":{"type":"array","items":{"$ref":"#/$defs/triangles"}},"texts":{"type":"array"},"models":{"type":"array"}},"required":["timestamp","frame_id","id","lifetime","frame_locked","metadata","arrows","cubes","spheres","cylinders","lines","triangles","texts","models"]}}},"required":["deletions","entities"]}"##;

/// The rosbag2 `offered_qos_profiles` of the latched channels (`/tf_static`,
/// `/robot_description`): reliable and transient-local, so that `ros2 bag play` latches them
/// as `robot_state_publisher` does.
pub const LATCHED_QOS: &str = "- history: 3\n  depth: 0\n  reliability: 1\n  durability: 1\n  deadline:\n    sec: 2147483647\n    nsec: 4294967295\n  lifespan:\n    sec: 2147483647\n    nsec: 4294967295\n  liveliness: 1\n  liveliness_lease_duration:\n    sec: 2147483647\n    nsec: 4294967295\n  avoid_ros_namespace_conventions: false\n";

/// The MCAP channel metadata key rosbag2 reads QoS profiles from.
pub const QOS_METADATA_KEY: &str = "offered_qos_profiles";

/// A robot's description for viewers: the topic its URDF is published on and the URDF text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RobotModelText {
    /// `/robot_description`, or `/<robot>/robot_description` when a file has several robots.
    pub topic: String,
    /// The URDF file's text, unchanged.
    pub urdf: String,
}

/// A shape of an object, placed in the object's tf frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Primitive {
    /// A box of this full size, centred on its pose.
    Cube { pose: Isometry3<f64>, size: [f64; 3] },
    /// A sphere of this radius, centred on its pose.
    Sphere { pose: Isometry3<f64>, radius: f64 },
    /// A cylinder along its pose's z axis, centred on its pose.
    Cylinder { pose: Isometry3<f64>, radius: f64, height: f64 },
    /// A triangle mesh: three points per triangle, in the frame of its pose.
    Triangles { pose: Isometry3<f64>, points: Vec<[f64; 3]> },
}

/// An object drawn in the 3D panel: its primitives move with its tf frame.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneObject {
    /// The entity id, the object's name.
    pub id: String,
    /// The tf frame the primitives are placed in.
    pub frame: String,
    /// The object's type, shown as the entity's `type` metadata.
    pub type_name: String,
    /// Red, green, blue and alpha in 0..=1.
    pub color: [f64; 4],
    pub primitives: Vec<Primitive>,
}

/// A frame on `/tf`: its name and the frame its pose is given in.
///
/// A frame is written when its pose changed since it was last written, and at least once a
/// second ([`TF_REFRESH_NANOSECONDS`]); a derived frame at most every
/// [`DERIVED_FRAME_PERIOD_NANOSECONDS`] (and at the last step).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TfFrame {
    /// The world frame or another frame of the file, for example a robot link's parent link.
    pub parent: String,
    pub frame: String,
    /// Whether the frame's pose follows from `/joint_states` and the robot description (a robot
    /// link below its root), as `robot_state_publisher` computes it; false for a frame that
    /// carries information of its own (a body, a robot's root).
    pub derived: bool,
}

/// Every `/tf` frame is written at least this often (one second of log time), even when it
/// did not move: tf2 (RViz, `ros2 bag play`) drops a frame's history after ten seconds, and a
/// viewer that starts playing in the middle of a file has every frame within a second.
pub const TF_REFRESH_NANOSECONDS: u64 = 1_000_000_000;

/// A derived frame that moves is written at most this often (50 Hz): its pose follows from the
/// joint values, which are written at every change; viewers interpolate between transforms as
/// they do for `robot_state_publisher`, which publishes at 20 Hz by default. Without this limit
/// a moving arm's links were most of a file's bytes.
pub const DERIVED_FRAME_PERIOD_NANOSECONDS: u64 = 20_000_000;

/// A fixed frame on `/tf_static`: its name, its parent and its pose in the parent's frame.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticFrame {
    pub parent: String,
    pub frame: String,
    pub pose: Isometry3<f64>,
}

/// A topic of joint trajectories (`trajectory_msgs/msg/JointTrajectory`): its name and the joints
/// every message on it moves, in the order of each point's values.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TrajectoryTopic {
    pub topic: String,
    pub joints: Vec<String>,
}

/// One point of a joint trajectory: where the joints are, how fast they move, and when, counted
/// from the trajectory's start.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryPoint {
    /// One value per joint of the topic (metres, radians).
    pub positions: Vec<f64>,
    /// One value per joint of the topic (metres or radians per second).
    pub velocities: Vec<f64>,
    /// Time from the trajectory's start, written as a `builtin_interfaces/Duration`.
    pub time_from_start_nanoseconds: u64,
}

/// A joint trajectory written at a step: the index of its topic in
/// [`StandardChannels::trajectory_topics`] and its points. Its header's stamp is zero ("start
/// when received", what a `joint_trajectory_controller` reads it as) and its frame empty.
#[derive(Debug, Clone, PartialEq)]
pub struct JointTrajectoryMessage {
    pub topic: usize,
    pub points: Vec<TrajectoryPoint>,
}

/// A gripper command written at a step: the index of its topic in
/// [`StandardChannels::gripper_topics`], the target position and the most effort to use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GripperCommand {
    pub topic: usize,
    pub position: f64,
    pub max_effort: f64,
}

/// The standard channels of a file: what is written once, and the layout of each step's values
/// ([`StandardStep`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StandardChannels {
    /// The fixed frame at the root of the tf tree, for example `world`.
    pub world_frame: String,
    /// The frames on `/tf`, in the order each [`StandardStep`] stores their poses.
    pub frames: Vec<TfFrame>,
    /// The frames on `/tf_static`, written once at time zero; none: no `/tf_static` channel.
    pub static_frames: Vec<StaticFrame>,
    /// The joints on `/joint_states`, in the order each step stores their values; none: no
    /// `/joint_states` channel.
    pub joints: Vec<String>,
    /// One description per robot, written once at time zero.
    pub robots: Vec<RobotModelText>,
    /// The objects on `/lamp/scene`, written once at time zero; none: no scene channel.
    pub objects: Vec<SceneObject>,
    /// Whether steps carry plan-step labels (`/lamp/step`).
    pub step_labels: bool,
    /// Whether steps carry the approaches into contact that begin there (`/lamp/approach`).
    pub approaches: bool,
    /// One topic per gripper, on which the frame it holds is written ([`HELD_TOPIC`]).
    pub held_topics: Vec<String>,
    /// The topics of joint trajectories a controller can execute ([`JOINT_TRAJECTORY_TOPIC`],
    /// [`BASE_TRAJECTORY_TOPIC`]); none in a demonstration.
    pub trajectory_topics: Vec<TrajectoryTopic>,
    /// The topics of gripper commands ([`GRIPPER_COMMAND_TOPIC`]); none in a demonstration.
    pub gripper_topics: Vec<String>,
}

/// The standard channels' values at one step.
#[derive(Debug, Clone, PartialEq)]
pub struct StandardStep {
    /// Pose of each of [`StandardChannels::frames`] in its parent's frame, in that order.
    pub frame_poses: Vec<Isometry3<f64>>,
    /// Value of each of [`StandardChannels::joints`], in that order (metres, radians).
    pub joint_positions: Vec<f64>,
    /// The plan step being executed, for example `(pick gripper can_0)`; written on
    /// `/lamp/step` whenever it differs from the previous step's.
    pub label: Option<String>,
    /// The approach into contact that begins at this step, written on `/lamp/approach` as it
    /// is given.
    pub approach: Option<String>,
    /// Per held topic, the frame the gripper holds, empty when none; written at the first step
    /// and whenever it differs from the previous step's.
    pub held: Vec<String>,
    /// The joint trajectories that start at this step.
    pub trajectories: Vec<JointTrajectoryMessage>,
    /// The gripper commands sent at this step.
    pub gripper_commands: Vec<GripperCommand>,
}

impl StandardChannels {
    /// The channels of a file with nothing on them but the root frame `world_frame`: the start
    /// from which a caller sets the channels it writes (`..StandardChannels::rooted_at("world")`).
    pub fn rooted_at(world_frame: impl Into<String>) -> Self {
        StandardChannels {
            world_frame: world_frame.into(),
            frames: Vec::new(),
            static_frames: Vec::new(),
            joints: Vec::new(),
            robots: Vec::new(),
            objects: Vec::new(),
            step_labels: false,
            approaches: false,
            held_topics: Vec::new(),
            trajectory_topics: Vec::new(),
            gripper_topics: Vec::new(),
        }
    }

    /// Checks that the channels can be written: frame and joint names are non-empty and unique,
    /// every parent and every object's frame is a frame of the file, and every number is finite.
    pub(crate) fn check(&self) -> Result<(), String> {
        let mut frames = BTreeSet::new();
        check_frame_name(&self.world_frame)?;
        frames.insert(self.world_frame.as_str());
        let dynamic = self.frames.iter().map(|frame| (&frame.parent, &frame.frame));
        let fixed = self.static_frames.iter().map(|frame| (&frame.parent, &frame.frame));
        let all: Vec<(&String, &String)> = dynamic.chain(fixed).collect();
        for (_, frame) in &all {
            check_frame_name(frame)?;
            if !frames.insert(frame.as_str()) {
                return Err(format!("tf frame `{frame}` is listed twice"));
            }
        }
        if let Some((parent, frame)) =
            all.iter().find(|(parent, _)| !frames.contains(parent.as_str()))
        {
            return Err(format!(
                "tf frame `{frame}` has parent `{parent}`, which is not a frame of the file"
            ));
        }
        for frame in &self.static_frames {
            check_pose(&frame.pose)
                .map_err(|reason| format!("frame `{}`: {reason}", frame.frame))?;
        }
        let mut joints = BTreeSet::new();
        for joint in &self.joints {
            if joint.is_empty() || !joints.insert(joint.as_str()) {
                return Err(format!("joint `{joint}` is empty or listed twice"));
            }
        }
        let mut topics = BTreeSet::new();
        let held = self.held_topics.iter();
        let trajectories = self.trajectory_topics.iter().map(|topic| &topic.topic);
        let topic_names = self.robots.iter().map(|robot| &robot.topic).chain(held);
        for topic in topic_names.chain(trajectories).chain(&self.gripper_topics) {
            if !topic.starts_with('/') || !topics.insert(topic.as_str()) {
                return Err(format!("topic `{topic}` does not start with `/` or is listed twice"));
            }
        }
        for topic in &self.trajectory_topics {
            let mut joints = BTreeSet::new();
            if topic.joints.is_empty() {
                return Err(format!("trajectory topic `{}` has no joints", topic.topic));
            }
            for joint in &topic.joints {
                if joint.is_empty() || !joints.insert(joint.as_str()) {
                    return Err(format!(
                        "joint `{joint}` of trajectory topic `{}` is empty or listed twice",
                        topic.topic
                    ));
                }
            }
        }
        for object in &self.objects {
            if !frames.contains(object.frame.as_str()) {
                return Err(format!(
                    "object `{}` is placed in frame `{}`, which is not a tf frame of the file",
                    object.id, object.frame
                ));
            }
            let mut numbers = object.color.to_vec();
            for primitive in &object.primitives {
                let (pose, sizes) = match primitive {
                    Primitive::Cube { pose, size } => (pose, size.to_vec()),
                    Primitive::Sphere { pose, radius } => (pose, vec![*radius]),
                    Primitive::Cylinder { pose, radius, height } => (pose, vec![*radius, *height]),
                    Primitive::Triangles { pose, points } => {
                        (pose, points.iter().flatten().copied().collect())
                    }
                };
                check_pose(pose).map_err(|reason| format!("object `{}`: {reason}", object.id))?;
                numbers.extend(sizes);
            }
            if numbers.iter().any(|value| !value.is_finite()) {
                return Err(format!(
                    "object `{}` has a size or colour that is not finite",
                    object.id
                ));
            }
        }
        Ok(())
    }

    /// Checks one step's values against the layout.
    pub(crate) fn check_step(&self, step: &StandardStep) -> Result<(), StepProblem> {
        if step.frame_poses.len() != self.frames.len() {
            return Err(StepProblem::Inconsistent(format!(
                "the step has {} tf frame poses but the file has {} tf frames",
                step.frame_poses.len(),
                self.frames.len()
            )));
        }
        if step.joint_positions.len() != self.joints.len() {
            return Err(StepProblem::Inconsistent(format!(
                "the step has {} joint values but the file has {} joints",
                step.joint_positions.len(),
                self.joints.len()
            )));
        }
        if step.held.len() != self.held_topics.len() {
            return Err(StepProblem::Inconsistent(format!(
                "the step has {} held frames but the file has {} held topics",
                step.held.len(),
                self.held_topics.len()
            )));
        }
        for trajectory in &step.trajectories {
            self.check_trajectory(trajectory)?;
        }
        for command in &step.gripper_commands {
            if command.topic >= self.gripper_topics.len() {
                return Err(StepProblem::Inconsistent(format!(
                    "a gripper command is for topic {} but the file has {} gripper topics",
                    command.topic,
                    self.gripper_topics.len()
                )));
            }
            if !(command.position.is_finite() && command.max_effort.is_finite()) {
                return Err(StepProblem::InvalidValue(format!(
                    "gripper command on `{}` is not finite",
                    self.gripper_topics[command.topic]
                )));
            }
        }
        if step.label.is_some() && !self.step_labels {
            return Err(StepProblem::Inconsistent(
                "the step has a plan-step label but the file has no step labels".into(),
            ));
        }
        if step.approach.is_some() && !self.approaches {
            return Err(StepProblem::Inconsistent(
                "the step begins an approach but the file has no approach topic".into(),
            ));
        }
        for (pose, frame) in step.frame_poses.iter().zip(&self.frames) {
            check_pose(pose).map_err(|reason| {
                StepProblem::InvalidValue(format!("pose of tf frame `{}`: {reason}", frame.frame))
            })?;
        }
        if let Some((value, joint)) =
            step.joint_positions.iter().zip(&self.joints).find(|(value, _)| !value.is_finite())
        {
            return Err(StepProblem::InvalidValue(format!("joint `{joint}` is {value}")));
        }
        Ok(())
    }
}

impl StandardChannels {
    /// Checks a joint trajectory: its topic exists, every point has one position and one
    /// velocity per joint, all finite, and times from the start never decrease and fit a
    /// `builtin_interfaces/Duration`.
    fn check_trajectory(&self, trajectory: &JointTrajectoryMessage) -> Result<(), StepProblem> {
        let Some(topic) = self.trajectory_topics.get(trajectory.topic) else {
            return Err(StepProblem::Inconsistent(format!(
                "a joint trajectory is for topic {} but the file has {} trajectory topics",
                trajectory.topic,
                self.trajectory_topics.len()
            )));
        };
        let mut previous = 0;
        for (index, point) in trajectory.points.iter().enumerate() {
            let joints = topic.joints.len();
            if point.positions.len() != joints || point.velocities.len() != joints {
                return Err(StepProblem::Inconsistent(format!(
                    "point {index} on `{}` has {} positions and {} velocities for {joints} joints",
                    topic.topic,
                    point.positions.len(),
                    point.velocities.len()
                )));
            }
            let values = point.positions.iter().chain(&point.velocities);
            if values.into_iter().any(|value| !value.is_finite()) {
                return Err(StepProblem::InvalidValue(format!(
                    "point {index} on `{}` has a value that is not finite",
                    topic.topic
                )));
            }
            let time = point.time_from_start_nanoseconds;
            if time < previous || time > MAXIMUM_TIME_NANOSECONDS {
                return Err(StepProblem::InvalidValue(format!(
                    "point {index} on `{}` is {time} ns from the start, before the point before \
                     or beyond what a Duration holds",
                    topic.topic
                )));
            }
            previous = time;
        }
        Ok(())
    }
}

/// A tf frame id may not be empty or contain whitespace or control characters.
fn check_frame_name(frame: &str) -> Result<(), String> {
    if frame.is_empty() || frame.chars().any(|c| c.is_whitespace() || c.is_control()) {
        return Err(format!("tf frame `{}` is empty or contains whitespace", frame.escape_debug()));
    }
    Ok(())
}

/// Bytes of one `geometry_msgs/TransformStamped` besides its two names.
const TRANSFORM_BYTES: usize = 8 + 8 + 7 * 8 + 16;

/// A CDR `tf2_msgs/msg/TFMessage`: one transform per (parent, frame, pose of the frame in the
/// parent's frame).
pub(crate) fn encode_tf<'a>(
    time_nanoseconds: u64,
    transforms: impl ExactSizeIterator<Item = (&'a str, &'a str, &'a Isometry3<f64>)>,
) -> Vec<u8> {
    let buffer = Vec::with_capacity(transforms.len() * (TRANSFORM_BYTES + 32));
    encode_tf_into(buffer, time_nanoseconds, transforms)
}

/// [`encode_tf`] into `buffer`, which is cleared first and returned with the message.
pub(crate) fn encode_tf_into<'a>(
    buffer: Vec<u8>,
    time_nanoseconds: u64,
    transforms: impl ExactSizeIterator<Item = (&'a str, &'a str, &'a Isometry3<f64>)>,
) -> Vec<u8> {
    let (seconds, nanoseconds) = split_time(time_nanoseconds);
    let mut writer = CdrWriter::reusing(buffer);
    writer.write_length(length(transforms.len()));
    for (parent, frame, pose) in transforms {
        writer.write_i32(seconds);
        writer.write_u32(nanoseconds);
        writer.write_string(parent);
        writer.write_string(frame);
        let translation = &pose.translation.vector;
        let rotation = &pose.rotation.as_ref().coords; // nalgebra stores [x, y, z, w]
        writer.write_f64s(translation.iter().chain(rotation.iter()).copied());
    }
    writer.into_bytes()
}

/// A CDR `sensor_msgs/msg/JointState` with positions only (velocity and effort empty).
/// The message is encoded into `buffer`, which is cleared first and returned with it.
pub(crate) fn encode_joint_state(
    buffer: Vec<u8>,
    time_nanoseconds: u64,
    names: &[String],
    values: &[f64],
) -> Vec<u8> {
    let (seconds, nanoseconds) = split_time(time_nanoseconds);
    let mut writer = CdrWriter::reusing(buffer);
    writer.write_i32(seconds);
    writer.write_u32(nanoseconds);
    writer.write_string("");
    writer.write_length(length(names.len()));
    for name in names {
        writer.write_string(name);
    }
    writer.write_length(length(values.len()));
    writer.write_f64s(values.iter().copied());
    writer.write_length(0);
    writer.write_length(0);
    writer.into_bytes()
}

/// A CDR `trajectory_msgs/msg/JointTrajectory` with a zero stamp and an empty frame: `joints`
/// and, per point, positions, velocities (accelerations and effort empty) and the time from the
/// start.
pub(crate) fn encode_joint_trajectory(
    buffer: Vec<u8>,
    joints: &[String],
    points: &[TrajectoryPoint],
) -> Vec<u8> {
    let mut writer = CdrWriter::reusing(buffer);
    writer.write_i32(0);
    writer.write_u32(0);
    writer.write_string("");
    writer.write_length(length(joints.len()));
    for joint in joints {
        writer.write_string(joint);
    }
    writer.write_length(length(points.len()));
    for point in points {
        writer.write_length(length(point.positions.len()));
        writer.write_f64s(point.positions.iter().copied());
        writer.write_length(length(point.velocities.len()));
        writer.write_f64s(point.velocities.iter().copied());
        writer.write_length(0);
        writer.write_length(0);
        let (seconds, nanoseconds) = split_time(point.time_from_start_nanoseconds);
        writer.write_i32(seconds);
        writer.write_u32(nanoseconds);
    }
    writer.into_bytes()
}

/// A CDR `control_msgs/msg/GripperCommand`.
pub(crate) fn encode_gripper_command(command: &GripperCommand) -> Vec<u8> {
    let mut writer = CdrWriter::new(16);
    writer.write_f64s([command.position, command.max_effort]);
    writer.into_bytes()
}

/// A CDR `std_msgs/msg/String`.
pub(crate) fn encode_string(text: &str) -> Vec<u8> {
    let mut writer = CdrWriter::new(text.len() + 8);
    writer.write_string(text);
    writer.into_bytes()
}

fn length(length: usize) -> u32 {
    // Built in memory from names and values; four billion of them would not fit there.
    u32::try_from(length).expect("sequence lengths of in-memory channels fit in u32")
}

/// The `foxglove.SceneUpdate` JSON message of every object: one entity per object, locked to
/// its frame, with no lifetime (it stays until replaced).
pub(crate) fn scene_update_json(objects: &[SceneObject]) -> String {
    let mut json = String::from(r#"{"deletions":[],"entities":["#);
    for (index, object) in objects.iter().enumerate() {
        if index > 0 {
            json.push(',');
        }
        json.push_str(r#"{"timestamp":{"sec":0,"nsec":0},"frame_id":"#);
        push_string(&mut json, &object.frame);
        json.push_str(r#","id":"#);
        push_string(&mut json, &object.id);
        json.push_str(r#","lifetime":{"sec":0,"nsec":0},"frame_locked":true,"metadata":[{"key":"type","value":"#);
        push_string(&mut json, &object.type_name);
        json.push_str(r#"}],"arrows":[]"#);
        let color = color_json(object.color);
        let mut lists: [(&str, Vec<String>); 4] = [
            ("cubes", Vec::new()),
            ("spheres", Vec::new()),
            ("cylinders", Vec::new()),
            ("triangles", Vec::new()),
        ];
        for primitive in &object.primitives {
            let (list, item) = match primitive {
                Primitive::Cube { pose, size } => (0, sized_json(pose, *size, &color, "")),
                Primitive::Sphere { pose, radius } => {
                    let diameter = 2.0 * radius;
                    (1, sized_json(pose, [diameter; 3], &color, ""))
                }
                Primitive::Cylinder { pose, radius, height } => {
                    let diameter = 2.0 * radius;
                    let scales = r#","bottom_scale":1,"top_scale":1"#;
                    (2, sized_json(pose, [diameter, diameter, *height], &color, scales))
                }
                Primitive::Triangles { pose, points } => {
                    let mut item = format!(r#"{{"pose":{},"points":["#, pose_json(pose));
                    for (index, point) in points.iter().enumerate() {
                        if index > 0 {
                            item.push(',');
                        }
                        item.push_str(&vector_json(*point));
                    }
                    let _ = write!(item, r#"],"color":{color},"colors":[],"indices":[]}}"#);
                    (3, item)
                }
            };
            lists[list].1.push(item);
        }
        for (name, items) in &lists[..3] {
            let _ = write!(json, r#","{name}":[{}]"#, items.join(","));
        }
        json.push_str(r#","lines":[]"#);
        let _ = write!(json, r#","triangles":[{}]"#, lists[3].1.join(","));
        json.push_str(r#","texts":[],"models":[]}"#);
    }
    json.push_str("]}");
    json
}

fn sized_json(pose: &Isometry3<f64>, size: [f64; 3], color: &str, extra: &str) -> String {
    format!(r#"{{"pose":{},"size":{},"color":{color}{extra}}}"#, pose_json(pose), vector_json(size))
}

fn pose_json(pose: &Isometry3<f64>) -> String {
    let t = &pose.translation.vector;
    let q = &pose.rotation.as_ref().coords;
    format!(
        r#"{{"position":{},"orientation":{{"x":{},"y":{},"z":{},"w":{}}}}}"#,
        vector_json([t.x, t.y, t.z]),
        q[0],
        q[1],
        q[2],
        q[3]
    )
}

/// Rust prints an `f64` as the shortest decimal that reads back to the same number, without an
/// exponent: valid JSON, exact and deterministic.
fn vector_json(v: [f64; 3]) -> String {
    format!(r#"{{"x":{},"y":{},"z":{}}}"#, v[0], v[1], v[2])
}

fn color_json(c: [f64; 4]) -> String {
    format!(r#"{{"r":{},"g":{},"b":{},"a":{}}}"#, c[0], c[1], c[2], c[3])
}

/// Appends `text` as a JSON string.
fn push_string(json: &mut String, text: &str) {
    json.push('"');
    for c in text.chars() {
        match c {
            '"' => json.push_str("\\\""),
            '\\' => json.push_str("\\\\"),
            c if u32::from(c) < 0x20 => {
                let _ = write!(json, "\\u{:04x}", u32::from(c));
            }
            c => json.push(c),
        }
    }
    json.push('"');
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    #[test]
    fn json_strings_escape_quotes_backslashes_and_control_characters() {
        let mut json = String::new();
        push_string(&mut json, "a\"b\\c\u{1}");
        assert_eq!(json, r#""a\"b\\c\u0001""#);
    }

    #[test]
    fn a_scene_update_names_every_primitive_list_and_places_shapes_in_the_frame() {
        let pose =
            Isometry3::from_parts(Translation3::new(0.0, 0.0, 0.075), UnitQuaternion::identity());
        let object = SceneObject {
            id: "can_0".into(),
            frame: "can_0".into(),
            type_name: "can".into(),
            color: [1.0, 0.5, 0.0, 1.0],
            primitives: vec![Primitive::Cylinder { pose, radius: 0.0325, height: 0.15 }],
        };
        let json = scene_update_json(&[object]);
        assert_eq!(
            json,
            r#"{"deletions":[],"entities":[{"timestamp":{"sec":0,"nsec":0},"frame_id":"can_0","id":"can_0","lifetime":{"sec":0,"nsec":0},"frame_locked":true,"metadata":[{"key":"type","value":"can"}],"arrows":[],"cubes":[],"spheres":[],"cylinders":[{"pose":{"position":{"x":0,"y":0,"z":0.075},"orientation":{"x":0,"y":0,"z":0,"w":1}},"size":{"x":0.065,"y":0.065,"z":0.15},"color":{"r":1,"g":0.5,"b":0,"a":1},"bottom_scale":1,"top_scale":1}],"lines":[],"triangles":[],"texts":[],"models":[]}]}"#
        );
    }

    #[test]
    fn a_tf_message_has_the_documented_layout() {
        let pose =
            Isometry3::from_parts(Translation3::new(1.0, 2.0, 3.0), UnitQuaternion::identity());
        let bytes = encode_tf(1_500_000_000, [("world", "a", &pose)].into_iter());
        // Header, count, stamp, "world", "a", padding to 8, then seven float64.
        let mut expected = vec![0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0x00, 0x65, 0xcd, 0x1d];
        expected.extend([6, 0, 0, 0]);
        expected.extend(b"world\0");
        expected.extend([0, 0]);
        expected.extend([2, 0, 0, 0]);
        expected.extend(b"a\0");
        expected.extend([0, 0]);
        for value in [1.0_f64, 2.0, 3.0, 0.0, 0.0, 0.0, 1.0] {
            expected.extend(value.to_le_bytes());
        }
        assert_eq!(bytes, expected);
    }

    #[test]
    fn checks_refuse_duplicate_frames_unknown_object_frames_and_bad_counts() {
        let mut channels = StandardChannels {
            world_frame: "world".into(),
            frames: ["a", "b"]
                .map(|frame| TfFrame {
                    parent: "world".into(),
                    frame: frame.into(),
                    derived: false,
                })
                .to_vec(),
            static_frames: vec![],
            joints: vec!["j".into()],
            robots: vec![],
            objects: vec![],
            step_labels: false,
            approaches: false,
            held_topics: vec![],
            trajectory_topics: vec![],
            gripper_topics: vec![],
        };
        assert_eq!(channels.check(), Ok(()));
        channels.frames.push(TfFrame { parent: "a".into(), frame: "world".into(), derived: true });
        assert!(channels.check().unwrap_err().contains("listed twice"));
        channels.frames.pop();
        channels.frames.push(TfFrame {
            parent: "nowhere".into(),
            frame: "c".into(),
            derived: true,
        });
        assert!(channels.check().unwrap_err().contains("not a frame of the file"));
        channels.frames.pop();
        channels.objects.push(SceneObject {
            id: "x".into(),
            frame: "c".into(),
            type_name: "t".into(),
            color: [0.0; 4],
            primitives: vec![],
        });
        assert!(channels.check().unwrap_err().contains("not a tf frame"));
        let step = StandardStep {
            frame_poses: vec![Isometry3::identity()],
            joint_positions: vec![0.0],
            label: None,
            approach: None,
            held: vec![],
            trajectories: vec![],
            gripper_commands: vec![],
        };
        assert!(matches!(channels.check_step(&step), Err(StepProblem::Inconsistent(_))));
        let step = StandardStep {
            frame_poses: vec![Isometry3::identity(); 2],
            joint_positions: vec![f64::NAN],
            label: None,
            approach: None,
            held: vec![],
            trajectories: vec![],
            gripper_commands: vec![],
        };
        assert!(matches!(channels.check_step(&step), Err(StepProblem::InvalidValue(_))));
    }
}
