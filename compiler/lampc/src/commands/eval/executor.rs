//! The parent's side of a solve: the command that runs it (`--executor`, by default this lampc's
//! `eval-worker`), started in a process group of its own, fed the job on its standard input, and
//! read for one result row on its standard output; stopped (its whole group) on an interrupt or
//! long after its time limit; and the diagnostics when the command breaks that protocol.
//!
//! A command that cannot start, fails, or prints no result row is an infrastructure failure,
//! never a row of the problem: the scheduler tries the solve once more, then stops the
//! evaluation with the [`ExecutorError`] (`docs/evaluation.md`, "Executors").

use std::collections::BTreeSet;
use std::ffi::OsString;
use std::io::Write as _;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use lamp_eval::{Outcome, SolveResult};

use super::worker::WORKER_COMMAND;

/// How long after its own time limit a worker may take to stop before it is killed: the solver
/// polls its cancellation check between steps, and a motion call or a grounding can take seconds.
const KILL_GRACE: Duration = Duration::from_secs(30);
/// How long a stopped command has between SIGTERM and SIGKILL: `srun` forwards SIGTERM to its
/// job step and waits for it to end, which SIGKILL would leave running on the cluster; a local
/// worker ends on SIGTERM at once.
const STOP_GRACE: Duration = Duration::from_secs(5);
/// How long the parent waits for a command's pipes to close after the command ended: a process
/// it left behind (a daemon a wrapper script started) may hold them open for ever.
const PIPE_GRACE: Duration = Duration::from_secs(5);
/// How often the parent looks at a running command.
const POLL: Duration = Duration::from_millis(20);
/// The most of a command's standard output kept: a result row is a few kilobytes at most, and a
/// command that prints without end must not fill the memory.
const STDOUT_LIMIT: usize = 16 << 20;
/// The most of a command's standard error kept (its end).
const STDERR_LIMIT: usize = 64 << 10;
/// Lines of a failed command's standard error shown.
const STDERR_LINES: usize = 5;
/// Bytes of standard output shown when it holds no result row.
const STDOUT_SHOWN: usize = 200;

/// The variable that sizes a process's rayon pool.
const POOL_THREADS: &str = "RAYON_NUM_THREADS";

/// The command that runs each solve.
pub(super) struct Executor {
    program: PathBuf,
    arguments: Vec<OsString>,
    /// The command as the user wrote it (or `lampc eval-worker`), for messages.
    text: String,
    /// The threads each solve's pool may use, when the solves share this machine's cores
    /// (`RAYON_NUM_THREADS`, unless the user set it): a command of the user's may run them
    /// anywhere, so it is left to choose.
    pool_threads: Option<usize>,
}

impl Executor {
    /// This lampc's `eval-worker`: the default. With `jobs` solves at once, each solve's pool gets
    /// its share of the cores (at least one thread): more threads than cores only wait on each
    /// other, and a solve's result is the same on any number.
    pub(super) fn local(jobs: usize) -> Result<Executor, ExecutorError> {
        let text = format!("lampc {WORKER_COMMAND}");
        let program = std::env::current_exe()
            .map_err(|source| ExecutorError::Start { command: text.clone(), source })?;
        let cores = std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get);
        let pool_threads = Some((cores / jobs.max(1)).max(1));
        Ok(Executor { program, arguments: vec![WORKER_COMMAND.into()], text, pool_threads })
    }

    /// `--executor`'s command: split into words as a POSIX shell would (quotes and backslashes,
    /// no variables, globs or pipes), the first word the program.
    pub(super) fn parse(text: &str) -> Result<Executor, ExecutorError> {
        let syntax = |reason: &str| ExecutorError::Syntax {
            command: text.to_string(),
            reason: reason.to_string(),
        };
        let words = shlex::split(text).ok_or_else(|| syntax("a quote is not closed"))?;
        let mut words = words.into_iter();
        let program = words.next().ok_or_else(|| syntax("it has no program"))?;
        Ok(Executor {
            program: PathBuf::from(program),
            arguments: words.map(OsString::from).collect(),
            text: text.to_string(),
            pool_threads: None,
        })
    }

    /// The command as written.
    pub(super) fn text(&self) -> &str {
        &self.text
    }

    /// Refuses a program that is neither a file nor on `PATH` before any work, with why: a typo
    /// should not cost generating and learning first.
    pub(super) fn check_program(&self) -> Result<(), ExecutorError> {
        let start = |source| ExecutorError::Start { command: self.text.clone(), source };
        // A program with a folder in its name is run from there, a bare name from `PATH`.
        if self.program.components().count() > 1 {
            let metadata = std::fs::metadata(&self.program).map_err(start)?;
            if !metadata.is_file() {
                let source =
                    std::io::Error::other(format!("{} is not a file", self.program.display()));
                return Err(start(source));
            }
            return Ok(());
        }
        let on_path = std::env::var_os("PATH").is_some_and(|path| {
            std::env::split_paths(&path).any(|folder| folder.join(&self.program).is_file())
        });
        if on_path {
            return Ok(());
        }
        Err(start(std::io::Error::new(
            std::io::ErrorKind::NotFound,
            format!("`{}` is in no folder of PATH", self.program.display()),
        )))
    }

    fn command(&self) -> Command {
        let mut command = Command::new(&self.program);
        command.args(&self.arguments);
        if let Some(threads) = self.pool_threads
            && std::env::var_os(POOL_THREADS).is_none()
        {
            command.env(POOL_THREADS, threads.to_string());
        }
        command
    }
}

