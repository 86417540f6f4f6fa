//! One solve in its own process: `lampc eval-worker` (hidden) reads a [`Job`] as JSON from its
//! standard input, solves it with `lampc solve`'s settings, and writes one [`SolveResult`] as
//! JSON to its standard output, with its own peak memory. The parent's side, which starts it
//! (or the `--executor` command that runs it), is [`super::executor`].
//!
//! A process per solve gives every row its own peak memory and lets a time limit or Ctrl-C end a
//! solve at once.
//!
//! A row is what the job gives: solved, or why not. What depends on where the worker runs is not
//! a row: a spec whose files this machine does not have, or robot files that changed since the
//! evaluation started. Then the worker writes no row, says why on its standard error and exits
//! with 1, which the parent reports as a failure of the executor (tried once more, then the
//! evaluation stops with the message), so that a misplaced node never turns into failed solves.

use std::io::Read as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use lamp_build::{SamplersFile, SpecSources};
use lamp_eval::{Outcome, SolveResult};
use lamp_participants::ParticipantMap;
use lamp_tamp::{SolveError, SolveInput};
use lamp_world::{SpecWorld, trajectory_header};
use miette::Diagnostic as _;
use serde::{Deserialize, Serialize};

use crate::commands::{Failure, Finished, Stopped};
use crate::solve_setup::{self, Overrides};

/// The hidden subcommand's name.
pub(crate) const WORKER_COMMAND: &str = "eval-worker";

/// What a worker solves: the problem of the spec with the subset's learned model.
#[derive(Serialize, Deserialize)]
pub(super) struct Job {
    /// The spec file (as the parent was given it; the worker runs in the same folder): where its
    /// relative paths start and what its messages name.
    pub(super) spec: PathBuf,
    /// The spec's text as the parent read it when the evaluation started: every solve answers
    /// that spec (the one the journal's settings key was made from), whatever the file says now.
    pub(super) spec_text: String,
    /// The digest of the model's sources as the parent loaded them (`SpecSources::model`): the
    /// spec's text cannot carry the robot and mesh files it names, which the worker reads again.
    pub(super) model_sources: String,
    pub(super) problem: String,
    /// The evaluation's seed.
    pub(super) seed: u64,
    /// Seconds of wall time before the solve is cancelled.
    pub(super) timeout: Option<f64>,
    /// The learned domain and problem as PDDL, and the sampler file's JSON.
    pub(super) domain: String,
    pub(super) problem_pddl: String,
    pub(super) samplers: String,
}

/// Runs `lampc eval-worker`: a job from standard input, a result to standard output.
pub(crate) fn run() -> crate::commands::Outcome {
    let started = Instant::now();
    let mut input = String::new();
    if let Err(error) = std::io::stdin().read_to_string(&mut input) {
        return Err(worker_failure(format!("cannot read the job: {error}")));
    }
    let job: Job = match serde_json::from_str(&input) {
        Ok(job) => job,
        Err(error) => return Err(worker_failure(format!("the job does not parse: {error}"))),
    };
    drop(input);
    // A panic in the solver is a property of this lampc and the job, as repeatable as any other
    // outcome: it becomes an `error` row (the panic hook has printed it on standard error). A
    // worker that ends without a row is the executor's failure, which stops the evaluation.
    let solved = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| solve(&job)));
    let mut result = match solved {
        Ok(Ok(result)) => result,
        Ok(Err(NotHere(reason))) => {
            return Err(worker_failure(format!("cannot run this job here: {reason}")));
        }
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .map(|text| (*text).to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            error(format!("internal error: lampc panicked while solving: {message}"))
        }
    };
    result.seconds_solving = Some(started.elapsed().as_secs_f64());
    result.peak_memory_bytes = peak_memory();
    match serde_json::to_string(&result) {
        Ok(line) => {
            println!("{line}");
            Ok(Finished::Done)
        }
        Err(error) => Err(worker_failure(format!("cannot write the result: {error}"))),
    }
}

/// A worker's stop: one line that the evaluation quotes as the executor's failure.
fn worker_failure(reason: String) -> Stopped {
    Stopped::from(Failure::Message(format!("lampc eval-worker: {reason}")))
}

/// One line: a multi-line message joined with spaces.
pub(super) fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn error(reason: impl std::fmt::Display) -> SolveResult {
    SolveResult::failed(Outcome::Error, one_line(&reason.to_string()))
}

/// Why a job cannot be solved where this worker runs (the files it reads differ from those the
/// evaluation started with), as opposed to a row that says why the problem was not solved.
struct NotHere(String);

