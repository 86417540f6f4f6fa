//! Why an evaluation cannot be set up as asked.

use miette::Diagnostic;
use thiserror::Error;

/// An evaluation request that cannot be met, with a stable code.
#[derive(Debug, Error, Diagnostic, Clone, PartialEq, Eq)]
pub enum EvalError {
    /// `--demos` is not a comma-separated list of positive whole numbers.
    #[error("`{text}` is not a list of demonstration counts")]
    #[diagnostic(
        code(lamp::eval::counts),
        help(
            "Give positive whole numbers separated by commas, each once, for example `--demos 200,100,50`."
        )
    )]
    Counts { text: String },
    /// A count is larger than the pool of demonstrations.
    #[error("{count} demonstrations asked for, but the pool has only {pool}")]
    #[diagnostic(
        code(lamp::eval::pool_too_small),
        help(
            "Lower the largest `--demos` count, or add demonstration files to the spec's source (a simulated source is topped up automatically)."
        )
    )]
    PoolTooSmall { count: usize, pool: usize },
}
