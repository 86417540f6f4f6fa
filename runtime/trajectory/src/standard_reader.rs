//! Reading the standard channels of any ROS 2 bag: `/tf`, `/tf_static`, `/joint_states`,
//! `std_msgs/msg/String` topics, and every `trajectory_msgs/msg/JointTrajectory` and
//! `control_msgs/msg/GripperCommand` topic, decoded from CDR into plain values in file order, for learning
//! from bags that have no `/lamp/world` (the `ros2` demonstration source).
//!
//! It reads records as [`crate::TrajectoryReader`] does (checksums verified, the same size
//! limits) and knows nothing of robots or objects: the caller maps frames to bodies.

use std::collections::BTreeMap;
use std::io::Read;

use mcap::records::Record;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

use crate::cdr::{CdrError, CdrReader};
use crate::error::TrajectoryError;
use crate::reader::RecordSource;
use crate::schema::{MESSAGE_ENCODING, SCHEMA_ENCODING};
use crate::standard::{
    GRIPPER_COMMAND_SCHEMA_NAME, JOINT_STATE_SCHEMA_NAME, JOINT_STATES_TOPIC,
    JOINT_TRAJECTORY_SCHEMA_NAME, STRING_SCHEMA_NAME, TF_SCHEMA_NAME, TF_STATIC_TOPIC, TF_TOPIC,
    TrajectoryPoint,
};

/// Bytes of a `geometry_msgs/TransformStamped` without its names: a lower bound for counts.
const TRANSFORM_MINIMUM_BYTES: usize = 8 + 4 + 4 + 7 * 8;

const NANOSECONDS_PER_SECOND: i64 = 1_000_000_000;

/// One transform of a `tf2_msgs/msg/TFMessage`.
#[derive(Debug, Clone, PartialEq)]
pub struct BagTransform {
    /// The header stamp in nanoseconds (negative stamps are refused).
    pub stamp_nanoseconds: u64,
    pub parent: String,
    pub frame: String,
    /// The frame's pose in the parent's frame, as stored (quaternions are not renormalised).
    pub pose: Isometry3<f64>,
}

/// A `/tf` or `/tf_static` message: its MCAP log time and its transforms.
#[derive(Debug, Clone, PartialEq)]
pub struct BagTfMessage {
    pub log_time: u64,
    pub transforms: Vec<BagTransform>,
}

/// A `sensor_msgs/msg/JointState` message (velocity and effort are not kept).
#[derive(Debug, Clone, PartialEq)]
pub struct BagJointState {
    pub log_time: u64,
    pub names: Vec<String>,
    pub positions: Vec<f64>,
}

/// A `trajectory_msgs/msg/JointTrajectory` message (accelerations and effort are not kept).
#[derive(Debug, Clone, PartialEq)]
pub struct BagJointTrajectory {
    pub log_time: u64,
    /// The header stamp in nanoseconds.
    pub stamp_nanoseconds: u64,
    pub joint_names: Vec<String>,
    pub points: Vec<TrajectoryPoint>,
}

/// A `control_msgs/msg/GripperCommand` message.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BagGripperCommand {
    pub log_time: u64,
    pub position: f64,
    pub max_effort: f64,
}

/// The standard channels of a bag, each in file order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StandardRecording {
    pub tf: Vec<BagTfMessage>,
    pub tf_static: Vec<BagTfMessage>,
    pub joint_states: Vec<BagJointState>,
    /// The `std_msgs/msg/String` messages of the topics asked for: topic → (log time, text).
    pub strings: BTreeMap<String, Vec<(u64, String)>>,
    /// The joint trajectories of every topic of that type: topic → messages.
    pub joint_trajectories: BTreeMap<String, Vec<BagJointTrajectory>>,
    /// The gripper commands of every topic of that type: topic → messages.
    pub gripper_commands: BTreeMap<String, Vec<BagGripperCommand>>,
    /// Every topic the bag declares a channel for, whatever its type.
    pub topics: std::collections::BTreeSet<String>,
}

