//! Robots from URDF: kinematic trees, the virtual mount, joint groups, the configuration space,
//! forward kinematics, Jacobians, inverse kinematics, link collision geometry, and the timing of a
//! path within the joints' velocity and acceleration limits.
//!
//! This crate owns the layout of a configuration vector (`docs/robots.md`): no other crate
//! interprets coordinates; everything goes through [`Robot`] methods.

mod collision;
mod configuration;
mod error;
mod ik;
mod kinematics;
mod mesh;
mod mount;
mod reach;
mod robot;
mod timing;
mod urdf;

pub use configuration::{
    LIMIT_TOLERANCE, UNBOUNDED_SAMPLE_HALF_WIDTH, slerp, uniform_rotation, wrap_angle,
};
pub use error::{IkError, RobotError};
pub use ik::{
    DEFAULT_DAMPING, DEFAULT_MAX_ITERATIONS, DEFAULT_ORIENTATION_TOLERANCE,
    DEFAULT_POSITION_TOLERANCE, DEFAULT_RESTARTS, IkConfig, IkGoal, pose_error_norms, solve_ik,
    solve_ik_screened,
};
pub use lamp_geometry::{Pose, Shape};
pub use mesh::load_mesh_file;
pub use mount::Mount;
pub use robot::{
    ALL_GROUP, ARM_GROUP, BASE_GROUP, Coordinate, CoordinateKind, GRIPPER_GROUP, JointGroup,
    LinkGeometry, LinkId, Robot,
};
pub use timing::{
    DEFAULT_ACCELERATION, DEFAULT_JOINT_VELOCITY, Limits, MOUNT_ANGULAR_VELOCITY,
    MOUNT_LINEAR_VELOCITY, TimingError, time_path,
};
pub use urdf::MAX_URDF_BYTES;