/// Why a solve's command gave no result row: an infrastructure failure, not the problem's.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub(super) enum ExecutorError {
    #[error("`--executor` `{command}` is not a command: {reason}")]
    #[diagnostic(
        code(lamp::eval::executor_syntax),
        help(
            "Write the command as for a shell, e.g. `--executor \"srun -N1 -n1 lampc eval-worker\"`: \
             words split at spaces, quotes around a word with spaces; no pipes or variables (put \
             those in a script and give its path)."
        )
    )]
    Syntax { command: String, reason: String },

    #[error("cannot start the executor `{command}`")]
    #[diagnostic(
        code(lamp::eval::executor_start),
        help(
            "The first word of `--executor` is the program to run for each solve: give its path, \
             or put it on PATH, and make it executable. Without `--executor`, this lampc's \
             `eval-worker` runs each solve."
        )
    )]
    Start {
        command: String,
        #[source]
        source: std::io::Error,
    },

    #[error("the executor `{command}` failed ({status}) without a result row for `{problem}`")]
    #[diagnostic(
        code(lamp::eval::executor_failed),
        help(
            "The command must run `lampc eval-worker` (the same lampc build) on the job it reads \
             from its standard input and exit with 0; its standard error says why it did not."
        )
    )]
    Failed {
        command: String,
        problem: String,
        status: String,
        #[source]
        output: Output,
    },

    #[error("the executor `{command}` printed no result row for `{problem}`")]
    #[diagnostic(
        code(lamp::eval::executor_output),
        help(
            "The command must write the one JSON line `lampc eval-worker` writes on its standard \
             output (other lines before it are ignored)."
        )
    )]
    NoRow {
        command: String,
        problem: String,
        #[source]
        output: Output,
    },

    #[error("cannot write the job of `{problem}`: {reason}")]
    #[diagnostic(code(lamp::eval::job))]
    Job { problem: String, reason: String },
}

impl ExecutorError {
    /// Whether trying the solve again may help: not when the command cannot start at all.
    pub(super) fn may_pass(&self) -> bool {
        matches!(self, ExecutorError::Failed { .. } | ExecutorError::NoRow { .. })
    }
}

/// What a failed command printed: the first bytes of its standard output and the end of its
/// standard error.
#[derive(Debug, thiserror::Error)]
#[error("{text}")]
pub(super) struct Output {
    text: String,
}

