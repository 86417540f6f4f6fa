//! Running the solves: one thread learns the subsets' models in order, while up to `--jobs`
//! worker processes solve the problems of the subsets learned so far. Each finished solve is
//! handed to the caller at once (which journals it); an interrupt stops learning, kills the
//! running workers and drops their solves.

use std::collections::{BTreeMap, VecDeque};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use lamp_eval::{Outcome, SolveResult};

use super::journal::Key;
use super::worker::{self, Finished, Job};

/// How often the scheduler looks for finished solves, learned subsets and an interrupt.
const POLL: Duration = Duration::from_millis(50);

/// A subset to learn, with the problems still to solve with its model.
pub(super) struct SubsetWork {
    pub(super) digest: lamp_build::Digest,
    /// Indices into the pool, ascending.
    pub(super) indices: Vec<usize>,
    pub(super) problems: Vec<String>,
}

/// A subset's model as text, or why learning failed.
pub(super) struct Learned {
    pub(super) digest: String,
    pub(super) seconds: f64,
    pub(super) model: Result<Model, String>,
    pub(super) problems: Vec<String>,
}

/// The artifacts a solve reads.
pub(super) struct Model {
    pub(super) domain: String,
    pub(super) samplers: String,
    /// Per problem: its PDDL, or why the build wrote none.
    pub(super) problems: BTreeMap<String, Result<String, String>>,
}

/// What stays the same for every solve.
pub(super) struct Settings<'a> {
    pub(super) spec: &'a std::path::Path,
    /// The spec's text as checked when the evaluation started, handed to every worker.
    pub(super) spec_text: &'a str,
    pub(super) seed: u64,
    pub(super) timeout: Option<f64>,
    pub(super) jobs: usize,
}

/// A finished solve: its key, what it reported, the subset's learning time, and whether it is a
/// property of the solve (to journal) or of the run (a crashed worker).
pub(super) struct Done {
    pub(super) key: Key,
    pub(super) result: SolveResult,
    pub(super) seconds_learning: f64,
    pub(super) journal: bool,
}

/// Learns every subset of `work` with `learn` and solves its problems; `started` is told each
/// solve's problem as it starts, `done` each result as it finishes. Returns whether it ran to
/// the end (false after an interrupt).
pub(super) fn run(
    settings: &Settings<'_>,
    work: Vec<SubsetWork>,
    learn: &(dyn Fn(&SubsetWork) -> Learned + Sync),
    interrupted: &(dyn Fn() -> bool + Sync),
    started: &mut dyn FnMut(&str),
    done: &mut dyn FnMut(Done),
) -> bool {
    let stop = AtomicBool::new(false);
    std::thread::scope(|scope| {
        let (learned_tx, learned_rx) = mpsc::sync_channel::<Learned>(1);
        let stop = &stop;
        scope.spawn(move || {
            for subset in &work {
                if stop.load(Ordering::Relaxed) || learned_tx.send(learn(subset)).is_err() {
                    return;
                }
            }
        });
        let (finished_tx, finished_rx) = mpsc::channel::<(Key, f64, Finished)>();
        let mut ready: VecDeque<(Arc<Learned>, String)> = VecDeque::new();
        let mut learner_done = false;
        let mut running = 0;
        loop {
            if interrupted() {
                stop.store(true, Ordering::Relaxed);
            }
            let stopping = stop.load(Ordering::Relaxed);
            if !stopping {
                while !learner_done && ready.len() < settings.jobs {
                    match learned_rx.try_recv() {
                        Ok(learned) => queue(Arc::new(learned), &mut ready, done),
                        Err(mpsc::TryRecvError::Empty) => break,
                        Err(mpsc::TryRecvError::Disconnected) => learner_done = true,
                    }
                }
                while running < settings.jobs {
                    let Some((learned, problem)) = ready.pop_front() else { break };
                    let key = (learned.digest.clone(), problem.clone());
                    let job = match job_text(settings, &learned, &problem) {
                        Ok(job) => job,
                        Err(reason) => {
                            let result = SolveResult::failed(Outcome::Error, reason);
                            let seconds_learning = learned.seconds;
                            done(Done { key, result, seconds_learning, journal: false });
                            continue;
                        }
                    };
                    started(&problem);
                    running += 1;
                    let finished_tx = finished_tx.clone();
                    let seconds = learned.seconds;
                    let timeout = settings.timeout;
                    scope.spawn(move || {
                        let finished = worker::run_worker(&job, timeout, stop);
                        let _ = finished_tx.send((key, seconds, finished));
                    });
                }
            }
            if running == 0 && (stopping || (learner_done && ready.is_empty())) {
                break;
            }
            match finished_rx.recv_timeout(POLL) {
                Ok((key, seconds_learning, finished)) => {
                    running -= 1;
                    match finished {
                        Finished::Result(result) => {
                            done(Done { key, result, seconds_learning, journal: true })
                        }
                        Finished::Crashed(reason) => done(Done {
                            key,
                            result: SolveResult::failed(Outcome::Error, reason),
                            seconds_learning,
                            journal: false,
                        }),
                        Finished::Stopped => {}
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout | mpsc::RecvTimeoutError::Disconnected) => {}
            }
        }
        // Dropping the receiver ends a learner blocked on sending.
        drop(learned_rx);
        !stop.load(Ordering::Relaxed)
    })
}

/// Queues the problems of a learned subset; a failed build ends them at once.
fn queue(
    learned: Arc<Learned>,
    ready: &mut VecDeque<(Arc<Learned>, String)>,
    done: &mut dyn FnMut(Done),
) {
    for problem in &learned.problems {
        let key = (learned.digest.clone(), problem.clone());
        let failed = |reason: String| Done {
            key: key.clone(),
            result: SolveResult::failed(Outcome::BuildFailed, reason),
            seconds_learning: learned.seconds,
            journal: true,
        };
        match &learned.model {
            Err(reason) => done(failed(reason.clone())),
            Ok(model) => match model.problems.get(problem) {
                Some(Ok(_)) => ready.push_back((Arc::clone(&learned), problem.clone())),
                Some(Err(reason)) => done(failed(format!("the build wrote no problem: {reason}"))),
                None => done(failed("the build wrote no problem".to_string())),
            },
        }
    }
}

/// The job's JSON for a worker (only problems with PDDL are queued).
fn job_text(settings: &Settings<'_>, learned: &Learned, problem: &str) -> Result<String, String> {
    let unwritten = || format!("no PDDL problem `{problem}` to solve");
    let model = learned.model.as_ref().map_err(|_| unwritten())?;
    let problem_pddl =
        model.problems.get(problem).and_then(|p| p.as_ref().ok()).ok_or_else(unwritten)?;
    let job = Job {
        spec: settings.spec.to_path_buf(),
        spec_text: settings.spec_text.to_string(),
        problem: problem.to_string(),
        seed: settings.seed,
        timeout: settings.timeout,
        domain: model.domain.clone(),
        problem_pddl: problem_pddl.clone(),
        samplers: model.samplers.clone(),
    };
    serde_json::to_string(&job).map_err(|error| format!("cannot write the job: {error}"))
}