fn solve(job: &Job) -> Result<SolveResult, NotHere> {
    let spec_dir = match job.spec.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = job.spec.display().to_string();
    let checked =
        lamp_lang::check_source(&name, &job.spec_text, &spec_dir, &crate::files::DiskLoader);
    let Some(spec) = checked.spec else {
        let first = checked.diagnostics.first().map(|diagnostic| diagnostic.error.to_string());
        return Err(NotHere(format!(
            "the spec {name}, read from {}, does not check here: {}; run the worker in the \
             folder `lampc eval` runs in, on a file system that holds the spec and the files it \
             names at the same paths",
            std::env::current_dir()
                .map_or_else(|_| "?".to_string(), |dir| dir.display().to_string()),
            one_line(&first.unwrap_or_default())
        )));
    };
    let spec_file = job.spec.file_name().map_or_else(String::new, |n| n.to_string_lossy().into());
    let Some(problem) = spec.problems.iter().find(|problem| problem.name == job.problem) else {
        return Ok(error(format!("the spec has no problem `{}`", job.problem)));
    };
    let samplers = match SamplersFile::from_json(&job.samplers) {
        Ok(samplers) => samplers,
        Err(failure) => return Ok(error(failure)),
    };
    let world = match SpecWorld::load(&spec_dir, &spec) {
        Ok(world) => world,
        Err(failure) => return Err(NotHere(one_line(&failure.to_string()))),
    };
    // The parent digested its spec with the evaluation's seed in place of the spec's.
    let as_evaluated = lamp_spec::Spec { seed: job.seed, ..spec.clone() };
    if SpecSources::of(&as_evaluated, &world).model != job.model_sources {
        return Err(NotHere(
            "a robot model or mesh file the spec names changed since the evaluation started: \
             this solve would move another robot than the one its model was learned for"
                .to_string(),
        ));
    }
    Ok(solve_loaded(job, &spec, &spec_dir, &spec_file, problem, &samplers, &world))
}

/// Solves `job` once its spec, robots and model are known to be the evaluation's.
fn solve_loaded(
    job: &Job,
    spec: &lamp_spec::Spec,
    spec_dir: &std::path::Path,
    spec_file: &str,
    problem: &lamp_spec::Problem,
    samplers: &SamplersFile,
    world: &SpecWorld,
) -> SolveResult {
    let participants = match ParticipantMap::new(spec, &world.robots) {
        Ok(participants) => participants,
        Err(failure) => return error(failure),
    };
    let scene = match world.problem_scene(problem) {
        Ok(scene) => scene,
        Err(failure) => return error(failure),
    };
    let targets = match world.placement_targets(problem) {
        Ok(targets) => targets,
        Err(failure) => return error(failure),
    };
    let overrides = Overrides { seed: Some(job.seed), ..Overrides::default() };
    let mut plugins =
        match solve_setup::plugins(spec, spec_dir, spec_file, &overrides, &samplers.artifact) {
            Ok(plugins) => plugins,
            Err(message) => return error(message),
        };
    let deadline = job.timeout.map(|seconds| Instant::now() + Duration::from_secs_f64(seconds));
    let cancelled = || deadline.is_some_and(|deadline| Instant::now() >= deadline);
    let settings = solve_setup::settings(spec, &plugins.runtime, &overrides, &cancelled);
    let mut header = trajectory_header(spec, &scene, settings.seed);
    header.provenance.insert("problem".to_string(), problem.name.clone());
    let input = SolveInput {
        scene: &scene,
        domain: &job.domain,
        problem: &job.problem_pddl,
        artifact: &samplers.artifact,
        participants: &participants,
        targets: &targets,
        header,
    };
    match lamp_tamp::solve(&input, &mut plugins.as_plugins(), &settings, &|_| {}) {
        Ok(solution) => summary_result(&solution.summary),
        Err(failure) => failure_result(&failure),
    }
}

/// A trajectory was found: solved, or only a relaxed goal reached (not a success).
fn summary_result(summary: &lamp_tamp::Summary) -> SolveResult {
    let (outcome, reason) = if !summary.relaxed_goal.is_empty() {
        (
            Outcome::RelaxedGoal,
            format!("the goal was relaxed: dropped {}", summary.relaxed_goal.join(", ")),
        )
    } else if summary.success {
        (Outcome::Solved, String::new())
    } else {
        (Outcome::Error, "the solver reported no success".to_string())
    };
    SolveResult {
        outcome,
        reason,
        relaxed: summary.relaxed_goal.clone(),
        plan_length: Some(summary.plan.len()),
        plans_tried: Some(summary.plans_tried),
        candidates: Some(summary.candidates),
        replans: Some(summary.replans),
        motion_calls: Some(summary.motion_calls),
        seconds_planning: Some(summary.seconds_planning),
        seconds_refining: Some(summary.seconds_refining),
        seconds_validating: Some(summary.seconds_validating),
        ..SolveResult::failed(outcome, String::new())
    }
}