impl Output {
    fn new(stdout: &[u8], stderr: &[u8]) -> Output {
        let shown = &stdout[..stdout.len().min(STDOUT_SHOWN)];
        let more = if stdout.len() > shown.len() { "…" } else { "" };
        let stdout = if stdout.is_empty() {
            "its standard output was empty".to_string()
        } else {
            format!("its standard output began {:?}{more}", String::from_utf8_lossy(shown))
        };
        let stderr = String::from_utf8_lossy(stderr);
        let lines: Vec<&str> = stderr.lines().filter(|line| !line.trim().is_empty()).collect();
        let tail = &lines[lines.len().saturating_sub(STDERR_LINES)..];
        let stderr = if tail.is_empty() {
            "its standard error was empty".to_string()
        } else {
            format!("its standard error ended: {}", tail.join(" / "))
        };
        Output { text: format!("{stdout}; {stderr}") }
    }
}

/// How a solve's command ended, as the parent sees it.
pub(super) enum Finished {
    /// It wrote a result (a time limit it overran by [`KILL_GRACE`] counts as a timeout).
    Result(SolveResult),
    /// It gave no result: the command's failure, not the problem's (never journaled).
    Broken(ExecutorError),
    /// The evaluation was stopped and the command with it: no row.
    Stopped,
}

/// The process groups of the commands running now, so that a second Ctrl-C, which ends lampc at
/// once, can end them too: in groups of their own, they no longer get the terminal's signals.
static RUNNING: Mutex<BTreeSet<u32>> = Mutex::new(BTreeSet::new());

/// Kills every running command's process group (the second Ctrl-C, just before lampc exits).
pub(super) fn kill_running() {
    let running = RUNNING.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    for &group in running.iter() {
        signal_group(group, "KILL");
    }
}

/// Runs `executor` on `job` (JSON) for `problem` and waits for it, stopping it when `stop` is set
/// or when it overruns `timeout` by [`KILL_GRACE`].
pub(super) fn run(
    executor: &Executor,
    job: String,
    problem: &str,
    timeout: Option<f64>,
    stop: &AtomicBool,
) -> Finished {
    let mut command = executor.command();
    command.stdin(Stdio::piped()).stdout(Stdio::piped()).stderr(Stdio::piped());
    own_process_group(&mut command);
    let mut child = match command.spawn() {
        Ok(child) => child,
        Err(source) => {
            return Finished::Broken(ExecutorError::Start {
                command: executor.text.clone(),
                source,
            });
        }
    };
    let group = child.id();
    RUNNING.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).insert(group);
    let finished = watch(executor, &mut child, job, problem, timeout, stop);
    RUNNING.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).remove(&group);
    finished
}

fn watch(
    executor: &Executor,
    child: &mut Child,
    job: String,
    problem: &str,
    timeout: Option<f64>,
    stop: &AtomicBool,
) -> Finished {
    // Written on a thread of its own: a command that does not read its input (a broken one)
    // must not block the parent, which still has to watch the clock and the interrupt. It ends
    // when the command reads the job or its input closes.
    if let Some(mut stdin) = child.stdin.take() {
        std::thread::spawn(move || {
            let _ = stdin.write_all(job.as_bytes());
        });
    }
    let stdout = child.stdout.take().map(|pipe| reader(pipe, Keep::Head(STDOUT_LIMIT)));
    let stderr = child.stderr.take().map(|pipe| reader(pipe, Keep::Tail(STDERR_LIMIT)));
    let hard_limit = timeout.map(|seconds| Duration::from_secs_f64(seconds) + KILL_GRACE);
    let started = Instant::now();
    let mut overran = false;
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) => {}
            Err(_) => break None,
        }
        if stop.load(Ordering::Relaxed) {
            end_group(child);
            return Finished::Stopped;
        }
        if hard_limit.is_some_and(|limit| started.elapsed() >= limit) {
            end_group(child);
            overran = true;
            break None;
        }
        std::thread::sleep(POLL);
    };
    if overran {
        let mut result = SolveResult::failed(
            Outcome::Timeout,
            format!(
                "killed {} s after the time limit, which it did not notice",
                KILL_GRACE.as_secs()
            ),
        );
        result.seconds_solving = Some(started.elapsed().as_secs_f64());
        return Finished::Result(result);
    }
    let pipes_closed = Instant::now() + PIPE_GRACE;
    let [stdout, stderr] = [stdout, stderr].map(|reader| collect(reader, pipes_closed));
    let succeeded = status.is_some_and(|status| status.success());
    if succeeded && let Some(result) = result_row(&stdout) {
        return Finished::Result(result);
    }
    if stop.load(Ordering::Relaxed) {
        return Finished::Stopped;
    }
    let output = Output::new(&stdout, &stderr);
    let (command, problem) = (executor.text.clone(), problem.to_string());
    if succeeded {
        return Finished::Broken(ExecutorError::NoRow { command, problem, output });
    }
    let status = status.map_or_else(|| "no exit status".to_string(), |status| status.to_string());
    Finished::Broken(ExecutorError::Failed { command, problem, status, output })
}

