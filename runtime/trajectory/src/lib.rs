//! Demonstration and trajectory files: the MCAP schema, writer and reader.
//!
//! Demonstrations (the learner's only input) and solved trajectories (the runtime's output) share
//! one format: an MCAP file that is a ROS 2 bag, with one CDR `lamp_msgs/msg/WorldStep` message
//! per time step on `/lamp/world` and the header in a `lamp` metadata record.
//! `docs/formats.md` specifies it for people who write such files with other tools.
//!
//! ```
//! use lamp_trajectory::{BodyDescription, Step, Trajectory, TrajectoryHeader, TrajectoryReader};
//! use nalgebra::Isometry3;
//!
//! let header = TrajectoryHeader {
//!     domain: "packing".into(),
//!     seed: 1,
//!     provenance: Default::default(),
//!     bodies: vec![BodyDescription { name: "can_0".into(), type_name: "can".into() }],
//!     robots: vec![],
//! };
//! let step = Step { time_nanoseconds: 0, body_poses: vec![Isometry3::identity()], robots: vec![] };
//! let bytes = Trajectory { header, steps: vec![step.clone()] }.to_bytes()?;
//! let mut reader = TrajectoryReader::from_bytes(&bytes, "example")?;
//! assert_eq!(reader.header().bodies[0].name, "can_0");
//! assert_eq!(reader.next().transpose()?, Some(step));
//! # Ok::<(), lamp_trajectory::TrajectoryError>(())
//! ```

mod bag_filter;
mod cdr;
mod chunk;
mod codec;
mod error;
mod model;
mod reader;
mod record;
mod schema;
mod standard;
mod standard_reader;
mod writer;

pub use bag_filter::filter_bag;
pub use codec::{MAXIMUM_TIME_NANOSECONDS, QUATERNION_NORM_TOLERANCE};
pub use error::TrajectoryError;
pub use model::{
    BodyDescription, RobotDescription, RobotState, Step, Trajectory, TrajectoryHeader,
};
pub use reader::{MAXIMUM_RECORD_BYTES, TrajectoryReader};
pub use schema::{
    FORMAT_VERSION, MESSAGE_ENCODING, METADATA_NAME, PROFILE, SCHEMA_ENCODING, WORLD_STEP_SCHEMA,
    WORLD_STEP_SCHEMA_NAME, WORLD_TOPIC,
};
pub use standard::{
    APPROACH_TOPIC, BASE_TRAJECTORY_TOPIC, DERIVED_FRAME_PERIOD_NANOSECONDS,
    GRIPPER_COMMAND_SCHEMA, GRIPPER_COMMAND_SCHEMA_NAME, GRIPPER_COMMAND_TOPIC, GripperCommand,
    HELD_TOPIC, JOINT_STATE_SCHEMA, JOINT_STATE_SCHEMA_NAME, JOINT_STATES_TOPIC,
    JOINT_TRAJECTORY_SCHEMA, JOINT_TRAJECTORY_SCHEMA_NAME, JOINT_TRAJECTORY_TOPIC,
    JointTrajectoryMessage, LATCHED_QOS, Primitive, QOS_METADATA_KEY, ROBOT_DESCRIPTION_TOPIC,
    RobotModelText, SCENE_MESSAGE_ENCODING, SCENE_SCHEMA, SCENE_SCHEMA_ENCODING, SCENE_SCHEMA_NAME,
    SCENE_TOPIC, STEP_LABEL_TOPIC, STRING_SCHEMA, STRING_SCHEMA_NAME, SceneObject,
    StandardChannels, StandardStep, StaticFrame, TF_REFRESH_NANOSECONDS, TF_SCHEMA, TF_SCHEMA_NAME,
    TF_STATIC_TOPIC, TF_TOPIC, TfFrame, TrajectoryPoint, TrajectoryTopic,
};
pub use standard_reader::{
    BagGripperCommand, BagJointState, BagJointTrajectory, BagTfMessage, BagTransform,
    StandardRecording, read_standard_channels,
};
pub use writer::{CHUNK_SIZE, IN_MEMORY_NAME, LIBRARY, TrajectoryWriter};
