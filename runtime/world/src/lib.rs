//! The world robots act in: scenes of bodies and robots, held objects, collision checking,
//! collision-free inverse kinematics and RRT-Connect motion planning.
//!
//! Geometry and collision queries come from `lamp-geometry`, kinematics from `lamp-robot`; this
//! crate puts them together into the state the demonstrators, the refiner and the validator
//! step through. It is a pure library: it reads no files beyond the robot and mesh files a spec
//! names.

mod checking;
mod contact;
mod error;
mod execution;
mod fingers;
mod from_spec;
mod ik;
mod motion;
mod recording;
mod resting;
mod scene;
mod straight;
mod timing;
mod viewing;

pub use checking::Contact;
pub use contact::{CONTACT_GAP, MAX_CONTACT_APPROACH, contact_approach};
pub use error::WorldError;
pub use execution::{
    FingerStop, HOLD_OFF, HOLD_ON, execution_channels, grasp_position, motion_segments,
};
pub use fingers::{FingerMove, finger_path};
pub use from_spec::{
    STRUCTURE_ANGLE_TOLERANCE, STRUCTURE_POSITION_TOLERANCE, SpecWorld, load_robot, mount_of,
    robot_names, type_parts_of,
};
pub use ik::{LinkGoal, ReachError, reach, reach_observed};
pub use lamp_rrt::{MAX_EDGE_STEPS, RrtConfig, RrtError, RrtStats, Space, rrt_connect, shortcut};
pub use motion::{
    DEFAULT_ANGULAR_RESOLUTION, DEFAULT_LINEAR_RESOLUTION, FREE_SAMPLING_MARGIN, MotionConfig,
    MotionError, MotionPlan, RobotSpace, checked_edge_steps, densify, edge_steps, plan_motion,
};
pub use recording::{Approach, ApproachKind, Recorder, STEP_NANOSECONDS, trajectory_header};
pub use resting::{LeftUnsupported, MAX_SETTLE_DROP, RESTING_GAP, RestError, SUPPORT_TOLERANCE};
pub use scene::{Body, Gripper, Held, Scene, SceneRobot};
pub use straight::{StraightLineError, straight_line};
pub use timing::{GRASP_SECONDS, time_steps};
pub use viewing::{WORLD_FRAME, label_plan_steps, mark_approaches, standard_channels};