/// The result row of a command's standard output: its last line that is one (a wrapper may log
/// before it).
fn result_row(stdout: &[u8]) -> Option<SolveResult> {
    let text = String::from_utf8_lossy(stdout);
    text.lines().rev().find_map(|line| serde_json::from_str::<SolveResult>(line).ok())
}

/// Which part of a pipe's bytes to keep.
#[derive(Clone, Copy)]
enum Keep {
    Head(usize),
    Tail(usize),
}

/// Reads a pipe to its end on its own thread, so that a chatty command never blocks on it,
/// keeping at most the given part.
fn reader(mut pipe: impl std::io::Read + Send + 'static, keep: Keep) -> JoinHandle<Vec<u8>> {
    std::thread::spawn(move || {
        let mut kept = Vec::new();
        let mut buffer = [0; 8192];
        loop {
            let read = match pipe.read(&mut buffer) {
                Ok(0) | Err(_) => return kept,
                Ok(read) => read,
            };
            kept.extend_from_slice(&buffer[..read]);
            match keep {
                Keep::Head(limit) => kept.truncate(limit),
                Keep::Tail(limit) => {
                    let excess = kept.len().saturating_sub(limit);
                    kept.drain(..excess);
                }
            }
        }
    })
}

/// A reader's bytes once its pipe closed, or none when it stays open past `deadline`.
fn collect(reader: Option<JoinHandle<Vec<u8>>>, deadline: Instant) -> Vec<u8> {
    let Some(reader) = reader else { return Vec::new() };
    while !reader.is_finished() && Instant::now() < deadline {
        std::thread::sleep(POLL);
    }
    if reader.is_finished() { reader.join().unwrap_or_default() } else { Vec::new() }
}

/// The command leads a process group of its own, so that what it starts (a worker under `srun`,
/// a script's children) is stopped with it.
#[cfg(unix)]
fn own_process_group(command: &mut Command) {
    use std::os::unix::process::CommandExt as _;
    command.process_group(0);
}

#[cfg(not(unix))]
fn own_process_group(_command: &mut Command) {}

/// Ends a command and its process group: SIGTERM, then SIGKILL after [`STOP_GRACE`] (elsewhere
/// than on Unix, a kill of the command alone); then reaps it.
fn end_group(child: &mut Child) {
    #[cfg(unix)]
    {
        let group = child.id();
        signal_group(group, "TERM");
        let deadline = Instant::now() + STOP_GRACE;
        while Instant::now() < deadline {
            if matches!(child.try_wait(), Ok(Some(_)) | Err(_)) {
                // The leader is gone; what it started in its group may not be.
                signal_group(group, "KILL");
                return;
            }
            std::thread::sleep(POLL);
        }
        signal_group(group, "KILL");
    }
    let _ = child.kill();
    let _ = child.wait();
}

