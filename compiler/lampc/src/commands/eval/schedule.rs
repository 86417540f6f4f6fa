//! Running the solves: one thread learns the subsets' models in order, while up to `--jobs`
//! worker processes (each through the executor's command) solve the problems of the subsets
//! learned so far. A problem whose journaled row was solved with the very model just learned is
//! not solved again. Each finished solve is handed to the caller at once (which journals it); an
//! interrupt stops learning, kills the running workers and drops their solves. A solve the
//! executor gives no row for is tried once more; a second failure, or a command that cannot
//! start, stops the evaluation as an interrupt does and is returned.

use std::collections::{BTreeMap, VecDeque};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use lamp_eval::{Outcome, SolveResult};

use super::executor::{self, Executor, ExecutorError, Finished};
use super::journal::Key;
use super::worker::Job;

/// How often the scheduler looks for finished solves, learned subsets and an interrupt.
const POLL: Duration = Duration::from_millis(50);

/// A subset to learn, with the problems to solve with its model.
pub(super) struct SubsetWork {
    pub(super) digest: lamp_build::Digest,
    /// Indices into the pool, ascending.
    pub(super) indices: Vec<usize>,
    pub(super) problems: Vec<String>,
    /// Per problem, the models its rows in the journal were solved with: a problem whose model
    /// is among them keeps its row.
    pub(super) journaled: BTreeMap<String, Vec<String>>,
}

/// A subset's model as text, or why learning failed.
pub(super) struct Learned {
    pub(super) digest: String,
    pub(super) seconds: f64,
    pub(super) model: Result<Model, String>,
    pub(super) problems: Vec<String>,
    /// Per problem, the digest of what its solve is given ([`model_digest`]).
    pub(super) models: BTreeMap<String, String>,
    pub(super) journaled: BTreeMap<String, Vec<String>>,
}

/// The digest of what one solve is given: the learned domain, the sampler file and the problem's
/// PDDL, or, when there is nothing to solve with, why. Equal digests mean equal answers to the
/// solver, whichever commit of the learner made them.
pub(super) fn model_digest(parts: &[&str]) -> String {
    let mut bytes = Vec::new();
    for part in parts {
        // Each part's length first, so that no two different lists give the same bytes.
        bytes.extend_from_slice(&(part.len() as u64).to_le_bytes());
        bytes.extend_from_slice(part.as_bytes());
    }
    lamp_build::file_digest(&bytes).to_string()
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
    /// The digest of what the models are learned from (`SpecSources::model`), robot models and
    /// object shapes as loaded when the evaluation started, for the worker to compare.
    pub(super) model_sources: &'a str,
    pub(super) seed: u64,
    pub(super) timeout: Option<f64>,
    pub(super) jobs: usize,
    /// The command each solve runs in.
    pub(super) executor: &'a Executor,
}

/// A finished solve: its key, what it reported (`None`: the journal's row for this model stands),
/// the model it was given and the subset's learning time.
pub(super) struct Done {
    pub(super) key: Key,
    pub(super) result: Option<SolveResult>,
    pub(super) model: String,
    pub(super) seconds_learning: f64,
}

/// How the schedule ended.
pub(super) enum Ending {
    /// Every solve finished.
    Complete,
    /// Interrupted: the running solves were dropped.
    Interrupted,
    /// The executor gave no row for a solve twice, or could not start: the running solves were
    /// dropped.
    Broken(ExecutorError),
}

/// How often a solve is started before the executor's failure stops the evaluation: once more
/// after a failure, for a lost node or a preempted job; a broken command fails twice in a row.
const ATTEMPTS: usize = 2;

