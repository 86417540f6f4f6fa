//! Typed errors of writing and reading trajectory files.
//!
//! Every error names the file (its path, or the name the caller gave an in-memory source) and,
//! where it applies, the MCAP record or the step at fault.

use crate::codec::StepProblem;

/// Why a trajectory file could not be written or read.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum TrajectoryError {
    /// The operating system refused to open, read or write the file.
    #[error("cannot {action} {file}")]
    #[diagnostic(code(lamp::trajectory::io), help("check that the path exists and is accessible"))]
    Io {
        file: String,
        /// `open`, `create`, `read` or `write`.
        action: &'static str,
        #[source]
        source: std::io::Error,
    },

    /// The file ends before its MCAP footer: the writer stopped before `finish`.
    #[error(
        "{file} is truncated: it ends inside MCAP record {record}, after {steps} complete steps"
    )]
    #[diagnostic(
        code(lamp::trajectory::truncated),
        help("the program that wrote it probably stopped early; write the file again")
    )]
    Truncated { file: String, record: u64, steps: u64 },

    /// The bytes are damaged: a bad checksum, magic, record or message encoding.
    #[error("{file} is corrupt at MCAP record {record} (after {steps} steps): {reason}")]
    #[diagnostic(
        code(lamp::trajectory::corrupt),
        help("the file is damaged; write or copy it again")
    )]
    Corrupt { file: String, record: u64, steps: u64, reason: String },

    /// The file is MCAP but not a lamp trajectory this reader understands (missing header record,
    /// another schema or encoding on the world topic, another format version).
    #[error("{file} is not a lamp trajectory: {reason}")]
    #[diagnostic(
        code(lamp::trajectory::schema),
        help(
            "a lamp trajectory has a `lamp` metadata record before a `/lamp/world` topic of `lamp_msgs/msg/WorldStep` in CDR; see docs/formats.md"
        )
    )]
    Schema { file: String, reason: String },

    /// The header (the `lamp` metadata record) is malformed, or a header given to the writer
    /// cannot be stored.
    #[error("{file}: invalid trajectory header: {reason}")]
    #[diagnostic(
        code(lamp::trajectory::header),
        help("names must be non-empty, without whitespace, and unique within their list")
    )]
    Header { file: String, reason: String },

    /// A step disagrees with the header (counts, unknown held body) or with the previous step.
    #[error("{file}, step {step}: {reason}")]
    #[diagnostic(code(lamp::trajectory::inconsistent))]
    Inconsistent { file: String, step: u64, reason: String },

    /// A step holds a value no trajectory can have (a non-finite number, a non-unit quaternion,
    /// a negative or too large time).
    #[error("{file}, step {step}: {reason}")]
    #[diagnostic(
        code(lamp::trajectory::invalid_value),
        help("positions and configurations must be finite and quaternions of unit norm")
    )]
    InvalidValue { file: String, step: u64, reason: String },
}

impl TrajectoryError {
    /// Wraps a step problem with the file name, step index and record index.
    pub(crate) fn from_step(file: &str, step: u64, record: u64, problem: StepProblem) -> Self {
        let file = file.to_string();
        match problem {
            StepProblem::Corrupt(reason) => Self::Corrupt { file, record, steps: step, reason },
            StepProblem::Inconsistent(reason) => Self::Inconsistent { file, step, reason },
            StepProblem::InvalidValue(reason) => Self::InvalidValue { file, step, reason },
        }
    }
}
