//! The streaming writer: a header, then one message per step, then the MCAP summary.
//!
//! Output is a pure function of the header and the steps: no wall-clock time is written (message
//! times are the steps' times), the metadata map is sorted, the chunk size, compression level
//! and compressor threading are fixed, and the library string does not carry a crate version.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Cursor, Seek, Write};
use std::path::Path;

use mcap::records::{MessageHeader, Metadata};
use mcap::{Compression, WriteOptions};
use nalgebra::Isometry3;

use crate::codec::{check_step, encode_step_into};
use crate::error::TrajectoryError;
use crate::model::{Step, Trajectory, TrajectoryHeader};
use crate::schema::{
    MESSAGE_ENCODING, METADATA_NAME, PROFILE, SCHEMA_ENCODING, WORLD_STEP_SCHEMA,
    WORLD_STEP_SCHEMA_NAME, WORLD_TOPIC, header_to_metadata,
};
use crate::standard::{
    APPROACH_TOPIC, DERIVED_FRAME_PERIOD_NANOSECONDS, GRIPPER_COMMAND_SCHEMA,
    GRIPPER_COMMAND_SCHEMA_NAME, JOINT_STATE_SCHEMA, JOINT_STATE_SCHEMA_NAME, JOINT_STATES_TOPIC,
    JOINT_TRAJECTORY_SCHEMA, JOINT_TRAJECTORY_SCHEMA_NAME, LATCHED_QOS, QOS_METADATA_KEY,
    SCENE_MESSAGE_ENCODING, SCENE_SCHEMA, SCENE_SCHEMA_ENCODING, SCENE_SCHEMA_NAME, SCENE_TOPIC,
    STEP_LABEL_TOPIC, STRING_SCHEMA, STRING_SCHEMA_NAME, StandardChannels, StandardStep,
    TF_REFRESH_NANOSECONDS, TF_SCHEMA, TF_SCHEMA_NAME, TF_STATIC_TOPIC, TF_TOPIC,
    encode_gripper_command, encode_joint_state, encode_joint_trajectory, encode_string, encode_tf,
    encode_tf_into, scene_update_json,
};

/// The MCAP `library` field; no crate version, so a release does not change every file.
pub const LIBRARY: &str = "lamp-trajectory format 1";

/// Target uncompressed chunk size: big enough for zstd to find the repetition between steps,
/// small enough that a reader holds little in memory (and the MCAP writers' common default).
pub const CHUNK_SIZE: u64 = 1024 * 1024;

/// zstd's own default level: fast to write, and trajectories compress well at it.
const ZSTD_LEVEL: u32 = 3;

/// Single-threaded zstd: multi-threaded zstd emits different bytes than single-threaded, and the
/// default thread count follows the machine's cores, which would make output machine-dependent.
const ZSTD_THREADS: u32 = 0;

/// The name in errors of a trajectory written to memory.
pub const IN_MEMORY_NAME: &str = "<in-memory trajectory>";

/// Writes a trajectory file step by step.
///
/// Dropping the writer without [`TrajectoryWriter::finish`] still completes the file, but
/// ignores any error in doing so and leaves out the last step's `/tf` message, which `finish`
/// writes.
pub struct TrajectoryWriter<W: Write + Seek> {
    mcap: mcap::Writer<W>,
    header: TrajectoryHeader,
    file: String,
    channel_id: u16,
    steps: u64,
    previous_time: Option<u64>,
    standard: Option<StandardOutput>,
    /// The `/lamp/world` encoding buffer, reused for every step.
    buffer: Vec<u8>,
}

