//! Typed errors of robot loading and inverse kinematics.
//!
//! Every loading error names the file (or `<string>` for in-memory URDF) and the element at fault.

use std::path::PathBuf;

/// Why a robot could not be loaded or configured.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum RobotError {
    /// The URDF file could not be read.
    #[error("cannot read robot file {file}")]
    #[diagnostic(code(lamp::robot::read), help("check that the path exists and is readable"))]
    Read {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// The URDF file is larger than any robot description: most likely a wrong path.
    #[error("robot file {file} is {size} bytes, more than the {limit} a robot file may be")]
    #[diagnostic(
        code(lamp::robot::too_large),
        help("Check that the path names the robot's URDF file.")
    )]
    TooLarge { file: PathBuf, size: u64, limit: u64 },

    /// The URDF text is not valid URDF XML.
    #[error("{file}: invalid URDF: {message}")]
    #[diagnostic(code(lamp::robot::urdf_parse))]
    UrdfParse { file: String, message: String },

    /// A joint names a parent or child link that the file does not define.
    #[error("{file}: joint `{joint}` refers to link `{link}`, which is not defined")]
    #[diagnostic(
        code(lamp::robot::missing_link),
        help("add a <link name=\"{link}\"/> element or fix the joint's parent/child name")
    )]
    MissingLink { file: String, joint: String, link: String },

    /// Two elements share a name.
    #[error("{file}: {element} `{name}` is defined more than once")]
    #[diagnostic(code(lamp::robot::duplicate_name))]
    DuplicateName { file: String, element: &'static str, name: String },

    /// The links do not form one tree (no root, several roots, a link with two parents, a cycle).
    #[error("{file}: the links do not form a single tree: {reason}")]
    #[diagnostic(code(lamp::robot::tree))]
    NotATree { file: String, reason: String },

    /// A joint is malformed (zero axis, inverted limits, a type lamp does not support).
    #[error("{file}: joint `{joint}`: {reason}")]
    #[diagnostic(code(lamp::robot::joint))]
    InvalidJoint { file: String, joint: String, reason: String },

    /// A collision geometry is malformed (negative size, non-finite numbers).
    #[error("{file}: link `{link}`: invalid collision geometry: {reason}")]
    #[diagnostic(code(lamp::robot::geometry))]
    InvalidGeometry { file: String, link: String, reason: String },

    /// A collision mesh could not be found or loaded.
    #[error("{file}: link `{link}`: cannot load mesh `{mesh}`: {reason}")]
    #[diagnostic(
        code(lamp::robot::mesh),
        help(
            "mesh paths are resolved against the URDF's folder; `package://NAME/...` looks for a folder NAME above it"
        )
    )]
    Mesh { file: String, link: String, mesh: String, reason: String },

    /// A joint name given by the caller does not exist in the robot.
    #[error("robot `{robot}` has no joint `{joint}`")]
    #[diagnostic(code(lamp::robot::unknown_joint))]
    UnknownJoint { robot: String, joint: String },

    /// A link name given by the caller does not exist in the robot.
    #[error("robot `{robot}` has no link `{link}`")]
    #[diagnostic(code(lamp::robot::unknown_link))]
    UnknownLink { robot: String, link: String },

    /// A coordinate name given by the caller does not exist in the robot.
    #[error("robot `{robot}` has no configuration coordinate `{coordinate}`")]
    #[diagnostic(code(lamp::robot::unknown_coordinate))]
    UnknownCoordinate { robot: String, coordinate: String },

    /// Limits given by the caller are not an interval.
    #[error("robot `{robot}`: invalid limits [{lower}, {upper}] for `{coordinate}`")]
    #[diagnostic(code(lamp::robot::limits))]
    InvalidLimits { robot: String, coordinate: String, lower: f64, upper: f64 },

    /// A joint group given by the caller is empty or clashes with a built-in group.
    #[error("robot `{robot}`: invalid joint group `{group}`: {reason}")]
    #[diagnostic(code(lamp::robot::group))]
    InvalidGroup { robot: String, group: String, reason: String },
}

/// Why inverse kinematics returned no configuration.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum IkError {
    /// No configuration reached the target within tolerance (or every one that did was rejected).
    #[error(
        "no IK solution for link `{link}` within {attempts} attempts \
         (best position error {best_position_error:.4} m, orientation error {best_orientation_error:.4} rad, \
         {rejected} converged solutions rejected)"
    )]
    #[diagnostic(code(lamp::robot::ik_no_solution))]
    NoSolution {
        link: String,
        attempts: usize,
        rejected: usize,
        best_position_error: f64,
        best_orientation_error: f64,
    },

    /// The target is farther from the group's first moving joint than the chain below it can
    /// stretch, so no configuration reaches it and no iteration was spent on it.
    #[error(
        "no IK solution for link `{link}`: the target is {distance:.3} m from the first joint \
         that moves, beyond the chain's reach of {reach:.3} m"
    )]
    #[diagnostic(code(lamp::robot::ik_out_of_reach))]
    OutOfReach { link: String, distance: f64, reach: f64 },

    /// The caller's screen ruled the target out before any iteration
    /// ([`solve_ik_screened`](crate::solve_ik_screened)): every configuration that meets it
    /// would be refused.
    #[error(
        "no IK solution for link `{link}`: every configuration that reaches the target is refused"
    )]
    #[diagnostic(code(lamp::robot::ik_target_refused))]
    TargetRefused { link: String },

    /// The request itself is malformed (wrong seed length, unknown link, bad group).
    #[error("invalid IK request: {reason}")]
    #[diagnostic(code(lamp::robot::ik_request))]
    InvalidRequest { reason: String },
}