/// No trajectory: the outcome by the error's code, with how far the search got when it says.
fn failure_result(failure: &SolveError) -> SolveResult {
    let code = failure.code().map(|code| code.to_string()).unwrap_or_default();
    let outcome = match code.as_str() {
        "lamp::solve::no_plan" | "lamp::solve::goal_relaxed_away" => Outcome::NoPlan,
        "lamp::solve::refinement_failed" => Outcome::RefinementBudget,
        "lamp::solve::cancelled" | "lamp::solve::planner_budget" => Outcome::Timeout,
        _ => Outcome::Error,
    };
    let mut result = SolveResult::failed(outcome, one_line(&format!("{code}: {failure}")));
    if let SolveError::RefinementFailed(progress) | SolveError::Cancelled(progress) = failure {
        result.plans_tried = Some(progress.plans);
        result.candidates = Some(progress.candidates);
        result.stopped_by = progress.report.advice().map(|advice| advice.stop.name().to_string());
    }
    result
}

/// This process's peak resident memory in bytes (`VmHWM` of `/proc/self/status`, Linux only).
fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|line| line.starts_with("VmHWM:"))?;
    let kilobytes: u64 =
        line.trim_start_matches("VmHWM:").trim().strip_suffix("kB")?.trim().parse().ok()?;
    Some(kilobytes * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;
    use lamp_tamp::{Progress, Summary};

    #[test]
    fn solver_errors_become_outcomes_with_how_far_the_search_got() {
        let progress =
            Progress { plans: 20, candidates: 2100, deepest: 8, length: 19, ..Progress::default() };
        let budget = failure_result(&SolveError::RefinementFailed(progress.clone()));
        assert_eq!(budget.outcome, Outcome::RefinementBudget);
        assert_eq!((budget.plans_tried, budget.candidates), (Some(20), Some(2100)));
        assert!(
            budget.reason.starts_with("lamp::solve::refinement_failed: no plan could be refined"),
            "{}",
            budget.reason
        );
        assert_eq!(budget.stopped_by, None, "nothing was refused: no kind stands out");
        // Plans that ended where other cans are in the way say so in the row.
        let mut log = lamp_tamp::failures::FailureLog::default();
        log.start_plan(19);
        log.reached(7, 19);
        let in_the_way = lamp_tamp::failures::Cause::Collision {
            moving: "can4".into(),
            held: true,
            other: "can1".into(),
            other_movable: true,
        };
        log.note(7, "(a2 gripper can4 box1)", in_the_way, None);
        let blocked = Progress { report: log.report(), ..progress.clone() };
        let blocked = failure_result(&SolveError::RefinementFailed(blocked));
        assert_eq!(blocked.stopped_by.as_deref(), Some("in_the_way"));
        let timeout = failure_result(&SolveError::Cancelled(progress));
        assert_eq!((timeout.outcome, timeout.plans_tried), (Outcome::Timeout, Some(20)));
        let no_plan =
            failure_result(&SolveError::NoPlan { reason: "the goal is unreachable".into() });
        assert_eq!((no_plan.outcome, no_plan.plans_tried), (Outcome::NoPlan, None));
        let internal = failure_result(&SolveError::Internal("a\nbroken  invariant".into()));
        assert_eq!(internal.outcome, Outcome::Error);
        assert_eq!(internal.reason, "lamp::solve::internal: internal error: a broken invariant");
    }

    #[test]
    fn a_trajectory_for_a_relaxed_goal_is_not_solved() {
        let summary = Summary {
            problem: "p".into(),
            success: true,
            plan: vec!["(a1 can1 gripper)".into(); 4],
            plans_tried: 1,
            candidates: 4,
            ..Summary::default()
        };
        let solved = summary_result(&summary);
        assert_eq!((solved.outcome, solved.plan_length), (Outcome::Solved, Some(4)));
        assert!(solved.reason.is_empty());
        let relaxed = Summary { relaxed_goal: vec!["(surface_can_0 box1 can1)".into()], ..summary };
        let relaxed = summary_result(&relaxed);
        assert_eq!(relaxed.outcome, Outcome::RelaxedGoal);
        assert_eq!(relaxed.relaxed, ["(surface_can_0 box1 can1)"]);
        assert_eq!(relaxed.plan_length, Some(4), "what the trajectory did is still reported");
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn the_peak_memory_is_read_on_linux() {
        assert!(peak_memory().is_some_and(|bytes| bytes > 1 << 20));
    }
}