/// The per-step standard channels of a writer and what it last wrote on them.
struct StandardOutput {
    channels: StandardChannels,
    tf: Option<u16>,
    /// Per `/tf` frame, the pose and log time it was last written with.
    tf_written: Vec<Option<(Isometry3<f64>, u64)>>,
    /// The latest step's frame poses, its time and index: its `/tf` message is written when the
    /// next step arrives or the file is finished, because a derived frame whose latest change
    /// was held back is written at the last step.
    tf_pending: Option<(u64, u32)>,
    pending_poses: Vec<Isometry3<f64>>,
    joint_states: Option<u16>,
    /// The joint values and log time `/joint_states` was last written with, and its count.
    joints_written: Option<(Vec<f64>, u64)>,
    joint_messages: u32,
    step_labels: Option<u16>,
    labels_written: u32,
    previous_label: Option<String>,
    /// The approach topic's channel and how many messages it has.
    approaches: Option<(u16, u32)>,
    /// Per held topic: its channel, how many messages it has, and the last frame written.
    held: Vec<(u16, u32, Option<String>)>,
    /// Per trajectory topic and per gripper topic: its channel and how many messages it has.
    trajectories: Vec<(u16, u32)>,
    gripper_commands: Vec<(u16, u32)>,
    /// The encoding buffer, reused for every message.
    buffer: Vec<u8>,
}

impl StandardOutput {
    /// Writes the pending step's `/tf` message: every frame not written yet, moved since it was
    /// last written (a derived frame only after its period, or at the `last` step), or not
    /// written for [`TF_REFRESH_NANOSECONDS`]. The message is written even when it is empty: a
    /// bag has one `/tf` message per step, which is how the `ros2` reader finds the steps.
    fn write_pending_tf<W: Write + Seek>(
        &mut self,
        mcap: &mut mcap::Writer<W>,
        last: bool,
    ) -> Result<(), mcap::McapError> {
        let (Some(channel_id), Some((time, sequence))) = (self.tf, self.tf_pending.take()) else {
            return Ok(());
        };
        let mut chosen = Vec::with_capacity(self.channels.frames.len());
        let frames = self.channels.frames.iter().zip(&self.pending_poses);
        for ((frame, pose), written) in frames.zip(&mut self.tf_written) {
            let due = match written {
                None => true,
                Some((_, at)) if time - *at >= TF_REFRESH_NANOSECONDS => true,
                Some((previous, _)) if previous == pose => false,
                Some(_) if !frame.derived || last => true,
                Some((_, at)) => time - *at >= DERIVED_FRAME_PERIOD_NANOSECONDS,
            };
            if due {
                *written = Some((*pose, time));
                chosen.push((frame.parent.as_str(), frame.frame.as_str(), pose));
            }
        }
        let buffer = std::mem::take(&mut self.buffer);
        self.buffer = encode_tf_into(buffer, time, chosen.into_iter());
        let message = MessageHeader { channel_id, sequence, log_time: time, publish_time: time };
        mcap.write_to_known_channel(&message, &self.buffer)
    }

    /// Writes the step's `/joint_states` message when a value changed since it was last
    /// written, at the first step, and at least every [`TF_REFRESH_NANOSECONDS`].
    fn write_joints<W: Write + Seek>(
        &mut self,
        mcap: &mut mcap::Writer<W>,
        time: u64,
        values: &[f64],
    ) -> Result<(), mcap::McapError> {
        let Some(channel_id) = self.joint_states else { return Ok(()) };
        let due = match &self.joints_written {
            None => true,
            Some((previous, at)) => {
                previous.as_slice() != values || time - *at >= TF_REFRESH_NANOSECONDS
            }
        };
        if !due {
            return Ok(());
        }
        match &mut self.joints_written {
            Some((previous, at)) => {
                previous.clone_from_slice(values);
                *at = time;
            }
            None => self.joints_written = Some((values.to_vec(), time)),
        }
        let buffer = std::mem::take(&mut self.buffer);
        self.buffer = encode_joint_state(buffer, time, &self.channels.joints, values);
        let sequence = self.joint_messages;
        self.joint_messages += 1;
        let message = MessageHeader { channel_id, sequence, log_time: time, publish_time: time };
        mcap.write_to_known_channel(&message, &self.buffer)
    }
}

impl TrajectoryWriter<BufWriter<File>> {
    /// Creates (or truncates) the file at `path` and writes the header.
    pub fn create(
        path: impl AsRef<Path>,
        header: TrajectoryHeader,
    ) -> Result<Self, TrajectoryError> {
        let path = path.as_ref();
        let file = File::create(path).map_err(|source| TrajectoryError::Io {
            file: path.display().to_string(),
            action: "create",
            source,
        })?;
        Self::new(BufWriter::new(file), path.display().to_string(), header)
    }
}

