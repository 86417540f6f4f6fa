//! `lampc solve`: plan, refine and write a validated trajectory for one problem of a built spec.
//!
//! Reads the build's model (`domain.pddl`, `problems/<name>.pddl`, `samplers.json`, each checked
//! against the build's manifest first), sets up the three plugins, runs lamp-tamp, and writes into
//! `<build>/solutions/<problem>/` the trajectory (`trajectory.mcap`), the plan (`plan.txt`), the
//! run summary (`summary.json`) and a picture (`trajectory.svg`) — only once the trajectory has
//! passed its replay check, as a whole folder swapped in for the previous one, under a lock that
//! refuses a second solve into the same folder. A trajectory to a relaxed goal is written too, as
//! a partial result with its own exit code.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use lamp_participants::ParticipantMap;
use lamp_tamp::{SolveError, SolveInput};
use lamp_world::{SpecWorld, trajectory_header};

use crate::build_folder::{Check, ModelFiles};
use crate::commands::{EXIT_INTERRUPTED, Failure, Finished, Outcome, Stopped};
use crate::output::{OutputError, OutputFolder};
use crate::solve_setup::{self, Overrides};

/// Arguments of `lampc solve`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The `.lamp` spec file.
    pub(crate) spec: PathBuf,
    /// The problem to solve, by name.
    #[arg(long)]
    pub(crate) problem: String,
    /// The build folder `lampc build` wrote [default: `build/` beside the spec].
    #[arg(long, value_name = "DIR")]
    pub(crate) build: Option<PathBuf>,
    /// Where to write the solution [default: `<build>/solutions/<problem>/`].
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    /// The planner: a built-in name (`gbfs-ff`, `topk`, `external`) or a library path.
    #[arg(long, value_name = "NAME|PATH")]
    pub(crate) planner: Option<String>,
    /// The refiner: `gmm` or a library path.
    #[arg(long, value_name = "NAME|PATH")]
    pub(crate) refiner: Option<String>,
    /// The motion planner: `rrt-connect` or a library path.
    #[arg(long, value_name = "NAME|PATH")]
    pub(crate) motion: Option<String>,
    /// Plans to ask the planner for (top-k) [default: the planner's `plans` option, else 3].
    #[arg(long, value_name = "K", value_parser = crate::flags::plans)]
    pub(crate) plans: Option<usize>,
    /// The run's seed [default: the spec's].
    #[arg(long)]
    pub(crate) seed: Option<u64>,
    /// Fail instead of dropping goal atoms no plan reaches.
    #[arg(long)]
    pub(crate) no_relax: bool,
    /// Stop after this many seconds of wall time and report how far the search got
    /// [default: no limit; Ctrl-C stops it the same way].
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub(crate) timeout: Option<f64>,
    /// Threads to share the work between (collision checks of a motion's states) [default: one
    /// per core]. The solution is the same, byte for byte, on any number.
    #[arg(long, value_name = "N", value_parser = crate::flags::threads)]
    pub(crate) threads: Option<usize>,
    /// Use the build's files as they are, even when they differ from the build's manifest (for
    /// PDDL edited by hand on purpose); every difference is reported as a warning.
    #[arg(long)]
    pub(crate) unchecked_build: bool,
}

/// The files of a solution folder, which replaces only a folder holding nothing else.
const SOLUTION_FILES: [&str; 4] = ["trajectory.mcap", "plan.txt", "summary.json", "trajectory.svg"];
/// The folder of solutions inside the build folder.
const SOLUTIONS_DIR: &str = "solutions";
/// The exit code of a partial result: a validated trajectory to a goal with atoms dropped.
/// Not 2, which is the exit code of a command line that does not parse.
pub(crate) const EXIT_PARTIAL: u8 = 3;

/// Set by the first Ctrl-C or SIGTERM; the solver polls it through its cancellation check.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

pub(crate) fn run(args: &Args) -> Outcome {
    let colour = crate::terminal::colour();
    if let Some(threads) = args.threads {
        // The process's first and only pool: nothing has used rayon yet.
        rayon::ThreadPoolBuilder::new().num_threads(threads).build_global().map_err(|error| {
            Stopped::from(Failure::Message(format!("cannot start {threads} thread(s): {error}")))
        })?;
    }
    watch_interrupts();
    let mut left = NOTHING_WRITTEN.to_string();
    // On a thread of the pool, so that `--threads N` is all the solve uses: work it hands the
    // pool runs beside it only when there is a thread to spare.
    match rayon::scope(|_| solve(args, colour, &mut left)) {
        Ok(summary) if summary.success => Ok(Finished::Done),
        Ok(_) => Ok(Finished::Partial),
        Err(stopped) => Err(Stopped {
            interrupted: INTERRUPTED.load(Ordering::Relaxed),
            ..stopped.leaving(left)
        }),
    }
}