/// Learns every subset of `work` with `learn` and solves its problems; `started` is told each
/// solve's problem as it starts, `retrying` each executor failure that is tried again, `done`
/// each result as it finishes.
pub(super) fn run(
    settings: &Settings<'_>,
    work: Vec<SubsetWork>,
    learn: &(dyn Fn(&SubsetWork) -> Learned + Sync),
    interrupted: &(dyn Fn() -> bool + Sync),
    started: &mut dyn FnMut(&str),
    retrying: &mut dyn FnMut(&ExecutorError),
    done: &mut dyn FnMut(Done),
) -> Ending {
    let stop = AtomicBool::new(false);
    let mut broken = None;
    // How often each solve was started.
    let mut attempts: BTreeMap<Key, usize> = BTreeMap::new();
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
        let (finished_tx, finished_rx) = mpsc::channel::<(Arc<Learned>, String, Finished)>();
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
                    let job = match job_text(settings, &learned, &problem) {
                        Ok(job) => job,
                        Err(reason) => {
                            broken.get_or_insert(ExecutorError::Job { problem, reason });
                            stop.store(true, Ordering::Relaxed);
                            break;
                        }
                    };
                    started(&problem);
                    *attempts.entry((learned.digest.clone(), problem.clone())).or_default() += 1;
                    running += 1;
                    let finished_tx = finished_tx.clone();
                    let (timeout, executor) = (settings.timeout, settings.executor);
                    scope.spawn(move || {
                        let finished = executor::run(executor, job, &problem, timeout, stop);
                        let _ = finished_tx.send((learned, problem, finished));
                    });
                }
            }
            if running == 0 && (stop.load(Ordering::Relaxed) || (learner_done && ready.is_empty()))
            {
                break;
            }
            match finished_rx.recv_timeout(POLL) {
                Ok((learned, problem, finished)) => {
                    running -= 1;
                    let key = (learned.digest.clone(), problem.clone());
                    match finished {
                        Finished::Result(result) => {
                            let seconds_learning = learned.seconds;
                            let model = learned.models.get(&problem).cloned().unwrap_or_default();
                            done(Done { key, result: Some(result), model, seconds_learning });
                        }
                        // Killed by the signal that stops the evaluation (a SIGTERM to a whole
                        // cgroup reaches the workers too), not broken.
                        Finished::Broken(_) if interrupted() => {
                            stop.store(true, Ordering::Relaxed);
                        }
                        Finished::Broken(error)
                            if error.may_pass()
                                && broken.is_none()
                                && attempts.get(&key).is_some_and(|&n| n < ATTEMPTS) =>
                        {
                            retrying(&error);
                            ready.push_front((learned, problem));
                        }
                        Finished::Broken(error) => {
                            broken.get_or_insert(error);
                            stop.store(true, Ordering::Relaxed);
                        }
                        Finished::Stopped => {}
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout | mpsc::RecvTimeoutError::Disconnected) => {}
            }
        }
        // Dropping the receiver ends a learner blocked on sending.
        drop(learned_rx);
    });
    match broken {
        Some(error) => Ending::Broken(error),
        None if stop.load(Ordering::Relaxed) => Ending::Interrupted,
        None => Ending::Complete,
    }
}

/// Queues the problems of a learned subset; a problem journaled with the same model and a
/// failed build end at once.
fn queue(
    learned: Arc<Learned>,
    ready: &mut VecDeque<(Arc<Learned>, String)>,
    done: &mut dyn FnMut(Done),
) {
    for problem in &learned.problems {
        let key = (learned.digest.clone(), problem.clone());
        let model = learned.models.get(problem).cloned().unwrap_or_default();
        if learned.journaled.get(problem).is_some_and(|models| models.contains(&model)) {
            done(Done { key, result: None, model, seconds_learning: learned.seconds });
            continue;
        }
        let failed = |reason: String| Done {
            key: key.clone(),
            result: Some(SolveResult::failed(Outcome::BuildFailed, reason)),
            model: model.clone(),
            seconds_learning: learned.seconds,
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
        model_sources: settings.model_sources.to_string(),
        problem: problem.to_string(),
        seed: settings.seed,
        timeout: settings.timeout,
        domain: model.domain.clone(),
        problem_pddl: problem_pddl.clone(),
        samplers: model.samplers.clone(),
    };
    serde_json::to_string(&job).map_err(|error| format!("cannot write the job: {error}"))
}