impl<W: Write + Seek> TrajectoryWriter<W> {
    /// Starts a trajectory on `sink`; `name` identifies it in errors. Writes the MCAP header, the
    /// `lamp` metadata record, the schema and the channel.
    pub fn new(
        sink: W,
        name: impl Into<String>,
        header: TrajectoryHeader,
    ) -> Result<Self, TrajectoryError> {
        Self::start(sink, name.into(), header, None)
    }

    /// Starts a trajectory with the standard ROS 2 and Foxglove channels beside `/lamp/world`
    /// (see [`StandardChannels`]): writes what [`TrajectoryWriter::new`] writes, then the robot
    /// descriptions, `/tf_static` and the objects' scene update at time zero. Steps are then
    /// written with [`TrajectoryWriter::write_step_with`].
    pub fn with_standard_channels(
        sink: W,
        name: impl Into<String>,
        header: TrajectoryHeader,
        channels: StandardChannels,
    ) -> Result<Self, TrajectoryError> {
        Self::start(sink, name.into(), header, Some(channels))
    }

    fn start(
        sink: W,
        file: String,
        header: TrajectoryHeader,
        channels: Option<StandardChannels>,
    ) -> Result<Self, TrajectoryError> {
        header.check().map_err(|reason| TrajectoryError::Header { file: file.clone(), reason })?;
        if let Some(channels) = &channels {
            channels.check().map_err(|reason| TrajectoryError::Header {
                file: file.clone(),
                reason: format!("standard channels: {reason}"),
            })?;
        }
        let write_error = |error| mcap_write_error(&file, error);
        let options = WriteOptions::new()
            .profile(PROFILE)
            .library(LIBRARY)
            .compression(Some(Compression::Zstd))
            .compression_level(ZSTD_LEVEL)
            .compression_threads(ZSTD_THREADS)
            .chunk_size(Some(CHUNK_SIZE));
        let mut mcap = options.create(sink).map_err(write_error)?;
        mcap.write_metadata(&Metadata {
            name: METADATA_NAME.to_string(),
            metadata: header_to_metadata(&header),
        })
        .map_err(write_error)?;
        let schema_id = mcap
            .add_schema(WORLD_STEP_SCHEMA_NAME, SCHEMA_ENCODING, WORLD_STEP_SCHEMA.as_bytes())
            .map_err(write_error)?;
        let channel_id = mcap
            .add_channel(schema_id, WORLD_TOPIC, MESSAGE_ENCODING, &BTreeMap::new())
            .map_err(write_error)?;
        let standard = match channels {
            Some(channels) => Some(start_standard(&mut mcap, channels).map_err(write_error)?),
            None => None,
        };
        Ok(Self {
            mcap,
            header,
            file,
            channel_id,
            steps: 0,
            previous_time: None,
            standard,
            buffer: Vec::new(),
        })
    }

    /// The header this file was started with.
    pub fn header(&self) -> &TrajectoryHeader {
        &self.header
    }

    /// How many steps have been written.
    pub fn steps_written(&self) -> u64 {
        self.steps
    }

    /// Checks a step against the header and the previous step, and appends it.
    /// A writer with standard channels refuses it: use [`TrajectoryWriter::write_step_with`].
    pub fn write_step(&mut self, step: &Step) -> Result<(), TrajectoryError> {
        if self.standard.is_some() {
            return Err(TrajectoryError::Inconsistent {
                file: self.file.clone(),
                step: self.steps,
                reason: "the file has standard channels, so each step needs their values".into(),
            });
        }
        self.write_world_step(step)
    }