/// The first Ctrl-C or SIGTERM asks the search to stop at its next check (it then reports how far it got
/// and writes nothing); a second one ends the process at once.
fn watch_interrupts() {
    // Without a handler (one was already set) Ctrl-C keeps its default, ending the process;
    // nothing half-written is left either way, since files are renamed into place at the end.
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::Relaxed) {
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
    });
}

/// How long after the time limit a solve that has not stopped is abandoned: the solver and the
/// built-in plugins stop within about a second of it.
const UNRESPONSIVE_GRACE: Duration = Duration::from_secs(5);

/// The time limit ran out and the solve did not stop: a plugin is in a call that never checks the
/// host's cancellation.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
#[error(
    "the time limit of {seconds} s (`--timeout`) ran out {grace} s ago and the solve has not stopped: \
     a plugin is in a call that does not check for cancellation; stopped without waiting for it, \
     nothing was written"
)]
#[diagnostic(
    code(lamp::solve::unresponsive),
    help(
        "A plugin should poll `HostServices::is_cancelled` in long work (docs/plugins.md); try the built-in plugins, which do."
    )
)]
struct Unresponsive {
    seconds: f64,
    grace: u64,
}

/// Holds the time limit whatever a plugin does: if the solve has not finished
/// [`UNRESPONSIVE_GRACE`] after `deadline`, says so and ends the process. Nothing is half
/// written then, since the solution folder is written only after the solve returns.
fn watch_deadline(deadline: Instant, seconds: f64, finished: Arc<AtomicBool>, colour: bool) {
    /// How often the watch looks whether the solve has finished.
    const POLL: Duration = Duration::from_millis(100);
    let Some(abandon) = deadline.checked_add(UNRESPONSIVE_GRACE) else { return };
    std::thread::spawn(move || {
        while !finished.load(Ordering::Relaxed) {
            let now = Instant::now();
            if now >= abandon {
                let error = Unresponsive { seconds, grace: UNRESPONSIVE_GRACE.as_secs() };
                let stopped = Stopped::from(error).leaving(NOTHING_WRITTEN);
                stopped.print("solve", colour);
                std::process::exit(i32::from(stopped.exit_code()));
            }
            std::thread::sleep(POLL.min(abandon - now));
        }
    });
}

pub(crate) fn parse_seconds(text: &str) -> Result<f64, String> {
    crate::flags::seconds(text)
}

/// What a failed solve says it left, unless it learns more.
const NOTHING_WRITTEN: &str = "no solution files were written";

