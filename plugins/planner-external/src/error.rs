//! Why an external planner call produced no answer.

use thiserror::Error;

/// How to install the planners this plugin finds by itself.
pub const INSTALL_HELP: &str = "install Fast Downward with `python3 -m pip install up-fast-downward` \
     (and K* for more than one plan with `python3 -m pip install kstar-planner`), put \
     `fast-downward` on PATH, or set the plugin's `command` option to a Fast Downward driver";

/// An external planner call that produced no answer. "No plan" and "out of time" are statuses of
/// the response, not errors.
#[derive(Debug, Error, miette::Diagnostic)]
pub enum ExternalError {
    /// No planner was configured and none was found.
    #[error("no external planner found for {purpose} (tried {tried})")]
    #[diagnostic(code(lamp::planner::external::not_installed), help("{INSTALL_HELP}"))]
    NotInstalled {
        /// What the planner was needed for (one plan, or the top k).
        purpose: String,
        /// Everything that was looked for, in order.
        tried: String,
    },
    /// The configured or found program could not be started.
    #[error("cannot start the external planner `{program}`: {source}")]
    #[diagnostic(code(lamp::planner::external::spawn), help("{INSTALL_HELP}"))]
    Spawn {
        /// The program as configured or found.
        program: String,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// Writing the inputs, reading the plans or waiting for the process failed.
    #[error("external planner files in {path}: {source}")]
    #[diagnostic(code(lamp::planner::external::io))]
    Io {
        /// The file or folder concerned.
        path: String,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The planner stopped with an error of its own (a crash, a signal, an unknown exit code).
    #[error("the external planner `{command}` failed: {reason}\n{log}")]
    #[diagnostic(code(lamp::planner::external::failed))]
    Failed {
        /// The command that ran.
        command: String,
        /// The exit code's meaning, or the signal.
        reason: String,
        /// The end of the planner's output.
        log: String,
    },
    /// The planner ended without printing anything and without writing a plan: a command that
    /// is no planner (a wrapper that runs nothing, a wrong `command` option). Fast Downward and K*
    /// always print their log, so an exit code saying "unsolvable" or "done" without it is not
    /// believed: it would be reported as a goal the learned model cannot reach.
    #[error(
        "the external planner `{command}` produced no output: it exited with code {code}, printed nothing on stdout or stderr and wrote no plan"
    )]
    #[diagnostic(
        code(lamp::planner::external::no_output),
        help(
            "This says nothing about the goal, which was not found unreachable: check that the command runs a Fast Downward driver (run it by hand on a domain and a problem file; it prints its search log), or set the plugin's `command` option to one. {INSTALL_HELP}."
        )
    )]
    NoOutput {
        /// The command that ran.
        command: String,
        /// Its exit code.
        code: i32,
    },
    /// The host cancelled the call; the planner was stopped.
    #[error("the external planner was stopped because the run was cancelled")]
    #[diagnostic(code(lamp::planner::external::cancelled))]
    Cancelled,
    /// The planner wrote a plan file that is not a plan.
    #[error("the external planner wrote a plan that does not parse ({file}): {message}")]
    #[diagnostic(code(lamp::planner::external::plan_syntax))]
    PlanSyntax {
        /// The plan file's name.
        file: String,
        /// What is wrong with it.
        message: String,
    },
    /// The planner returned a plan that the domain does not allow or that misses the goal.
    #[error("the external planner returned an invalid plan ({file}): {message}")]
    #[diagnostic(
        code(lamp::planner::external::invalid_plan),
        help("the planner and lamp disagree on the task; report it with the domain and problem")
    )]
    InvalidPlan {
        /// The plan file's name.
        file: String,
        /// The validator's message.
        message: String,
    },
}