    /// Checks a step and its standard channels' values, and appends them: the `/lamp/world`
    /// message, then `/joint_states` when a joint moved, `/lamp/step` when the label changed,
    /// the held topics when the held frame changed, the joint trajectories that start and the
    /// gripper commands sent at the step, and `/tf` with the frames that moved, all
    /// at the step's time (`/tf` is written when the next step arrives or at
    /// [`TrajectoryWriter::finish`]; see [`TfFrame`](crate::TfFrame) for which frames).
    pub fn write_step_with(
        &mut self,
        step: &Step,
        values: &StandardStep,
    ) -> Result<(), TrajectoryError> {
        let Some(standard) = &self.standard else {
            return Err(TrajectoryError::Inconsistent {
                file: self.file.clone(),
                step: self.steps,
                reason: "the file has no standard channels to write values on".into(),
            });
        };
        standard
            .channels
            .check_step(values)
            .map_err(|problem| TrajectoryError::from_step(&self.file, self.steps, 0, problem))?;
        let sequence = self.check_world_step(step)?;
        let write_error = |error| mcap_write_error(&self.file, error);
        let standard = self.standard.as_mut().expect("checked above");
        standard.write_pending_tf(&mut self.mcap, false).map_err(write_error)?;
        self.append_world_step(step, sequence)?;
        let standard = self.standard.as_mut().expect("checked above");
        let time = step.time_nanoseconds;
        if standard.tf.is_some() {
            standard.pending_poses.clone_from(&values.frame_poses);
            standard.tf_pending = Some((time, sequence));
        }
        standard
            .write_joints(&mut self.mcap, time, &values.joint_positions)
            .map_err(|error| mcap_write_error(&self.file, error))?;
        let mut messages = Vec::new();
        if let Some(step_labels) = standard.step_labels
            && values.label.is_some()
            && values.label != standard.previous_label
        {
            let label = values.label.as_deref().unwrap_or_default();
            messages.push((step_labels, standard.labels_written, encode_string(label)));
            standard.labels_written += 1;
            standard.previous_label.clone_from(&values.label);
        }
        if let (Some((channel, written)), Some(approach)) =
            (standard.approaches.as_mut(), values.approach.as_deref())
        {
            messages.push((*channel, *written, encode_string(approach)));
            *written += 1;
        }
        for ((channel, written, previous), frame) in standard.held.iter_mut().zip(&values.held) {
            if previous.as_ref() != Some(frame) {
                messages.push((*channel, *written, encode_string(frame)));
                *written += 1;
                *previous = Some(frame.clone());
            }
        }
        for trajectory in &values.trajectories {
            let (channel, written) = &mut standard.trajectories[trajectory.topic];
            let joints = &standard.channels.trajectory_topics[trajectory.topic].joints;
            let data = encode_joint_trajectory(Vec::new(), joints, &trajectory.points);
            messages.push((*channel, *written, data));
            *written += 1;
        }
        for command in &values.gripper_commands {
            let (channel, written) = &mut standard.gripper_commands[command.topic];
            messages.push((*channel, *written, encode_gripper_command(command)));
            *written += 1;
        }
        for (channel_id, sequence, data) in messages {
            let message =
                MessageHeader { channel_id, sequence, log_time: time, publish_time: time };
            self.mcap
                .write_to_known_channel(&message, &data)
                .map_err(|error| mcap_write_error(&self.file, error))?;
        }
        Ok(())
    }

    fn write_world_step(&mut self, step: &Step) -> Result<(), TrajectoryError> {
        let sequence = self.check_world_step(step)?;
        self.append_world_step(step, sequence)
    }

    /// Checks a step against the header and the previous step; returns its sequence number.
    fn check_world_step(&self, step: &Step) -> Result<u32, TrajectoryError> {
        check_step(&self.header, step, self.previous_time)
            .map_err(|problem| TrajectoryError::from_step(&self.file, self.steps, 0, problem))?;
        u32::try_from(self.steps).map_err(|_| TrajectoryError::InvalidValue {
            file: self.file.clone(),
            step: self.steps,
            reason: "a file holds at most 2^32 steps (the MCAP sequence number is 32 bits)".into(),
        })
    }

    /// Appends a step that passed [`Self::check_world_step`].
    fn append_world_step(&mut self, step: &Step, sequence: u32) -> Result<(), TrajectoryError> {
        self.buffer = encode_step_into(std::mem::take(&mut self.buffer), &self.header, step);
        let message = MessageHeader {
            channel_id: self.channel_id,
            sequence,
            log_time: step.time_nanoseconds,
            publish_time: step.time_nanoseconds,
        };
        self.mcap
            .write_to_known_channel(&message, &self.buffer)
            .map_err(|error| mcap_write_error(&self.file, error))?;
        self.steps += 1;
        self.previous_time = Some(step.time_nanoseconds);
        Ok(())
    }

