//! One module per subcommand: its arguments and what it does. Each owns its own IO but for how
//! it ends: it returns an [`Outcome`], which `main` alone renders.

pub(crate) mod build;
pub(crate) mod demos;
pub(crate) mod eval;
mod failure;
pub(crate) mod render;
pub(crate) mod solve;

pub(crate) use failure::{EXIT_INTERRUPTED, Failure, Finished, Stopped};

/// What every subcommand returns, for `main` to render.
pub(crate) type Outcome = Result<Finished, Stopped>;