/// What a channel holds, for decoding its messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Tf,
    TfStatic,
    JointState,
    String,
    JointTrajectory,
    GripperCommand,
    Other,
}

/// Reads the standard channels of the bag in `source` (`name` identifies it in errors), and the
/// `std_msgs/msg/String` messages of `string_topics`. A standard topic with another type or
/// encoding is refused with [`TrajectoryError::Schema`].
pub fn read_standard_channels<R: Read>(
    source: R,
    name: impl Into<String>,
    string_topics: &[&str],
) -> Result<StandardRecording, TrajectoryError> {
    let mut records = RecordSource::new(source, name.into());
    let mut schemas: BTreeMap<u16, (String, String)> = BTreeMap::new();
    let mut channels: BTreeMap<u16, (Kind, String)> = BTreeMap::new();
    let mut recording = StandardRecording::default();
    for topic in string_topics {
        recording.strings.insert((*topic).to_string(), Vec::new());
    }
    let mut messages = 0;
    loop {
        let record_index = records.records;
        let Some(record) = records.next_record(messages)? else { break };
        let file = &records.file;
        match record {
            Record::Schema { header, .. } => {
                schemas.insert(header.id, (header.name.clone(), header.encoding.clone()));
            }
            Record::Channel(channel) => {
                let topic = channel.topic.as_str();
                let schema_name = schemas.get(&channel.schema_id).map(|(name, _)| name.as_str());
                let kind = match (topic, schema_name) {
                    (TF_TOPIC, _) => Kind::Tf,
                    (TF_STATIC_TOPIC, _) => Kind::TfStatic,
                    (JOINT_STATES_TOPIC, _) => Kind::JointState,
                    _ if string_topics.contains(&topic) => Kind::String,
                    (_, Some(JOINT_TRAJECTORY_SCHEMA_NAME)) => Kind::JointTrajectory,
                    (_, Some(GRIPPER_COMMAND_SCHEMA_NAME)) => Kind::GripperCommand,
                    _ => Kind::Other,
                };
                let expected = match kind {
                    Kind::Tf | Kind::TfStatic => TF_SCHEMA_NAME,
                    Kind::JointState => JOINT_STATE_SCHEMA_NAME,
                    Kind::String => STRING_SCHEMA_NAME,
                    Kind::JointTrajectory => JOINT_TRAJECTORY_SCHEMA_NAME,
                    Kind::GripperCommand => GRIPPER_COMMAND_SCHEMA_NAME,
                    Kind::Other => "",
                };
                if kind != Kind::Other {
                    let schema = schemas.get(&channel.schema_id);
                    let found = schema.map(|(name, encoding)| (name.as_str(), encoding.as_str()));
                    if found != Some((expected, SCHEMA_ENCODING))
                        || channel.message_encoding != MESSAGE_ENCODING
                    {
                        return Err(TrajectoryError::Schema {
                            file: file.clone(),
                            reason: format!(
                                "topic `{topic}` has schema {found:?} in `{}`, expected `{expected}` in `{SCHEMA_ENCODING}` and `{MESSAGE_ENCODING}`",
                                channel.message_encoding
                            ),
                        });
                    }
                }
                match kind {
                    Kind::JointTrajectory => {
                        recording.joint_trajectories.entry(channel.topic.clone()).or_default();
                    }
                    Kind::GripperCommand => {
                        recording.gripper_commands.entry(channel.topic.clone()).or_default();
                    }
                    _ => {}
                }
                recording.topics.insert(channel.topic.clone());
                channels.insert(channel.id, (kind, channel.topic.clone()));
            }
            Record::Message { header, data } => {
                let (kind, topic) =
                    channels.get(&header.channel_id).ok_or_else(|| TrajectoryError::Corrupt {
                        file: file.clone(),
                        record: record_index,
                        steps: messages,
                        reason: format!("a message uses undeclared channel {}", header.channel_id),
                    })?;
                let corrupt = |error: CdrError| TrajectoryError::Corrupt {
                    file: file.clone(),
                    record: record_index,
                    steps: messages,
                    reason: format!("`{topic}` message at {} ns: {error}", header.log_time),
                };
                let invalid = |reason: String| TrajectoryError::InvalidValue {
                    file: file.clone(),
                    step: messages,
                    reason: format!("`{topic}` message at {} ns: {reason}", header.log_time),
                };
                let log_time = header.log_time;
                match kind {
                    Kind::Tf | Kind::TfStatic => {
                        let transforms = decode_tf(&data).map_err(|problem| match problem {
                            Problem::Cdr(error) => corrupt(error),
                            Problem::Value(reason) => invalid(reason),
                        })?;
                        let message = BagTfMessage { log_time, transforms };
                        match kind {
                            Kind::Tf => recording.tf.push(message),
                            _ => recording.tf_static.push(message),
                        }
                    }
                    Kind::JointState => {
                        let (names, positions) =
                            decode_joint_state(&data).map_err(|problem| match problem {
                                Problem::Cdr(error) => corrupt(error),
                                Problem::Value(reason) => invalid(reason),
                            })?;
                        recording.joint_states.push(BagJointState { log_time, names, positions });
                    }
                    Kind::String => {
                        let text = decode_string(&data).map_err(corrupt)?;
                        if let Some(list) = recording.strings.get_mut(topic) {
                            list.push((log_time, text));
                        }
                    }
                    Kind::JointTrajectory => {
                        let (stamp_nanoseconds, joint_names, points) =
                            decode_joint_trajectory(&data).map_err(|problem| match problem {
                                Problem::Cdr(error) => corrupt(error),
                                Problem::Value(reason) => invalid(reason),
                            })?;
                        let message =
                            BagJointTrajectory { log_time, stamp_nanoseconds, joint_names, points };
                        recording
                            .joint_trajectories
                            .entry(topic.clone())
                            .or_default()
                            .push(message);
                    }
                    Kind::GripperCommand => {
                        let (position, max_effort) =
                            decode_gripper_command(&data).map_err(corrupt)?;
                        let message = BagGripperCommand { log_time, position, max_effort };
                        recording.gripper_commands.entry(topic.clone()).or_default().push(message);
                    }
                    Kind::Other => {}
                }
                messages += 1;
            }
            _ => {}
        }
    }
    Ok(recording)
}

