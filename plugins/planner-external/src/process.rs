//! Running the planner process in its scratch folder, under the request's time limit and the
//! host's cancellation, and killing its whole process tree when either cuts it short.

use std::fs::File;
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use lamp_plugin_api::HostServices;

use crate::error::ExternalError;
use crate::options::CommandLine;

/// How often a running planner is checked for its end, the clock and cancellation: short against
/// a planner's start-up (a tenth of a second or more), long enough to cost nothing.
const POLL_INTERVAL: Duration = Duration::from_millis(10);

/// The file in the scratch folder that receives the planner's standard output and error.
pub const LOG_FILE: &str = "planner.log";

/// Lines of the log quoted in an error.
const LOG_TAIL_LINES: usize = 20;

/// How a planner run ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Ending {
    /// The process exited with this code.
    Exited(i32),
    /// The process ended without an exit code (killed by a signal).
    Signalled(String),
    /// The time limit passed; the process tree was killed.
    TimedOut,
    /// The host asked to stop; the process tree was killed.
    Cancelled,
}

/// Runs `command` followed by `arguments` in `folder` until it ends, `time_limit` passes, or the
/// host cancels.
///
/// # Errors
/// [`ExternalError::Spawn`] when the program cannot start, [`ExternalError::Io`] when the log
/// cannot be created or the process cannot be waited for.
pub fn run(
    command: &CommandLine,
    arguments: &[String],
    folder: &Path,
    time_limit: Option<Duration>,
    host: &dyn HostServices,
) -> Result<Ending, ExternalError> {
    let log_path = folder.join(LOG_FILE);
    let io_error = |source| ExternalError::Io { path: log_path.display().to_string(), source };
    let log = File::create(&log_path).map_err(io_error)?;
    let log_for_errors = log.try_clone().map_err(io_error)?;
    let mut process = Command::new(&command.program);
    process
        .args(&command.arguments)
        .args(arguments)
        .current_dir(folder)
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(log_for_errors);
    own_process_group(&mut process);
    let mut child = process
        .spawn()
        .map_err(|source| ExternalError::Spawn { program: command.program.clone(), source })?;
    let started = Instant::now();
    loop {
        let status = child.try_wait().map_err(|source| wait_error(folder, source))?;
        if let Some(status) = status {
            return Ok(ending_of(status));
        }
        if host.is_cancelled() {
            kill_tree(&mut child);
            return Ok(Ending::Cancelled);
        }
        if time_limit.is_some_and(|limit| started.elapsed() >= limit) {
            kill_tree(&mut child);
            return Ok(Ending::TimedOut);
        }
        std::thread::sleep(POLL_INTERVAL);
    }
}

/// The last lines of the planner's log, for error messages.
#[must_use]
pub fn log_tail(folder: &Path) -> String {
    let text = std::fs::read_to_string(folder.join(LOG_FILE)).unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(LOG_TAIL_LINES)..].join("\n")
}

/// Whether the planner printed nothing (only white space) on stdout and stderr.
#[must_use]
pub fn log_is_empty(folder: &Path) -> bool {
    std::fs::read(folder.join(LOG_FILE)).is_ok_and(|bytes| bytes.trim_ascii().is_empty())
}

fn wait_error(folder: &Path, source: std::io::Error) -> ExternalError {
    ExternalError::Io { path: folder.display().to_string(), source }
}

fn ending_of(status: ExitStatus) -> Ending {
    match status.code() {
        Some(code) => Ending::Exited(code),
        None => Ending::Signalled(status.to_string()),
    }
}

/// The planner leads a process group of its own, so that the translator and search processes a
/// driver script starts can be killed with it.
#[cfg(unix)]
fn own_process_group(command: &mut Command) {
    use std::os::unix::process::CommandExt;
    command.process_group(0);
}

#[cfg(not(unix))]
fn own_process_group(_command: &mut Command) {}

/// Kills the planner and everything it started, then reaps it.
fn kill_tree(child: &mut Child) {
    #[cfg(unix)]
    {
        // The standard library can only signal the child itself; `kill` signals its group
        // (whose id is the child's pid, see `own_process_group`) without unsafe code here.
        let group = format!("-{}", child.id());
        let _ = Command::new("kill")
            .args(["-s", "KILL", "--", &group])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status();
    }
    // Either the group kill already ended it, or this is the only way left; both end in a reap.
    let _ = child.kill();
    let _ = child.wait();
}
