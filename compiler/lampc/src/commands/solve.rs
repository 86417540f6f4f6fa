//! `lampc solve`: Plan, refine and write a validated trajectory for one problem.

use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `lampc solve`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The `.lamp` spec file.
    pub(crate) spec: PathBuf,
    /// The problem to solve, by name.
    #[arg(long)]
    pub(crate) problem: String,
}

pub(crate) fn run(_args: &Args) -> ExitCode {
    crate::not_yet("solve")
}