/// Why a standard message does not decode.
enum Problem {
    Cdr(CdrError),
    Value(String),
}

impl From<CdrError> for Problem {
    fn from(error: CdrError) -> Self {
        Problem::Cdr(error)
    }
}

fn read_stamp(reader: &mut CdrReader<'_>) -> Result<u64, Problem> {
    let seconds = reader.read_i32()?;
    let nanoseconds = reader.read_u32()?;
    let total = i64::from(seconds) * NANOSECONDS_PER_SECOND + i64::from(nanoseconds);
    u64::try_from(total)
        .ok()
        .filter(|_| i64::from(nanoseconds) < NANOSECONDS_PER_SECOND)
        .ok_or_else(|| Problem::Value(format!("stamp {seconds} s {nanoseconds} ns is negative")))
}

fn decode_tf(bytes: &[u8]) -> Result<Vec<BagTransform>, Problem> {
    let mut reader = CdrReader::new(bytes)?;
    let count = reader.read_length(TRANSFORM_MINIMUM_BYTES)?;
    let mut transforms = Vec::with_capacity(count);
    for _ in 0..count {
        let stamp_nanoseconds = read_stamp(&mut reader)?;
        let parent = reader.read_string()?.to_string();
        let frame = reader.read_string()?.to_string();
        let mut values = [0.0; 7];
        for value in &mut values {
            *value = reader.read_f64()?;
        }
        if values.iter().any(|value| !value.is_finite()) {
            return Err(Problem::Value(format!("the transform of `{frame}` is not finite")));
        }
        let [x, y, z, qx, qy, qz, qw] = values;
        let rotation = UnitQuaternion::new_unchecked(Quaternion::new(qw, qx, qy, qz));
        let pose = Isometry3::from_parts(Translation3::new(x, y, z), rotation);
        crate::codec::check_pose(&pose)
            .map_err(|reason| Problem::Value(format!("the transform of `{frame}`: {reason}")))?;
        transforms.push(BagTransform { stamp_nanoseconds, parent, frame, pose });
    }
    reader.finish()?;
    Ok(transforms)
}

