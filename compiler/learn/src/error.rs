//! The learner's typed errors: bad demonstrations, bad settings, and data too thin to learn from.

use miette::Diagnostic;
use thiserror::Error;

/// Everything that can stop learning.
#[derive(Debug, Error, Diagnostic, Clone, PartialEq)]
pub enum LearnError {
    /// There is nothing to learn from.
    #[error("no demonstrations were given")]
    #[diagnostic(
        code(lamp::learn::no_demonstrations),
        help("Record demonstrations of the training task and list them in the spec.")
    )]
    NoDemonstrations,

    /// A time step does not carry one pose per participant.
    #[error(
        "demonstration `{demonstration}` step {step} has {found} poses for {expected} participants"
    )]
    #[diagnostic(
        code(lamp::learn::pose_count),
        help(
            "Every time step must give the world pose of every participant, in participant order."
        )
    )]
    PoseCount { demonstration: String, step: usize, expected: usize, found: usize },

    /// A held pair names a participant that does not exist or cannot hold or be held.
    #[error("demonstration `{demonstration}` step {step}: `{gripper}` cannot hold `{held}`")]
    #[diagnostic(
        code(lamp::learn::bad_held),
        help("Only a gripper robot part can hold, and only a movable object can be held.")
    )]
    BadHeld { demonstration: String, step: usize, gripper: String, held: String },

    /// A held pair index is out of range.
    #[error(
        "demonstration `{demonstration}` step {step}: held pair ({gripper}, {held}) is out of range"
    )]
    #[diagnostic(code(lamp::learn::held_out_of_range))]
    HeldOutOfRange { demonstration: String, step: usize, gripper: usize, held: usize },

    /// A pose is not finite.
    #[error(
        "demonstration `{demonstration}` step {step}: the pose of `{participant}` is not finite"
    )]
    #[diagnostic(code(lamp::learn::non_finite_pose))]
    NonFinitePose { demonstration: String, step: usize, participant: String },

    /// Two participants share a name, so atoms would be ambiguous.
    #[error("demonstration `{demonstration}` has two participants named `{name}`")]
    #[diagnostic(code(lamp::learn::duplicate_participant))]
    DuplicateParticipant { demonstration: String, name: String },

    /// One type is used with two different roles.
    #[error("type `{type_name}` is used both as {first} and as {second}")]
    #[diagnostic(
        code(lamp::learn::conflicting_role),
        help("A type is a robot part, a static object or a movable object everywhere.")
    )]
    ConflictingRole { type_name: String, first: String, second: String },

    /// A type or participant name cannot become a PDDL identifier.
    #[error("`{name}` is not a usable name (letters, digits, `-` and `_`, starting with a letter)")]
    #[diagnostic(code(lamp::learn::bad_name))]
    BadName { name: String },

    /// A learning setting is outside its domain.
    #[error("invalid learning setting for {pair}: {reason}")]
    #[diagnostic(code(lamp::learn::bad_setting))]
    BadSetting { pair: String, reason: String },

    /// Thresholding found no critical region for any type pair.
    #[error("no relational critical region was found in {demonstrations} demonstrations")]
    #[diagnostic(
        code(lamp::learn::no_regions),
        help(
            "Record more demonstrations, lower the threshold θ, or use coarser bins: no cell was visited by enough demonstrations."
        )
    )]
    NoRegions { demonstrations: usize },

    /// The model of a region could not be built or is invalid.
    #[error("the model of region {relation} failed: {reason}")]
    #[diagnostic(code(lamp::learn::region_model))]
    Mixture { relation: String, reason: String },

    /// The learned domain could not be written as PDDL.
    #[error("writing PDDL failed: {reason}")]
    #[diagnostic(code(lamp::learn::emit))]
    Emit { reason: String },

    /// A sampler artifact or a snapshot that cannot be read.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Abstraction(#[from] lamp_abstraction::AbstractionError),
}
