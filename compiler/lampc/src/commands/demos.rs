//! `lampc demos`: Generate simulated demonstrations as MCAP files.

use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `lampc demos`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The `.lamp` spec file.
    pub(crate) spec: PathBuf,
}

pub(crate) fn run(_args: &Args) -> ExitCode {
    crate::not_yet("demos")
}
