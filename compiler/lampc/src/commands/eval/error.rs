//! Why an evaluation stops before its figures are written, besides the errors of the libraries
//! it calls (which reach the user as they are).

use std::path::PathBuf;

use lamp_spec::limits::RangeError;

#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub(super) enum EvaluationError {
    #[error("{spec_file}: `{pattern}` matches no problem; the spec has: {names}")]
    #[diagnostic(
        code(lamp::eval::problems),
        help("`--problems` takes names or globs, comma-separated")
    )]
    NoProblem { spec_file: String, pattern: String, names: String },

    #[error("{spec_file}: `{pattern}` is not a name or glob: {reason}")]
    #[diagnostic(code(lamp::eval::problems))]
    BadPattern { spec_file: String, pattern: String, reason: String },

    #[error("`--demos`: {0}")]
    #[diagnostic(code(lamp::eval::demos))]
    Demos(RangeError),

    #[error(
        "`--out` {out} is inside the model folder {model} of a build, which the next `lampc build` \
         replaces whole, results and journal included"
    )]
    #[diagnostic(code(lamp::eval::out_in_model), help("give `--out` a folder outside it"))]
    OutInModel { out: String, model: String },

    #[error(
        "{spec_file}: {findings} finding(s) in the initial scenes of the problems to evaluate, \
         which the solver cannot start from; nothing was evaluated"
    )]
    #[diagnostic(code(lamp::eval::scenes))]
    Scenes { spec_file: String, findings: usize },

    #[error("cannot read the journal {path}: {reason}")]
    #[diagnostic(
        code(lamp::eval::journal),
        help("move it away (a new journal is started), or give `--out` another folder")
    )]
    Journal { path: String, reason: String },

    #[error("{wanted} demonstrations are more than the simulator numbers")]
    #[diagnostic(code(lamp::eval::demos))]
    TooManyDemonstrations { wanted: usize },

    #[error("cannot write {what}: {reason}")]
    #[diagnostic(code(lamp::eval::encode))]
    Encode { what: &'static str, reason: String },

    /// A file operation failed; `consequence` says what it left, when that needs saying.
    #[error("cannot {action} {}: {error}{consequence}", path.display())]
    #[diagnostic(code(lamp::eval::io))]
    Io { action: &'static str, path: PathBuf, error: std::io::Error, consequence: String },
}

impl EvaluationError {
    /// `action` on `path` failed with `error`.
    pub(super) fn io(
        action: &'static str,
        path: impl Into<PathBuf>,
        error: std::io::Error,
    ) -> Self {
        EvaluationError::Io { action, path: path.into(), error, consequence: String::new() }
    }
}