/// Sends `signal` to the process group `group` (Unix; elsewhere nothing).
fn signal_group(group: u32, signal: &str) {
    // The standard library signals only its own child; `kill` signals a group without unsafe
    // code here.
    if cfg!(unix) {
        let _ = Command::new("kill")
            .args(["-s", signal, "--", &format!("-{group}")])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn a_command_is_split_into_words_as_a_shell_would() {
        let executor = Executor::parse("srun -N1 -n1 'my lampc' eval-worker").expect("parses");
        assert_eq!(executor.program, Path::new("srun"));
        assert_eq!(executor.arguments, ["-N1", "-n1", "my lampc", "eval-worker"]);
        assert_eq!(executor.text(), "srun -N1 -n1 'my lampc' eval-worker");
        let quoted = Executor::parse(r#"sh -c "cat >/dev/null; echo nope""#).expect("parses");
        assert_eq!(quoted.arguments, ["-c", "cat >/dev/null; echo nope"]);
        for (text, reason) in [("", "it has no program"), ("sh -c 'echo", "a quote is not closed")]
        {
            match Executor::parse(text) {
                Err(ExecutorError::Syntax { reason: said, .. }) => assert_eq!(said, reason),
                _ => panic!("`{text}` is refused"),
            }
        }
    }

    #[test]
    fn a_program_that_is_not_there_is_refused_before_any_work() {
        let missing = Executor::parse("/nonexistent/lampc-executor eval-worker").expect("parses");
        assert!(matches!(missing.check_program(), Err(ExecutorError::Start { .. })));
        let on_path = Executor::parse("sh -c true").expect("parses");
        assert!(on_path.check_program().is_ok());
        let local = Executor::local(2).expect("this test binary");
        assert!(local.check_program().is_ok());
        let threads = |executor: &Executor| {
            let command = executor.command();
            let found = command.get_envs().find(|(name, _)| *name == POOL_THREADS);
            found.and_then(|(_, value)| value).map(|value| value.to_string_lossy().into_owned())
        };
        if std::env::var_os(POOL_THREADS).is_none() {
            let cores = std::thread::available_parallelism().map_or(1, usize::from);
            assert_eq!(threads(&local).as_deref(), Some((cores / 2).max(1).to_string().as_str()));
            let alone = Executor::local(1).expect("this test binary");
            assert_eq!(threads(&alone).as_deref(), Some(cores.to_string().as_str()));
        }
        assert_eq!(threads(&on_path), None, "a command of the user's chooses for itself");
    }

    #[test]
    fn output_without_a_row_shows_its_first_bytes_and_the_end_of_standard_error() {
        let output = Output::new(b"nope\n", b"one\n\ntwo\n");
        assert_eq!(
            output.to_string(),
            r#"its standard output began "nope\n"; its standard error ended: one / two"#
        );
        let long = Output::new(&[b'x'; 300], b"");
        assert!(long.to_string().contains(&format!("{}\"…;", "x".repeat(200))), "{long}");
        assert!(long.to_string().ends_with("its standard error was empty"));
        assert!(result_row(b"a log line\nnope\n").is_none());
        let row =
            serde_json::to_string(&SolveResult::failed(Outcome::NoPlan, "none")).expect("a row");
        let found = result_row(format!("a log line\n{row}\n").as_bytes()).expect("the row");
        assert_eq!(found.outcome, Outcome::NoPlan);
    }

    /// Stopping a command ends what it started too: the whole process group.
    #[cfg(target_os = "linux")]
    #[test]
    fn stopping_a_command_ends_its_process_group() {
        let scratch = tempfile::tempdir().expect("a scratch directory");
        let pid_file = scratch.path().join("pid");
        let script = format!("sleep 100 & echo $! > {}; wait", pid_file.display());
        let executor = Executor {
            program: "sh".into(),
            arguments: vec!["-c".into(), script.into()],
            text: "sh -c …".to_string(),
            pool_threads: None,
        };
        let stop = AtomicBool::new(false);
        std::thread::scope(|scope| {
            let running = scope.spawn(|| run(&executor, String::new(), "p", None, &stop));
            let started = Instant::now();
            let pid = loop {
                let text = std::fs::read_to_string(&pid_file).unwrap_or_default();
                if let Ok(pid) = text.trim().parse::<u32>() {
                    break pid;
                }
                assert!(started.elapsed() < Duration::from_secs(10), "the script never started");
                std::thread::sleep(POLL);
            };
            stop.store(true, Ordering::Relaxed);
            assert!(matches!(running.join().expect("returns"), Finished::Stopped));
            // The orphaned `sleep` is reaped by init; until then it is a zombie.
            let gone = || {
                std::fs::read_to_string(format!("/proc/{pid}/stat"))
                    .map_or(true, |stat| stat.contains(") Z "))
            };
            while !gone() {
                assert!(started.elapsed() < Duration::from_secs(10), "`sleep` {pid} runs on");
                std::thread::sleep(POLL);
            }
        });
        assert!(RUNNING.lock().expect("not poisoned").is_empty());
    }
}
