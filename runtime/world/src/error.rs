//! Errors of building scenes and planning in them.

use std::path::PathBuf;

/// Why a scene could not be built or a query could not be answered.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum WorldError {
    /// The robot's URDF could not be loaded or a spec setting does not fit it.
    #[error("robot `{robot}` ({urdf}): {source}")]
    #[diagnostic(
        code(lamp::world::robot),
        help("check the robot's URDF and its settings in the spec")
    )]
    Robot {
        robot: String,
        urdf: PathBuf,
        #[source]
        source: Box<lamp_robot::RobotError>,
    },
    /// An object type's geometry is unusable.
    #[error("type `{type_name}`: {reason}")]
    #[diagnostic(code(lamp::world::shape), help("check the type's shapes and mesh files"))]
    Shape { type_name: String, reason: String },
    /// A name that the scene does not contain.
    #[error("the scene has no {what} named `{name}`")]
    #[diagnostic(code(lamp::world::unknown_name))]
    UnknownName { what: &'static str, name: String },
    /// A problem refers to a robot or type the spec does not declare (the checker prevents this).
    #[error("problem `{problem}` mentions `{name}`, which the spec does not declare")]
    #[diagnostic(code(lamp::world::undeclared))]
    Undeclared { problem: String, name: String },
    /// A configuration of the wrong length or outside the robot's limits.
    #[error("robot `{robot}`: {reason}")]
    #[diagnostic(code(lamp::world::configuration))]
    Configuration { robot: String, reason: String },
    /// A grab that is not possible (already holding, out of reach, not movable).
    #[error("robot `{robot}` cannot grab `{object}`: {reason}")]
    #[diagnostic(code(lamp::world::grab))]
    Grab { robot: String, object: String, reason: String },
    /// Fingers that cannot close onto the held object or open from it: they would touch
    /// something else, or the robot holds nothing.
    #[error("robot `{robot}` cannot {action} its fingers: {reason}")]
    #[diagnostic(code(lamp::world::fingers))]
    Fingers { robot: String, action: &'static str, reason: String },
    /// A gripper without fingers that cannot come to contact with the object it is to hold.
    #[error("robot `{robot}` cannot bring its gripper to `{object}`: {reason}")]
    #[diagnostic(code(lamp::world::contact))]
    Contact { robot: String, object: String, reason: String },
    /// A recorded trajectory whose steps cannot be timed: they do not fit the robots, or a
    /// robot moves by something that is not a number.
    #[error("the trajectory cannot be timed at step {step}: {reason}")]
    #[diagnostic(code(lamp::world::timing))]
    Timing { step: usize, reason: String },
}