fn decode_joint_state(bytes: &[u8]) -> Result<(Vec<String>, Vec<f64>), Problem> {
    let mut reader = CdrReader::new(bytes)?;
    read_stamp(&mut reader)?;
    reader.read_string()?;
    let count = reader.read_length(5)?;
    let mut names = Vec::with_capacity(count);
    for _ in 0..count {
        names.push(reader.read_string()?.to_string());
    }
    let count = reader.read_length(8)?;
    let mut positions = Vec::with_capacity(count);
    for _ in 0..count {
        positions.push(reader.read_f64()?);
    }
    for _ in 0..2 {
        let count = reader.read_length(8)?;
        for _ in 0..count {
            reader.read_f64()?;
        }
    }
    reader.finish()?;
    if names.len() != positions.len() {
        return Err(Problem::Value(format!(
            "{} joint names but {} positions",
            names.len(),
            positions.len()
        )));
    }
    if let Some((name, value)) = names.iter().zip(&positions).find(|(_, v)| !v.is_finite()) {
        return Err(Problem::Value(format!("joint `{name}` is {value}")));
    }
    Ok((names, positions))
}

/// A float64 sequence, its count bounded by the bytes left.
fn read_f64_sequence(reader: &mut CdrReader<'_>) -> Result<Vec<f64>, CdrError> {
    let count = reader.read_length(8)?;
    (0..count).map(|_| reader.read_f64()).collect()
}

/// The stamp, joint names and points (positions, velocities, time from start) of a
/// `trajectory_msgs/msg/JointTrajectory`.
fn decode_joint_trajectory(
    bytes: &[u8],
) -> Result<(u64, Vec<String>, Vec<TrajectoryPoint>), Problem> {
    let mut reader = CdrReader::new(bytes)?;
    let stamp = read_stamp(&mut reader)?;
    reader.read_string()?;
    let count = reader.read_length(5)?;
    let mut names = Vec::with_capacity(count);
    for _ in 0..count {
        names.push(reader.read_string()?.to_string());
    }
    // Four empty sequences and a duration: 24 bytes at least.
    let count = reader.read_length(24)?;
    let mut points = Vec::with_capacity(count);
    for index in 0..count {
        let positions = read_f64_sequence(&mut reader)?;
        let velocities = read_f64_sequence(&mut reader)?;
        read_f64_sequence(&mut reader)?;
        read_f64_sequence(&mut reader)?;
        let time_from_start_nanoseconds = read_stamp(&mut reader)?;
        let values = positions.iter().chain(&velocities);
        if values.into_iter().any(|value| !value.is_finite()) {
            return Err(Problem::Value(format!("point {index} has a value that is not finite")));
        }
        points.push(TrajectoryPoint { positions, velocities, time_from_start_nanoseconds });
    }
    reader.finish()?;
    Ok((stamp, names, points))
}

/// The position and maximum effort of a `control_msgs/msg/GripperCommand`.
fn decode_gripper_command(bytes: &[u8]) -> Result<(f64, f64), CdrError> {
    let mut reader = CdrReader::new(bytes)?;
    let position = reader.read_f64()?;
    let max_effort = reader.read_f64()?;
    reader.finish()?;
    Ok((position, max_effort))
}

fn decode_string(bytes: &[u8]) -> Result<String, CdrError> {
    let mut reader = CdrReader::new(bytes)?;
    let text = reader.read_string()?.to_string();
    reader.finish()?;
    Ok(text)
}
