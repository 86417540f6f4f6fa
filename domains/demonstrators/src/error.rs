//! Why a demonstration could not be generated.

/// A demonstrator failure; every variant names what the user can change.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum DemoError {
    /// The spec has no `simulate` demonstration source.
    #[error("the spec declares no simulated demonstrator")]
    #[diagnostic(
        code(lamp::demos::no_simulator),
        help(
            "add `demonstrations {{ simulate packing {{ count 200 cut 0.5 objects 1 seed 1 }} }}` (or `cafe`) to the spec"
        )
    )]
    NoSimulator,
    /// The demonstrator name is not one lamp ships.
    #[error("unknown demonstrator `{name}`")]
    #[diagnostic(
        code(lamp::demos::unknown_demonstrator),
        help("lamp ships `packing`, `cafe`, `dinner` and `jenga`")
    )]
    UnknownDemonstrator { name: String },
    /// The spec lacks something the demonstrator needs (a type, a robot, a part, a problem).
    #[error("demonstrator `{demonstrator}` needs {what}")]
    #[diagnostic(
        code(lamp::demos::spec_mismatch),
        help(
            "the bundled demonstrators expect the bundled spec of their domain (domains/<name>/<name>.lamp)"
        )
    )]
    SpecMismatch { demonstrator: String, what: String },
    /// A setting the demonstrator cannot honour.
    #[error("demonstrator `{demonstrator}`: {reason}")]
    #[diagnostic(code(lamp::demos::unsupported))]
    Unsupported { demonstrator: String, reason: String },
    /// Every attempt at a demonstration failed (IK or motion planning).
    #[error("demonstration {index} failed after {attempts} attempts; last failure: {last}")]
    #[diagnostic(
        code(lamp::demos::attempts_exhausted),
        help("try another seed; if it keeps failing, the layout ranges do not fit the robot")
    )]
    AttemptsExhausted { index: u32, attempts: u32, last: String },
    /// Building the scene failed.
    #[error(transparent)]
    #[diagnostic(transparent)]
    World(#[from] lamp_world::WorldError),
    /// Encoding the recording failed.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Trajectory(#[from] lamp_trajectory::TrajectoryError),
}