/// Solves and writes the solution folder; `left` is kept true about what a failure leaves.
fn solve(args: &Args, colour: bool, left: &mut String) -> Result<lamp_tamp::Summary, Stopped> {
    let Some(checked) = crate::spec_input::check_spec(
        &args.spec,
        colour,
        crate::spec_input::Demonstrations::Unread,
    ) else {
        return Err(Stopped::said());
    };
    let (spec, spec_dir) = (&checked.spec, &checked.dir);
    let problem =
        spec.problems.iter().find(|problem| problem.name == args.problem).ok_or_else(|| {
            let names: Vec<&str> = spec.problems.iter().map(|p| p.name.as_str()).collect();
            Failure::Message(format!(
                "{}: no problem `{}`; the spec has: {}",
                checked.file_name,
                args.problem,
                names.join(", ")
            ))
        })?;
    let build_dir =
        args.build.clone().unwrap_or_else(|| spec_dir.join(lamp_build::DEFAULT_BUILD_DIR));
    let check = if args.unchecked_build { Check::Unchecked } else { Check::Manifest };
    if args.unchecked_build {
        eprintln!(
            "lampc solve: warning: `--unchecked-build`: the model in {} is used without checking it against the build's manifest",
            crate::build_folder::model_dir(&build_dir).display()
        );
    }
    // Loaded first: the build is checked against the robot models and shapes as they are now.
    let world = SpecWorld::load(spec_dir, spec)?;
    // Before the build: a problem whose start cannot be (a can in the air) is the spec's fault,
    // whichever build answers it, and is said at its line rather than as a stale build.
    let located = (&checked.places, &checked.sources);
    if crate::spec_input::refuse_scenes(spec, located, &world, Some(&problem.name), colour) > 0 {
        return Err(Stopped::from(Failure::Message(format!(
            "problem `{}`: its initial scene is not one the solver can start from",
            problem.name
        ))));
    }
    let ModelFiles { domain, problem: problem_text, samplers, warnings } =
        crate::build_folder::read_model(&build_dir, &problem.name, spec, &world, check)
            .map_err(Failure::Report)?;
    for warning in &warnings {
        eprintln!("lampc solve: warning: {warning}");
    }
    let out = args.out.clone().unwrap_or_else(|| build_dir.join(SOLUTIONS_DIR).join(&problem.name));
    let folder = OutputFolder::new(&out)?;
    let lock = folder.lock("solve")?;
    if out.is_dir() {
        *left =
            format!("{NOTHING_WRITTEN}; the previous solution in {} is unchanged", out.display());
    }
    replaceable(&out)?;
    folder.remove_leftovers(&lock);

    let participants = ParticipantMap::new(spec, &world.robots)?;
    let scene = world.problem_scene(problem)?;
    let targets = world.placement_targets(problem)?;

    let overrides = Overrides {
        planner: args.planner.as_deref(),
        refiner: args.refiner.as_deref(),
        motion: args.motion.as_deref(),
        plans: args.plans,
        seed: args.seed,
        no_relax: args.no_relax,
    };
    let mut plugins =
        solve_setup::plugins(spec, spec_dir, &checked.file_name, &overrides, &samplers.artifact)?;
    let deadline = args.timeout.map(deadline_after).transpose()?;
    let out_of_time = || deadline.is_some_and(|deadline| Instant::now() >= deadline);
    let cancelled = || INTERRUPTED.load(Ordering::Relaxed) || out_of_time();
    let settings = solve_setup::settings(spec, &plugins.runtime, &overrides, &cancelled);
    let seed = settings.seed;
    let mut header = trajectory_header(spec, &scene, seed);
    header.provenance.insert("problem".to_string(), problem.name.clone());
    header.provenance.insert("samplers".to_string(), samplers.provenance.digest.clone());
    let input = SolveInput {
        scene: &scene,
        domain: &domain,
        problem: &problem_text,
        artifact: &samplers.artifact,
        participants: &participants,
        targets: &targets,
        header,
    };
    let spinner = crate::terminal::spinner();
    let report = |phase: &str| spinner.set_message(format!("{}: {phase}", problem.name));
    let finished = Arc::new(AtomicBool::new(false));
    if let (Some(deadline), Some(seconds)) = (deadline, args.timeout) {
        watch_deadline(deadline, seconds, Arc::clone(&finished), colour);
    }
    let outcome = lamp_tamp::solve(&input, &mut plugins.as_plugins(), &settings, &report);
    finished.store(true, Ordering::Relaxed);
    spinner.finish_and_clear();
    let failed_folder = failed_folder(&out);
    if let Err(error) = &outcome {
        write_failure_report(&failed_folder, &problem.name, error);
    }
    let solution = outcome.map_err(|error| {
        let model = crate::build_folder::model_dir(&build_dir);
        let problem_file =
            Path::new(lamp_build::PROBLEMS_DIR).join(format!("{}.pddl", problem.name));
        let error = error.in_files(
            &model.join(lamp_build::DOMAIN_FILE).display().to_string(),
            &model.join(problem_file).display().to_string(),
        );
        let notes = match (&error, args.timeout) {
            (SolveError::Cancelled(_), Some(seconds)) if out_of_time() => {
                vec![format!("the time limit of {seconds} s (`--timeout`) ran out")]
            }
            _ => Vec::new(),
        };
        Stopped { notes, ..Stopped::from(error) }
    })?;

    let contents = solution_contents(&world, &solution)?;
    let files: Vec<(&Path, &[u8])> =
        SOLUTION_FILES.iter().map(Path::new).zip(contents.iter().map(Vec::as_slice)).collect();
    // Checked again: the folder may have changed while the solve ran.
    replaceable(&out)?;
    let replaced = folder.replace(&lock, &files).inspect_err(|error| {
        if let OutputError::Swap { state, .. } = error {
            left.clone_from(state);
        }
    })?;
    remove_failure_report(&failed_folder);
    print_summary(&solution.summary, &out);
    if let Some((kept, reason)) = replaced.kept {
        eprintln!(
            "lampc solve: warning: the previous solution, moved to {}, could not be removed: {reason}",
            kept.display()
        );
    }
    Ok(solution.summary)
}

