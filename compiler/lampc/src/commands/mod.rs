//! One module per subcommand: its arguments and what it does. Each owns its own IO.

pub(crate) mod build;
pub(crate) mod demos;
pub(crate) mod eval;
mod failure;
pub(crate) mod render;
pub(crate) mod solve;
