//! Why a drawing could not be made: a trajectory that does not fit the spec it is drawn with.

/// Errors of matching a trajectory to a spec and picking a step.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum RenderError {
    /// A body's type is not an object type of the spec.
    #[error("body `{body}` has type `{type_name}`, which spec `{spec}` does not declare")]
    #[diagnostic(
        code(lamp::render::unknown_type),
        help("draw the file with the spec it was recorded or solved for (`--spec`)")
    )]
    UnknownType { body: String, type_name: String, spec: String },

    /// A robot of the file is not a robot of the spec.
    #[error("robot `{robot}` is not a robot of spec `{spec}` (it has: {known})")]
    #[diagnostic(
        code(lamp::render::unknown_robot),
        help("draw the file with the spec it was recorded or solved for (`--spec`)")
    )]
    UnknownRobot { robot: String, spec: String, known: String },

    /// The file's coordinates of a robot are not the model's.
    #[error("robot `{robot}`: the file's coordinates do not match the robot model: {reason}")]
    #[diagnostic(
        code(lamp::render::coordinates),
        help("the file was written for another version of the robot's URDF or kind")
    )]
    Coordinates { robot: String, reason: String },

    /// A step does not have the shape the header announces.
    #[error("step {step} does not match the header: {reason}")]
    #[diagnostic(code(lamp::render::inconsistent))]
    Inconsistent { step: usize, reason: String },

    /// The trajectory has no steps.
    #[error("the trajectory has no steps to draw")]
    #[diagnostic(code(lamp::render::empty))]
    Empty,

    /// The requested step does not exist.
    #[error("there is no step {step}: the trajectory has {count} step(s)")]
    #[diagnostic(
        code(lamp::render::step_out_of_range),
        help("steps are numbered from 0; leave out `--step` to draw the last one")
    )]
    StepOutOfRange { step: usize, count: usize },

    /// The spec's robots or types could not be built into a scene (boxed: it is large).
    #[error(transparent)]
    #[diagnostic(transparent)]
    World(Box<lamp_world::WorldError>),
}

impl From<lamp_world::WorldError> for RenderError {
    fn from(error: lamp_world::WorldError) -> Self {
        RenderError::World(Box::new(error))
    }
}