    /// Writes the last step's `/tf` message, the summary and footer, flushes, and returns the
    /// sink.
    pub fn finish(mut self) -> Result<W, TrajectoryError> {
        if let Some(standard) = &mut self.standard {
            standard
                .write_pending_tf(&mut self.mcap, true)
                .map_err(|error| mcap_write_error(&self.file, error))?;
        }
        self.mcap.finish().map_err(|error| mcap_write_error(&self.file, error))?;
        let mut sink = self.mcap.into_inner();
        sink.flush().map_err(|source| TrajectoryError::Io {
            file: self.file.clone(),
            action: "write",
            source,
        })?;
        Ok(sink)
    }
}

/// Adds the standard channels and writes what is written once, at time zero: the robot
/// descriptions, `/tf_static` and the scene update.
fn start_standard<W: Write + Seek>(
    mcap: &mut mcap::Writer<W>,
    channels: StandardChannels,
) -> Result<StandardOutput, mcap::McapError> {
    let latched = BTreeMap::from([(QOS_METADATA_KEY.to_string(), LATCHED_QOS.to_string())]);
    let none = BTreeMap::new();
    let (mut string_schema, mut tf_schema) = (None, None);
    let mut string_channel = |mcap: &mut mcap::Writer<W>, topic: &str, metadata| {
        let schema = schema_once(mcap, &mut string_schema, STRING_SCHEMA_NAME, STRING_SCHEMA)?;
        mcap.add_channel(schema, topic, MESSAGE_ENCODING, metadata)
    };
    let mut once = Vec::new();
    for robot in &channels.robots {
        let channel = string_channel(mcap, &robot.topic, &latched)?;
        once.push((channel, encode_string(&robot.urdf)));
    }
    if !channels.static_frames.is_empty() {
        let schema = schema_once(mcap, &mut tf_schema, TF_SCHEMA_NAME, TF_SCHEMA)?;
        let channel = mcap.add_channel(schema, TF_STATIC_TOPIC, MESSAGE_ENCODING, &latched)?;
        let frames = channels.static_frames.iter();
        let frames = frames.map(|f| (f.parent.as_str(), f.frame.as_str(), &f.pose));
        once.push((channel, encode_tf(0, frames)));
    }
    if !channels.objects.is_empty() {
        let schema =
            mcap.add_schema(SCENE_SCHEMA_NAME, SCENE_SCHEMA_ENCODING, SCENE_SCHEMA.as_bytes())?;
        let channel = mcap.add_channel(schema, SCENE_TOPIC, SCENE_MESSAGE_ENCODING, &none)?;
        once.push((channel, scene_update_json(&channels.objects).into_bytes()));
    }
    let tf = match channels.frames.is_empty() {
        true => None,
        false => {
            let schema = schema_once(mcap, &mut tf_schema, TF_SCHEMA_NAME, TF_SCHEMA)?;
            Some(mcap.add_channel(schema, TF_TOPIC, MESSAGE_ENCODING, &none)?)
        }
    };
    let joint_states = match channels.joints.is_empty() {
        true => None,
        false => {
            let schema = mcap.add_schema(
                JOINT_STATE_SCHEMA_NAME,
                SCHEMA_ENCODING,
                JOINT_STATE_SCHEMA.as_bytes(),
            )?;
            Some(mcap.add_channel(schema, JOINT_STATES_TOPIC, MESSAGE_ENCODING, &none)?)
        }
    };
    let step_labels = match channels.step_labels {
        false => None,
        true => Some(string_channel(mcap, STEP_LABEL_TOPIC, &none)?),
    };
    let approaches = match channels.approaches {
        false => None,
        true => Some((string_channel(mcap, APPROACH_TOPIC, &none)?, 0)),
    };
    let mut held = Vec::new();
    for topic in &channels.held_topics {
        held.push((string_channel(mcap, topic, &none)?, 0, None));
    }
    let (mut trajectory_schema, mut gripper_schema) = (None, None);
    let mut trajectories = Vec::new();
    for topic in &channels.trajectory_topics {
        let schema = schema_once(
            mcap,
            &mut trajectory_schema,
            JOINT_TRAJECTORY_SCHEMA_NAME,
            JOINT_TRAJECTORY_SCHEMA,
        )?;
        trajectories.push((mcap.add_channel(schema, &topic.topic, MESSAGE_ENCODING, &none)?, 0));
    }
    let mut gripper_commands = Vec::new();
    for topic in &channels.gripper_topics {
        let schema = schema_once(
            mcap,
            &mut gripper_schema,
            GRIPPER_COMMAND_SCHEMA_NAME,
            GRIPPER_COMMAND_SCHEMA,
        )?;
        gripper_commands.push((mcap.add_channel(schema, topic, MESSAGE_ENCODING, &none)?, 0));
    }
    for (channel_id, data) in once {
        let message = MessageHeader { channel_id, sequence: 0, log_time: 0, publish_time: 0 };
        mcap.write_to_known_channel(&message, &data)?;
    }
    Ok(StandardOutput {
        tf_written: vec![None; channels.frames.len()],
        tf_pending: None,
        pending_poses: Vec::with_capacity(channels.frames.len()),
        channels,
        tf,
        joint_states,
        joints_written: None,
        joint_messages: 0,
        step_labels,
        labels_written: 0,
        previous_label: None,
        approaches,
        held,
        trajectories,
        gripper_commands,
        buffer: Vec::new(),
    })
}