/// The instant `seconds` (`--timeout`) from now.
fn deadline_after(seconds: f64) -> Result<Instant, Failure> {
    let limit = lamp_spec::limits::duration(seconds)
        .map_err(|error| Failure::Message(format!("--timeout: {error}")))?;
    Instant::now()
        .checked_add(limit)
        .ok_or_else(|| Failure::Message("--timeout: beyond the clock's range".to_string()))
}

/// The contents of the solution files, in the order of [`SOLUTION_FILES`]: the trajectory with
/// its standard and execution channels, the plan, the summary and the picture.
fn solution_contents(
    world: &SpecWorld,
    solution: &lamp_tamp::Solution,
) -> Result<[Vec<u8>; 4], Failure> {
    let picture =
        lamp_render::render_trajectory(world, &solution.trajectory, None, &Default::default())?;
    let summary = &solution.summary;
    let approaches = summary
        .approaches
        .iter()
        .map(|span| Ok((span.from_step, serde_json::to_string(span)?)))
        .collect::<Result<Vec<_>, serde_json::Error>>()
        .map_err(|error| Failure::Message(error.to_string()))?;
    let marks = crate::viewable::SolutionMarks {
        starts: &solution.step_starts,
        plan: &summary.plan,
        approaches: &approaches,
    };
    let mcap = crate::viewable::mcap_bytes(world, &solution.trajectory, Some(marks))
        .map_err(Failure::Report)?;
    let mut summary_json = serde_json::to_string_pretty(summary)
        .map_err(|error| Failure::Message(error.to_string()))?;
    summary_json.push('\n');
    Ok([mcap, summary.plan_text().into_bytes(), summary_json.into_bytes(), picture.into_bytes()])
}

/// The folder of a failed solve's report, beside the solution folder `out`:
/// `<build>/solutions/<problem>.failed/`.
fn failed_folder(out: &Path) -> PathBuf {
    let name = out
        .file_name()
        .map_or_else(|| "solution".to_string(), |name| name.to_string_lossy().into_owned());
    out.with_file_name(format!("{name}.{FAILED_SUFFIX}"))
}

/// The suffix of the failure report's folder, after the solution folder's name.
const FAILED_SUFFIX: &str = "failed";
/// The failure report's file in its folder, and the picture of the deepest state reached.
const FAILURE_FILE: &str = "failure.json";
const DEEPEST_FILE: &str = "deepest.svg";
/// The `format` and `version` of the failure report (`docs/solving.md`).
const FAILURE_FORMAT: &str = "lamp-failure-report";
const FAILURE_VERSION: u32 = 1;

/// The failure report written when a solve fails.
#[derive(serde::Serialize)]
struct FailureFile<'a> {
    format: &'static str,
    version: u32,
    problem: &'a str,
    /// The error's code and its message.
    code: String,
    message: String,
    /// How far the refinement got, when it got anywhere.
    #[serde(skip_serializing_if = "Option::is_none")]
    refinement: Option<&'a lamp_tamp::Progress>,
}

/// Writes why the solve failed to `folder` (replacing an earlier report), and says where; a
/// report that cannot be written is only mentioned, as the failure itself is what the user needs
/// to read.
fn write_failure_report(folder: &Path, problem: &str, error: &SolveError) {
    use miette::Diagnostic;
    let refinement = match error {
        SolveError::RefinementFailed(progress) | SolveError::Cancelled(progress) => Some(progress),
        _ => None,
    };
    let file = FailureFile {
        format: FAILURE_FORMAT,
        version: FAILURE_VERSION,
        problem,
        code: error.code().map(|code| code.to_string()).unwrap_or_default(),
        message: error.to_string(),
        refinement,
    };
    let picture = refinement.and_then(|progress| {
        let state = progress.deepest_state.as_ref()?;
        let options = lamp_render::RenderOptions {
            title: Some(format!(
                "{problem}: the deepest state reached, before step {} of {} {}",
                progress.deepest, progress.length, state.action
            )),
            marked: progress.report.blockers(),
            ..lamp_render::RenderOptions::default()
        };
        Some(lamp_render::render_scene(&state.scene, &options))
    });
    let written = serde_json::to_string_pretty(&file).map_err(|error| error.to_string()).and_then(
        |mut json| {
            json.push('\n');
            let mut files = vec![(Path::new(FAILURE_FILE), json.as_bytes())];
            if let Some(picture) = &picture {
                files.push((Path::new(DEEPEST_FILE), picture.as_bytes()));
            }
            let output = OutputFolder::new(folder).map_err(|error| error.to_string())?;
            let lock = output.lock("solve").map_err(|error| error.to_string())?;
            output.replace(&lock, &files).map_err(|error| error.to_string())
        },
    );
    match written {
        Ok(_) => {
            eprintln!(
                "lampc solve: why it failed, step by step, is in {}",
                folder.join(FAILURE_FILE).display()
            );
            if picture.is_some() {
                eprintln!(
                    "lampc solve: the deepest state reached is drawn in {}, what is in the way outlined in red",
                    folder.join(DEEPEST_FILE).display()
                );
            }
        }
        Err(reason) => eprintln!("lampc solve: the failure report could not be written: {reason}"),
    }
}

