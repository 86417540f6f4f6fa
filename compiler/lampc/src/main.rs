//! `lampc`: the command-line front end. It owns all terminal and file IO of the pipeline.

// The binary is the one place that talks to the terminal.
#![allow(clippy::print_stdout, clippy::print_stderr)]

mod build_folder;
mod builtin_plugins;
mod commands;
mod diagnostics;
mod files;
mod flags;
mod output;
mod plugin_setup;
mod solve_setup;
mod spec_input;
mod terminal;
mod viewable;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::commands::{Finished, Outcome, Stopped};

/// Learn symbolic world models from demonstrations and plan with them.
#[derive(Parser)]
#[command(name = "lampc", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Parse and check a spec; report every problem found.
    Check {
        /// The `.lamp` spec file.
        spec: PathBuf,
    },
    /// Generate simulated demonstrations as MCAP files.
    Demos(commands::demos::Args),
    /// Learn regions, relations and actions; write PDDL, samplers and a report.
    Build(commands::build::Args),
    /// Plan, refine and write a validated trajectory for one problem.
    Solve(commands::solve::Args),
    /// Evaluate a spec: success per test problem and per number of demonstrations.
    Eval(commands::eval::Args),
    /// One solve of an evaluation, its job read from standard input (used by `eval`).
    #[command(name = "eval-worker", hide = true)]
    EvalWorker,
    /// Draw a scene, a demonstration or a trajectory.
    Render(commands::render::Args),
}

/// Exit code for a spec with diagnostics.
pub(crate) const EXIT_DIAGNOSTICS: u8 = 1;

fn main() -> ExitCode {
    install_panic_hook();
    let cli = Cli::parse();
    let (name, outcome) = match cli.command {
        Command::Check { spec } => ("check", check(&spec)),
        Command::Demos(args) => ("demos", commands::demos::run(&args)),
        Command::Build(args) => ("build", commands::build::run(&args)),
        Command::Solve(args) => ("solve", commands::solve::run(&args)),
        Command::Eval(args) => ("eval", commands::eval::run(&args)),
        Command::EvalWorker => ("eval-worker", commands::eval::worker::run()),
        Command::Render(args) => ("render", commands::render::run(&args)),
    };
    match outcome {
        Ok(Finished::Done) => ExitCode::SUCCESS,
        Ok(Finished::Partial) => ExitCode::from(commands::solve::EXIT_PARTIAL),
        Err(stopped) => {
            stopped.print(name, terminal::colour());
            ExitCode::from(stopped.exit_code())
        }
    }
}

fn check(spec: &std::path::Path) -> Outcome {
    let outcome = lamp_lang::check(spec, &files::DiskLoader);
    let colour = crate::terminal::colour();
    eprint!("{}", diagnostics::render_all(&outcome, colour, terminal_width()));
    let dir = spec.parent().filter(|dir| !dir.as_os_str().is_empty()).unwrap_or(Path::new("."));
    // The scenes as the world builds them: an object in the air or two bodies overlapping is as
    // much a broken spec as a misspelt name, and is said here rather than first by the build.
    let scene_errors =
        outcome.spec.as_ref().map_or(0, |checked| {
            match lamp_world::SpecWorld::load(dir, checked) {
                Ok(world) => {
                    let located = (&outcome.places, &outcome.sources);
                    spec_input::refuse_scenes(checked, located, &world, None, colour)
                }
                Err(error) => {
                    eprint!("{}", diagnostics::render_error(&error, colour));
                    1
                }
            }
        });
    match outcome.spec.filter(|_| scene_errors == 0) {
        Some(spec) => {
            let problems = spec.problems.len();
            eprintln!(
                "{}: ok (domain `{}`, {} problem(s))",
                spec_name(&outcome.sources),
                spec.domain,
                problems
            );
            Ok(Finished::Done)
        }
        None => {
            let count = outcome.diagnostics.len() + scene_errors;
            eprintln!("{}: {count} error(s)", spec_name(&outcome.sources));
            Err(Stopped::said())
        }
    }
}

fn spec_name(sources: &lamp_lang::SourceMap) -> String {
    sources.name(lamp_lang::FileId(0)).to_string()
}

fn terminal_width() -> usize {
    std::env::var("COLUMNS").ok().and_then(|c| c.parse().ok()).unwrap_or(100)
}

/// A panic is a bug in lampc, never the user's fault: say so and ask for a report.
fn install_panic_hook() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        eprintln!(
            "internal error: lampc {} crashed. This is a bug in lampc, not in your input; \
             please report it with the spec that triggered it.",
            env!("CARGO_PKG_VERSION")
        );
        default(info);
    }));
}