/// The id of a ROS 2 schema, added the first time it is asked for.
fn schema_once<W: Write + Seek>(
    mcap: &mut mcap::Writer<W>,
    id: &mut Option<u16>,
    name: &str,
    text: &str,
) -> Result<u16, mcap::McapError> {
    if let Some(id) = id {
        return Ok(*id);
    }
    let schema = mcap.add_schema(name, SCHEMA_ENCODING, text.as_bytes())?;
    *id = Some(schema);
    Ok(schema)
}

fn mcap_write_error(file: &str, error: mcap::McapError) -> TrajectoryError {
    let source = match error {
        mcap::McapError::Io(source) => source,
        other => std::io::Error::other(other),
    };
    TrajectoryError::Io { file: file.to_string(), action: "write", source }
}

impl Trajectory {
    /// Writes the whole trajectory to `sink`.
    pub fn write_to<W: Write + Seek>(
        &self,
        sink: W,
        name: impl Into<String>,
    ) -> Result<W, TrajectoryError> {
        let mut writer = TrajectoryWriter::new(sink, name, self.header.clone())?;
        for step in &self.steps {
            writer.write_step(step)?;
        }
        writer.finish()
    }

    /// The file's bytes.
    pub fn to_bytes(&self) -> Result<Vec<u8>, TrajectoryError> {
        Ok(self.write_to(Cursor::new(Vec::new()), IN_MEMORY_NAME)?.into_inner())
    }

    /// The file's bytes with the standard channels beside `/lamp/world`: `values` holds one
    /// [`StandardStep`] per step.
    pub fn to_bytes_with(
        &self,
        channels: &StandardChannels,
        values: &[StandardStep],
    ) -> Result<Vec<u8>, TrajectoryError> {
        if values.len() != self.steps.len() {
            return Err(TrajectoryError::Inconsistent {
                file: IN_MEMORY_NAME.to_string(),
                step: 0,
                reason: format!(
                    "{} steps but standard channel values for {}",
                    self.steps.len(),
                    values.len()
                ),
            });
        }
        let sink = Cursor::new(Vec::new());
        let mut writer = TrajectoryWriter::with_standard_channels(
            sink,
            IN_MEMORY_NAME,
            self.header.clone(),
            channels.clone(),
        )?;
        for (step, values) in self.steps.iter().zip(values) {
            writer.write_step_with(step, values)?;
        }
        Ok(writer.finish()?.into_inner())
    }

    /// Writes the trajectory to the file at `path`.
    pub fn write_file(&self, path: impl AsRef<Path>) -> Result<(), TrajectoryError> {
        let path = path.as_ref();
        let mut writer = TrajectoryWriter::create(path, self.header.clone())?;
        for step in &self.steps {
            writer.write_step(step)?;
        }
        writer.finish()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schema::FORMAT_VERSION;

    #[test]
    fn library_string_names_the_format_version() {
        assert!(LIBRARY.ends_with(&format!(" {FORMAT_VERSION}")));
    }
}
