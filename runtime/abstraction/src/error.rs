//! Why an artifact or a snapshot cannot be read.

use miette::Diagnostic;
use thiserror::Error;

/// A sampler artifact that cannot be used, or a snapshot that does not fit its participants.
///
/// The codes are the learner's (`lamp::learn::*`): the same artifact is refused in the same words
/// whether the build or the run time reads it.
#[derive(Debug, Error, Diagnostic, Clone, PartialEq)]
pub enum AbstractionError {
    /// The model of a region is invalid.
    #[error("the model of region {relation} failed: {reason}")]
    #[diagnostic(code(lamp::learn::region_model))]
    Mixture { relation: String, reason: String },

    /// A sampler artifact of another format version.
    #[error(
        "the sampler artifact has format version {found}, this build reads version {supported}"
    )]
    #[diagnostic(
        code(lamp::learn::artifact_version),
        help("Rebuild the artifact with `lampc build`.")
    )]
    ArtifactVersion { found: u32, supported: u32 },

    /// A snapshot handed to the abstraction does not fit the participants.
    #[error("a snapshot has {found} poses for {expected} participants")]
    #[diagnostic(code(lamp::learn::snapshot_shape))]
    SnapshotShape { expected: usize, found: usize },
}