/// Removes the report of an earlier failed solve once the problem is solved, so that it is never
/// read as the report of the solution beside it. Only a folder holding nothing but the report
/// is removed.
fn remove_failure_report(folder: &Path) {
    crate::output::remove_if_only(folder, &[FAILURE_FILE, DEEPEST_FILE]);
}

/// Refuses to replace `out` unless it is missing or a folder of solution files only, so that no
/// file lampc did not write is ever removed.
fn replaceable(out: &Path) -> Result<(), OutputError> {
    let occupied =
        |reason: String| OutputError::Occupied { folder: out.display().to_string(), reason };
    let Ok(metadata) = std::fs::symlink_metadata(out) else { return Ok(()) };
    if !metadata.is_dir() {
        let kind = crate::output::kind_of(&metadata);
        return Err(occupied(format!("it is {kind}, not a solution folder")));
    }
    let entries = std::fs::read_dir(out).map_err(|error| occupied(error.to_string()))?;
    let mut entries: Vec<_> = entries.flatten().collect();
    entries.sort_by_key(|entry| entry.file_name());
    for entry in entries {
        let name = entry.file_name().to_string_lossy().into_owned();
        let metadata = std::fs::symlink_metadata(entry.path())
            .map_err(|error| occupied(format!("{}: {error}", entry.path().display())))?;
        if !SOLUTION_FILES.contains(&name.as_str()) {
            return Err(occupied(format!("it holds {name}, which is not a solution file")));
        }
        if !metadata.is_file() {
            let kind = crate::output::kind_of(&metadata);
            return Err(occupied(format!(
                "{} is {kind}, not a solution file",
                entry.path().display()
            )));
        }
    }
    Ok(())
}

fn print_summary(summary: &lamp_tamp::Summary, out: &Path) {
    if summary.is_partial() {
        println!(
            "{}: partially solved: dropped {}; written to {}",
            summary.problem,
            summary.relaxed_goal.join(", "),
            out.display()
        );
    } else {
        println!("{}: solved, written to {}", summary.problem, out.display());
    }
    println!(
        "  plan            {} steps ({} plan(s) tried)",
        summary.plan.len(),
        summary.plans_tried
    );
    println!(
        "  refinement      {} candidates, {} backtracks, {} replans, {} motion calls ({} without a path)",
        summary.candidates,
        summary.backtracks,
        summary.replans,
        summary.motion_calls,
        summary.motion_failures
    );
    println!(
        "  trajectory      {} steps, {:.1} s to execute, validated by replay",
        summary.trajectory_steps, summary.execution_seconds
    );
    if !summary.approaches.is_empty() {
        let count = |end: lamp_tamp::ApproachEnd| {
            summary.approaches.iter().filter(|approach| approach.kind == end).count()
        };
        println!(
            "  approaches      {} put-down(s), {} contact grasp(s) end in contact: make them compliant (`/lamp/approach`)",
            count(lamp_tamp::ApproachEnd::PutDown),
            count(lamp_tamp::ApproachEnd::Contact)
        );
    }
    if let Some(sink) = &summary.sink {
        println!(
            "  resting         `{}` goes down farthest onto what it rests on, {:.1} mm: the resting gaps under it",
            sink.object,
            sink.metres * 1000.0
        );
    }
    println!(
        "  time            planning {:.2} s, refining {:.2} s, validating {:.2} s",
        summary.seconds_planning, summary.seconds_refining, summary.seconds_validating
    );
}
