//! `lampc eval`: the paper's evaluation of a spec in one command.
//!
//! Per demonstration count and run it draws a stratified subset of one pool of demonstrations
//! (lamp-eval), learns a model from it in memory (lamp-build), and solves every selected test
//! problem with `lampc solve`'s settings, each solve in its own worker process
//! ([`worker`]) started by this lampc or by the `--executor` command ([`executor`]), up to
//! `--jobs` at once ([`schedule`]). Finished rows go to a journal as they
//! finish ([`journal`]), so that an interrupted evaluation continues where it stopped; at the
//! end `eval.json`, `eval.csv`, `report.md`, `success.svg` and `sample_efficiency.svg` are written
//! into the output folder. The protocol and the design are in `docs/evaluation.md`.

mod error;
mod executor;
mod journal;
mod kept_models;
mod pool;
mod schedule;
pub(crate) mod worker;

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::io::Write as _;
use std::num::NonZeroUsize;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::ProgressBar;
use lamp_build::{Adapter, BuildContext, DemoFile};
use lamp_eval::{EvalDocument, EvalInfo, PoolInfo, ProblemInfo, Row, SettingsInfo};
use lamp_spec::{OptionValue, PluginChoice, PluginSource, Problem, Spec};
use lamp_world::SpecWorld;
use miette::Diagnostic as _;

use self::error::EvaluationError;
use self::executor::Executor;
use self::journal::{JOURNAL_FILE, Journal, Key};
use self::kept_models::KeptModels;
use self::schedule::{Done, Ending, Learned, Model, SubsetWork, model_digest};
use self::worker::one_line;
use crate::commands::{EXIT_INTERRUPTED, Failure, Finished, Outcome, Stopped};
use crate::solve_setup::{self, Overrides, PluginSetupError};

/// Arguments of `lampc eval`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The `.lamp` spec file.
    pub(crate) spec: PathBuf,
    /// Demonstration counts to learn from, comma-separated [default: the whole pool].
    #[arg(long, value_name = "N,N,…")]
    pub(crate) demos: Option<String>,
    /// Runs per count, each with its own subset of demonstrations.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=MAX_RUNS))]
    pub(crate) runs: u32,
    /// The test problems: comma-separated names or globs [default: every problem of the spec].
    #[arg(long, value_name = "GLOB,GLOB")]
    pub(crate) problems: Option<String>,
    /// Solves at once, each in its own process [default: the number of cores].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=MAX_JOBS))]
    pub(crate) jobs: Option<u32>,
    /// Stop each solve after this many seconds of wall time [default: no limit; with a limit
    /// the results depend on the machine].
    #[arg(long, value_name = "SECONDS", value_parser = crate::flags::seconds)]
    pub(crate) timeout: Option<f64>,
    /// The output folder [default: `<build>/eval/` beside the spec].
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    /// The seed of the subset draws, the learning and the solves [default: the spec's].
    #[arg(long)]
    pub(crate) seed: Option<u64>,
    /// The command that runs each solve: it reads the job on its standard input and writes the
    /// result row `lampc eval-worker` writes, e.g. "srun -N1 -n1 lampc eval-worker" [default:
    /// this lampc's `eval-worker`].
    #[arg(long, value_name = "COMMAND")]
    pub(crate) executor: Option<String>,
    /// Also write each run's learned model to `<out>/models/<count>-<run>/`, a build folder that
    /// `lampc solve --build` reads, to see what a run learned and why it failed.
    #[arg(long)]
    pub(crate) keep_models: bool,
}

/// The most runs per count: far beyond any evaluation (the paper uses 10), low enough that a
/// typo cannot queue billions of solves.
const MAX_RUNS: i64 = 10_000;
/// The most solves at once: far more processes than cores help nothing, and each holds a
/// robot world and a learned model in memory.
const MAX_JOBS: i64 = 1024;
/// Set by the first Ctrl-C or SIGTERM: the evaluation stops its workers, keeping the rows it
/// finished.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

pub(crate) fn run(args: &Args) -> Outcome {
    let colour = crate::terminal::colour();
    // The first Ctrl-C or SIGTERM stops the evaluation at once, killing its workers and keeping
    // finished rows; a second one kills them and ends the process (the journal holds every
    // finished row either way).
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::Relaxed) {
            executor::kill_running();
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
    });
    match evaluate(args, colour)? {
        true => Ok(Finished::Done),
        // The summary of what is kept has been said.
        false => Err(Stopped { interrupted: true, ..Stopped::said() }),
    }
}

/// One solve of the evaluation: its place, and the key its result is found under.
struct Slot {
    demos: usize,
    run: usize,
    problem: String,
    objects: usize,
    key: Key,
}

/// Runs the evaluation; `Ok(false)` when interrupted.
fn evaluate(args: &Args, colour: bool) -> Result<bool, Stopped> {
    let started = Instant::now();
    let Some(checked) =
        crate::spec_input::check_spec(&args.spec, colour, crate::spec_input::Demonstrations::Read)
    else {
        return Err(Stopped::said());
    };
    evaluate_checked(args, colour, &checked, started)
}

/// Runs the evaluation of a checked spec.
fn evaluate_checked(
    args: &Args,
    colour: bool,
    checked: &crate::spec_input::CheckedSpec,
    started: Instant,
) -> Result<bool, Stopped> {
    let render = |error: &dyn miette::Diagnostic| crate::diagnostics::render_error(error, colour);
    let seed = args.seed.unwrap_or(checked.spec.seed);
    // The learner and the problems take their seed from the spec.
    let spec = Spec { seed, ..checked.spec.clone() };
    let spec_dir = &checked.dir;
    let problems = select_problems(&spec, &checked.file_name, args.problems.as_deref())?;
    let Options { counts, build_dir, out, runs, jobs, executor } = options(args, spec_dir)?;

    refuse_out_in_a_model_folder(&out)?;
    // Held to the end: a second evaluation into the folder would interleave its journal lines
    // and outputs with this one's.
    let _lock = crate::output::OutputFolder::new(&out).and_then(|folder| folder.lock("eval"))?;
    let settings = settings_info(&spec, spec_dir, &checked.file_name, args.timeout)?;
    // Read before any demonstration is generated: a journal that cannot be read stops the
    // evaluation before its slow part.
    let journal_path = out.join(JOURNAL_FILE);
    let (mut journaled, skipped) = journal::read(&journal_path, &settings.key)?;

    let world = SpecWorld::load(spec_dir, &spec)?;
    // Before any demonstration: a problem whose start cannot be (a can in the air) would fail
    // every row in the final physics check, blaming the solves for the scene.
    let located = (&checked.places, &checked.sources);
    let findings: usize = problems
        .iter()
        .map(|problem| {
            crate::spec_input::refuse_scenes(&spec, located, &world, Some(&problem.name), colour)
        })
        .sum();
    if findings > 0 {
        let spec_file = checked.file_name.clone();
        return Err(Stopped::from(EvaluationError::Scenes { spec_file, findings }));
    }
    let adapter = Adapter::new(&spec, &world.robots)?;
    let largest = counts.as_ref().and_then(|counts| counts.iter().copied().max());
    let note = |message: &str| eprintln!("{}: {message}", checked.file_name);
    let pool = pool::gather(&spec, spec_dir, &build_dir, &world, &adapter, largest, &note)?;
    let counts = counts.unwrap_or_else(|| vec![pool.files.len()]);

    let draw = Draw { spec: &spec, pool: &pool, problems: &problems, counts: &counts, runs, seed };
    let (slots, subsets) = draw_slots(&draw)?;

    journaled.retain(|key, _| slots.iter().any(|slot| slot.key == *key));
    if skipped > 0 {
        note(&format!(
            "skipped {skipped} unreadable or self-contradicting line(s) of {}; their solves run again",
            journal_path.display()
        ));
    }
    let mut journal = Journal::open(&journal_path, &settings.key)?;
    let work = subset_work(&slots, &journaled, &subsets);
    let reused = slots.iter().filter(|slot| journaled.contains_key(&slot.key)).count();
    let through = match args.executor {
        Some(_) => format!(" through `{}`", executor.text()),
        None => String::new(),
    };
    note(&plan_note(&draw, slots.len(), reused, jobs, &through));

    let context = BuildContext {
        spec: &spec,
        spec_file: &checked.file_name,
        world: &world,
        adapter: &adapter,
        model_file_limit: crate::files::MODEL_FILE_LIMIT,
    };
    let kept_models = args.keep_models.then(|| KeptModels::new(&out, &slots));
    let learn = |work: &SubsetWork| {
        learn(&context, &pool.demonstrations, work, kept_models.as_ref(), &render)
    };
    let model_sources = lamp_build::SpecSources::of(&spec, &world).model;
    let schedule_settings = schedule::Settings {
        spec: &args.spec,
        spec_text: checked.sources.text(lamp_lang::FileId(0)),
        model_sources: &model_sources,
        seed,
        timeout: args.timeout,
        jobs,
        executor: &executor,
    };
    let mut results = BTreeMap::new();
    let ending = run_solves(
        &schedule_settings,
        work,
        &learn,
        &slots,
        &journaled,
        &mut results,
        &mut journal,
    )?;
    let solved_again =
        journaled.keys().filter(|key| results.get(*key).is_some_and(|(_, fresh)| *fresh)).count();
    if solved_again > 0 {
        note(&format!(
            "solved {solved_again} journaled solve(s) again: this lampc learns another model for them; the earlier rows stay in {} and are reported apart",
            journal_path.display()
        ));
    }
    // Solved by this run, for the time line: a row from the journal took its time earlier.
    let solved_now: Vec<Row> =
        results.values().filter(|(_, fresh)| *fresh).map(|(row, _)| row.clone()).collect();
    let results: BTreeMap<Key, Row> =
        results.into_iter().map(|(key, (row, _))| (key, row)).collect();
    let kept = slots
        .iter()
        .filter(|slot| results.contains_key(&slot.key) || journaled.contains_key(&slot.key))
        .count();
    if !completed(ending, kept, slots.len(), &journal_path)? {
        return Ok(false);
    }

    let rows: Vec<Row> = slots
        .iter()
        .filter_map(|slot| {
            let row = results.get(&slot.key)?;
            Some(Row { demos: slot.demos, run: slot.run, objects: slot.objects, ..row.clone() })
        })
        .collect();
    let earlier = earlier_rows(&slots, &journaled, &results);
    let info = eval_info(&checked.file_name, &draw, settings);
    write_outputs(&out, &info, &rows, &earlier)?;
    let from_journal = results.len() - solved_now.len();
    print_summary(&info, &rows, &out, (&solved_now, from_journal, started.elapsed()));
    Ok(true)
}

/// The evaluation's settings from its flags (besides the seed and the problems).
struct Options {
    /// The counts of `--demos`, if given.
    counts: Option<Vec<usize>>,
    build_dir: PathBuf,
    out: PathBuf,
    runs: usize,
    jobs: usize,
    executor: Executor,
}

/// Reads the flags, for a spec in `spec_dir`.
fn options(args: &Args, spec_dir: &Path) -> Result<Options, Failure> {
    let counts = demonstration_counts(args)?;
    let build_dir = spec_dir.join(lamp_build::DEFAULT_BUILD_DIR);
    let out = args.out.clone().unwrap_or_else(|| build_dir.join("eval"));
    let runs = args.runs as usize;
    let jobs = match args.jobs {
        Some(jobs) => jobs as usize,
        None => std::thread::available_parallelism().map_or(1, NonZeroUsize::get),
    };
    let executor = executor_of(args, jobs)?;
    Ok(Options { counts, build_dir, out, runs, jobs, executor })
}

/// The counts of `--demos`, if given, each within the bounds of `lampc demos --count` and the
/// spec's `count`.
fn demonstration_counts(args: &Args) -> Result<Option<Vec<usize>>, Failure> {
    let counts = args.demos.as_deref().map(lamp_eval::parse_counts).transpose()?;
    for count in counts.iter().flatten() {
        lamp_spec::limits::DEMONSTRATIONS.count(*count as f64).map_err(EvaluationError::Demos)?;
    }
    Ok(counts)
}

/// The command each solve runs in: `--executor`'s, checked to be there, or this binary's worker.
fn executor_of(args: &Args, jobs: usize) -> Result<Executor, executor::ExecutorError> {
    match &args.executor {
        Some(text) => {
            let executor = Executor::parse(text)?;
            executor.check_program()?;
            Ok(executor)
        }
        None => Executor::local(jobs),
    }
}

/// What the solves of an evaluation are drawn from.
struct Draw<'a> {
    spec: &'a Spec,
    pool: &'a pool::Pool,
    problems: &'a [&'a Problem],
    counts: &'a [usize],
    runs: usize,
    seed: u64,
}

/// A drawn subset's digest and its indices into the pool, by the digest's text.
type Subsets = BTreeMap<String, (lamp_build::Digest, Vec<usize>)>;

/// Every solve in order; subsets drawn, their digests taken.
fn draw_slots(draw: &Draw<'_>) -> Result<(Vec<Slot>, Subsets), lamp_eval::EvalError> {
    let mut slots = Vec::new();
    let mut subsets = Subsets::new();
    for &count in draw.counts {
        for run in 1..=draw.runs {
            let indices = lamp_eval::draw_subset(&draw.pool.entries, count, draw.seed, run)?;
            let files: Vec<DemoFile> =
                indices.iter().map(|&i| draw.pool.files[i].clone()).collect();
            let digest = lamp_build::demonstration_digest(&files);
            subsets.entry(digest.to_string()).or_insert((digest, indices));
            for problem in draw.problems {
                slots.push(Slot {
                    demos: count,
                    run,
                    problem: problem.name.clone(),
                    objects: objects_of(draw.spec, problem),
                    key: (digest.to_string(), problem.name.clone()),
                });
            }
        }
    }
    Ok((slots, subsets))
}

/// Every subset with its problems, in the order of their first solve, and the models their rows
/// in the journal were solved with: every subset is learned, since only the model it gives now
/// tells whether a journaled row still answers the solve.
fn subset_work(
    slots: &[Slot],
    journaled: &BTreeMap<Key, Vec<Row>>,
    subsets: &Subsets,
) -> Vec<SubsetWork> {
    let mut work: Vec<SubsetWork> = Vec::new();
    for slot in slots {
        let subset = &slot.key.0;
        let index = match work.iter().position(|work| work.digest.to_string() == *subset) {
            Some(index) => index,
            None => {
                let (digest, indices) = subsets[subset].clone();
                let journaled = BTreeMap::new();
                work.push(SubsetWork { digest, indices, problems: Vec::new(), journaled });
                work.len() - 1
            }
        };
        let entry = &mut work[index];
        if entry.problems.contains(&slot.problem) {
            continue;
        }
        entry.problems.push(slot.problem.clone());
        let models = journaled.get(&slot.key).into_iter().flatten();
        let models: Vec<String> = models.filter_map(|row| row.model.clone()).collect();
        if !models.is_empty() {
            entry.journaled.insert(slot.problem.clone(), models);
        }
    }
    work
}

/// The journal's rows for the evaluation's solves that another model answered, in slot order:
/// an earlier learner's, kept apart from the figures.
fn earlier_rows(
    slots: &[Slot],
    journaled: &BTreeMap<Key, Vec<Row>>,
    results: &BTreeMap<Key, Row>,
) -> Vec<Row> {
    let mut seen = std::collections::BTreeSet::new();
    let mut earlier = Vec::new();
    for slot in slots {
        let Some(current) = results.get(&slot.key) else { continue };
        if !seen.insert(&slot.key) {
            continue;
        }
        let others = journaled.get(&slot.key).into_iter().flatten();
        earlier.extend(others.filter(|row| row.model != current.model).cloned());
    }
    earlier
}

/// Runs the solves with a progress bar, each new result journalled as it comes, into `results`
/// by key with whether it was solved now (`false`: the journal's row for the same model); an
/// error is a journal line that could not be written.
fn run_solves(
    schedule_settings: &schedule::Settings<'_>,
    work: Vec<SubsetWork>,
    learn: &(dyn Fn(&SubsetWork) -> Learned + Sync),
    slots: &[Slot],
    journaled: &BTreeMap<Key, Vec<Row>>,
    results: &mut BTreeMap<Key, (Row, bool)>,
    journal: &mut Journal,
) -> Result<Ending, EvaluationError> {
    let progress = progress_bar(slots.len() as u64);
    let solved_in = |results: &BTreeMap<Key, (Row, bool)>| {
        let solved = |slot: &&Slot| results.get(&slot.key).is_some_and(|(row, _)| row.solved);
        slots.iter().filter(solved).count()
    };
    progress.set_message("0 solved".to_string());
    let mut write_error = None;
    let current = RefCell::new(String::new());
    let ending = schedule::run(
        schedule_settings,
        work,
        learn,
        &|| INTERRUPTED.load(Ordering::Relaxed),
        &mut |problem| *current.borrow_mut() = problem.to_string(),
        &mut |error| {
            let code = error.code().map(|code| format!(" ({code})")).unwrap_or_default();
            let why = std::error::Error::source(error)
                .map(|source| format!(": {source}"))
                .unwrap_or_default();
            progress.suspend(|| {
                eprintln!("lampc eval: {error}{why}{code}; trying that solve once more");
            });
        },
        &mut |done: Done| {
            let Some(first) = slots.iter().find(|slot| slot.key == done.key) else { return };
            let entry = match done.result {
                Some(result) => {
                    let mut row = Row::new(
                        first.demos,
                        first.run,
                        &first.problem,
                        first.objects,
                        &first.key.0,
                        result,
                        Some(done.seconds_learning),
                    );
                    row.commit = Some(env!("LAMP_SOURCE_COMMIT").to_string());
                    row.model = Some(done.model);
                    if let Err(error) = journal.append(&row) {
                        write_error.get_or_insert(error);
                    }
                    (row, true)
                }
                None => {
                    let same = journaled.get(&done.key).and_then(|rows| {
                        rows.iter().rfind(|row| row.model.as_ref() == Some(&done.model))
                    });
                    let Some(row) = same else { return };
                    (row.clone(), false)
                }
            };
            results.insert(done.key.clone(), entry);
            let finished = slots.iter().filter(|slot| slot.key == done.key).count();
            progress.inc(finished as u64);
            progress.set_message(format!("{} · {} solved", current.borrow(), solved_in(results)));
        },
    );
    progress.finish_and_clear();
    if let Some(error) = write_error {
        return Err(error);
    }
    Ok(ending)
}

/// The line that says what the evaluation is about to do.
fn plan_note(draw: &Draw<'_>, slots: usize, reused: usize, jobs: usize, through: &str) -> String {
    let (runs, pool) = (draw.runs, draw.pool);
    format!(
        "{} solves ({} count(s) × {runs} run(s) × {} problem(s)), {reused} already in the journal; {} demonstrations in the pool ({} cut{}); {jobs} at once{through}",
        slots,
        draw.counts.len(),
        draw.problems.len(),
        pool.files.len(),
        pool.entries.iter().filter(|demo| demo.cut).count(),
        if pool.generated > 0 { format!(", {} generated", pool.generated) } else { String::new() },
    )
}

/// Whether every solve ran: when interrupted it says so and how many of the `total` solves are
/// `kept` in the journal; a broken executor is an error that says the same.
fn completed(
    ending: Ending,
    kept: usize,
    total: usize,
    journal_path: &Path,
) -> Result<bool, Stopped> {
    match ending {
        Ending::Complete => Ok(true),
        Ending::Interrupted => {
            eprintln!(
                "lampc eval: interrupted; {} of {} solves are kept in {}; run the same command again to continue",
                kept,
                total,
                journal_path.display()
            );
            Ok(false)
        }
        Ending::Broken(error) => Err(Stopped {
            notes: vec![format!(
                "stopped by the executor's failure, which is not recorded as a result; {} of {} solves are kept in {}; run the same command again to continue",
                kept,
                total,
                journal_path.display()
            )],
            ..Stopped::from(error)
        }),
    }
}

/// What `eval.json` says of the evaluation besides its rows.
fn eval_info(spec_file: &str, draw: &Draw<'_>, settings: SettingsInfo) -> EvalInfo {
    let pool = draw.pool;
    EvalInfo {
        spec: spec_file.to_string(),
        domain: draw.spec.domain.clone(),
        seed: draw.seed,
        counts: draw.counts.to_vec(),
        runs: draw.runs,
        problems: draw
            .problems
            .iter()
            .map(|problem| ProblemInfo {
                name: problem.name.clone(),
                objects: objects_of(draw.spec, problem),
            })
            .collect(),
        pool: PoolInfo {
            demonstrations: pool.files.len(),
            cut: pool.entries.iter().filter(|demo| demo.cut).count(),
            generated: pool.generated,
            max_objects: pool.entries.iter().map(|demo| demo.objects).max().unwrap_or(0),
            digest: lamp_build::demonstration_digest(&pool.files).to_string(),
        },
        settings,
    }
}

/// The spec's problems whose names match one of the comma-separated globs of `filter` (all
/// without a filter), in spec order; a glob that matches nothing is an error.
fn select_problems<'a>(
    spec: &'a Spec,
    spec_file: &str,
    filter: Option<&str>,
) -> Result<Vec<&'a Problem>, EvaluationError> {
    let Some(filter) = filter else { return Ok(spec.problems.iter().collect()) };
    let names: Vec<&str> = spec.problems.iter().map(|problem| problem.name.as_str()).collect();
    let mut patterns = Vec::new();
    for text in filter.split(',').map(str::trim) {
        let pattern = glob::Pattern::new(text).map_err(|error| EvaluationError::BadPattern {
            spec_file: spec_file.to_string(),
            pattern: text.to_string(),
            reason: error.to_string(),
        })?;
        if !names.iter().any(|name| pattern.matches(name)) {
            return Err(EvaluationError::NoProblem {
                spec_file: spec_file.to_string(),
                pattern: text.to_string(),
                names: names.join(", "),
            });
        }
        patterns.push(pattern);
    }
    Ok(spec
        .problems
        .iter()
        .filter(|problem| patterns.iter().any(|pattern| pattern.matches(&problem.name)))
        .collect())
}

/// A test problem's objects: its scene's objects of a movable type.
fn objects_of(spec: &Spec, problem: &Problem) -> usize {
    let movable = pool::movable_types(spec);
    problem
        .scene
        .objects
        .iter()
        .filter(|object| movable.contains(object.type_name.as_str()))
        .count()
}

/// Refuses an output folder inside a build's model folder (one holding a build manifest): the next
/// `lampc build` replaces that folder whole, and the evaluation's journal and results with it.
fn refuse_out_in_a_model_folder(out: &Path) -> Result<(), EvaluationError> {
    let absolute = std::path::absolute(out).unwrap_or_else(|_| out.to_path_buf());
    for folder in absolute.ancestors() {
        // Links resolved where they exist, so that a link into a model folder is seen too.
        let folder = std::fs::canonicalize(folder).unwrap_or_else(|_| folder.to_path_buf());
        if folder.join(lamp_build::MANIFEST_FILE).is_file() {
            return Err(EvaluationError::OutInModel {
                out: out.display().to_string(),
                model: folder.display().to_string(),
            });
        }
    }
    Ok(())
}

/// What every solve uses, described, and the digest that keys the journal: lampc's version, the
/// whole checked spec (with the evaluation's seed) and the time limit. Not the executable or its
/// commit: rows accumulate across builds, each reused only while the learner gives the same model
/// (`journal`), so figures grow over many commits.
fn settings_info(
    spec: &Spec,
    spec_dir: &Path,
    spec_file: &str,
    timeout: Option<f64>,
) -> Result<SettingsInfo, PluginSetupError> {
    let overrides = Overrides::default();
    let choice =
        |spec_choice: &PluginChoice| crate::plugin_setup::chosen(spec_choice, spec_dir, None);
    let (planner, motion) = (choice(&spec.plugins.planner), choice(&spec.plugins.motion));
    // Set up now, so that a broken plugin block stops the evaluation before any solve.
    let mut runtime = crate::plugin_setup::RuntimeOptions::default();
    crate::plugin_setup::planner(&planner, &mut runtime)
        .map_err(|error| PluginSetupError::new(spec_file, "planner", error))?;
    crate::plugin_setup::motion(&motion, &mut runtime)
        .map_err(|error| PluginSetupError::new(spec_file, "motion", error))?;
    let never = || false;
    let solve = solve_setup::settings(spec, &runtime, &overrides, &never);
    let text = format!("lampc {}\n{spec:?}\ntimeout {timeout:?}\n", env!("CARGO_PKG_VERSION"));
    let key = lamp_build::demonstration_digest(&[DemoFile {
        name: "lampc eval settings".to_string(),
        bytes: text.into_bytes(),
    }]);
    Ok(SettingsInfo {
        planner: plugin_text(&planner),
        refiner: plugin_text(&choice(&spec.plugins.refiner)),
        motion: plugin_text(&motion),
        plans: solve.plan_count,
        rounds: solve.rounds,
        max_refused: solve.max_refused,
        motion_iterations: solve.motion.budget.max_iterations.unwrap_or(0),
        relax_goal: solve.relax_goal,
        timeout,
        key: key.to_string(),
    })
}

/// A plugin as its name (or library path) and its options, e.g. `gbfs-ff (timeout 30 s)`.
fn plugin_text(choice: &PluginChoice) -> String {
    let name = match &choice.source {
        PluginSource::Builtin(name) => name.clone(),
        PluginSource::Library(path) => path.display().to_string(),
    };
    if choice.options.is_empty() {
        return name;
    }
    let options: Vec<String> = choice
        .options
        .iter()
        .map(|(key, value)| match value {
            OptionValue::Number(v) => format!("{key} {v}"),
            OptionValue::Length(v) => format!("{key} {v} m"),
            OptionValue::Angle(v) => format!("{key} {v} rad"),
            OptionValue::Duration(v) => format!("{key} {v} s"),
            OptionValue::Text(text) | OptionValue::Word(text) => format!("{key} {text}"),
        })
        .collect();
    format!("{name} ({})", options.join(", "))
}

/// Learns a subset's model and takes the artifacts a solve reads out of the build's: the
/// problems of the subset's solves are written together, and, when that fails, each on its own,
/// so that a goal one problem cannot state fails that problem's solves only.
fn learn(
    context: &BuildContext<'_>,
    demonstrations: &[lamp_learn::Demonstration],
    work: &SubsetWork,
    kept_models: Option<&KeptModels>,
    render: &dyn Fn(&dyn miette::Diagnostic) -> String,
) -> Learned {
    let started = Instant::now();
    let subset: Vec<lamp_learn::Demonstration> =
        work.indices.iter().map(|&index| demonstrations[index].clone()).collect();
    let model = lamp_build::learn_model(context.spec, context.world, &subset)
        .map_err(|error| reason(&error))
        .and_then(|model| {
            let names: Vec<&str> = work.problems.iter().map(String::as_str).collect();
            let selected = with_problems(context.spec, &names);
            let together = BuildContext { spec: &selected, ..*context };
            let emitted = lamp_build::artifacts(&together, &model, &subset, work.digest);
            if let Some(kept_models) = kept_models {
                match &emitted {
                    Ok(artifacts) => kept_models.write(work, &artifacts.files, render),
                    Err(_) => {
                        let report =
                            lamp_build::learned_vocabulary(&together, &model, &subset, work.digest);
                        kept_models.write_failed(work, &report, render);
                    }
                }
            }
            match emitted {
                Ok(artifacts) => model_of(&artifacts, &work.problems),
                Err(error) => {
                    let emit = |names: &[&str]| {
                        let spec = with_problems(context.spec, names);
                        let alone = BuildContext { spec: &spec, ..*context };
                        lamp_build::artifacts(&alone, &model, &subset, work.digest)
                    };
                    // Without any problem, a failure is the model's own, and every solve's.
                    let base = emit(&[]).map_err(|_| reason(&error))?;
                    let mut written = model_of(&base, &[])?;
                    for name in &names {
                        let problem = match emit(&[name]) {
                            Ok(artifacts) => problem_of(&artifacts, name),
                            Err(error) => Err(reason(&error)),
                        };
                        written.problems.insert((*name).to_string(), problem);
                    }
                    Ok(written)
                }
            }
        });
    let models = work
        .problems
        .iter()
        .map(|name| {
            let digest = match &model {
                Ok(model) => match &model.problems[name] {
                    Ok(pddl) => model_digest(&[&model.domain, &model.samplers, pddl]),
                    Err(reason) => model_digest(&[&model.domain, &model.samplers, "", reason]),
                },
                Err(reason) => model_digest(&["", "", "", reason]),
            };
            (name.clone(), digest)
        })
        .collect();
    Learned {
        digest: work.digest.to_string(),
        seconds: started.elapsed().as_secs_f64(),
        model,
        problems: work.problems.clone(),
        models,
        journaled: work.journaled.clone(),
    }
}

/// `spec` with only the problems named in `names`, in the spec's order.
fn with_problems(spec: &Spec, names: &[&str]) -> Spec {
    let problems =
        spec.problems.iter().filter(|problem| names.contains(&problem.name.as_str())).cloned();
    Spec { problems: problems.collect(), ..spec.clone() }
}

/// Why a model or a problem could not be written, on one line with its code.
fn reason(error: &lamp_build::BuildError) -> String {
    let code = error.code().map(|code| format!("{code}: ")).unwrap_or_default();
    one_line(&format!("{code}{error}"))
}

/// The text of the build's file at `path`, if it wrote one.
fn text_of(artifacts: &lamp_build::Artifacts, path: &Path) -> Option<String> {
    artifacts.files.iter().find(|file| file.path == path).map(|file| file.contents.clone())
}

/// What a solve reads of a build: the domain, the sampler file and each of `problems`.
fn model_of(artifacts: &lamp_build::Artifacts, problems: &[String]) -> Result<Model, String> {
    let missing = |what: &str| format!("the build wrote no {what}");
    let domain =
        text_of(artifacts, Path::new(lamp_build::DOMAIN_FILE)).ok_or_else(|| missing("domain"))?;
    let samplers = text_of(artifacts, Path::new(lamp_build::SAMPLERS_FILE))
        .ok_or_else(|| missing("sampler file"))?;
    let problems =
        problems.iter().map(|name| (name.clone(), problem_of(artifacts, name))).collect();
    Ok(Model { domain, samplers, problems })
}

/// The PDDL of problem `name`, or why the build skipped it.
fn problem_of(artifacts: &lamp_build::Artifacts, name: &str) -> Result<String, String> {
    let path = Path::new(lamp_build::PROBLEMS_DIR).join(format!("{name}.pddl"));
    let skipped = artifacts.summary.problems_skipped.iter().find(|(n, _)| n == name);
    text_of(artifacts, &path).ok_or_else(|| {
        skipped.map_or_else(|| "not written".to_string(), |(_, reason)| one_line(reason))
    })
}

/// Writes the five outputs as one set: every one into a temporary file beside it first, and only
/// when all are written are they renamed into place, so that a failed write (a full disk) leaves
/// the previous set whole, never new figures beside an old report. The journal beside them stays.
fn write_outputs(
    out: &Path,
    info: &EvalInfo,
    rows: &[Row],
    earlier: &[Row],
) -> Result<(), EvaluationError> {
    let json = EvalDocument::new(info.clone(), rows.to_vec()).to_json().map_err(|error| {
        EvaluationError::Encode { what: "eval.json", reason: error.to_string() }
    })?;
    let csv = lamp_eval::csv(rows);
    let report = lamp_eval::report(info, rows, earlier);
    let success = lamp_eval::success_plot(info, rows);
    let efficiency = lamp_eval::sample_efficiency_plot(info, rows);
    let files: [(&str, &[u8]); 5] = [
        ("eval.json", json.as_bytes()),
        ("eval.csv", csv.as_bytes()),
        ("report.md", report.as_bytes()),
        (lamp_eval::SUCCESS_PLOT_FILE, success.as_bytes()),
        (lamp_eval::EFFICIENCY_PLOT_FILE, efficiency.as_bytes()),
    ];
    std::fs::create_dir_all(out).map_err(|error| EvaluationError::io("create", out, error))?;
    let temporary = |name: &str| out.join(format!(".{name}.tmp"));
    let remove_temporaries = || {
        for (name, _) in &files {
            let _ = std::fs::remove_file(temporary(name));
        }
    };
    for (name, contents) in &files {
        let path = temporary(name);
        let written = std::fs::File::create(&path)
            .and_then(|mut file| file.write_all(contents).and_then(|()| file.sync_all()));
        if let Err(error) = written {
            remove_temporaries();
            let consequence = format!("; the previous results in {} are unchanged", out.display());
            return Err(EvaluationError::Io { action: "write", path, error, consequence });
        }
    }
    for (name, _) in &files {
        let path = out.join(name);
        if let Err(error) = std::fs::rename(temporary(name), &path) {
            remove_temporaries();
            return Err(EvaluationError::io("move into place", path, error));
        }
    }
    Ok(())
}

/// Prints the figures of `rows`, then the time line of `timing`: the rows solved now, how many
/// distinct solves came from the journal, and the wall time.
fn print_summary(info: &EvalInfo, rows: &[Row], out: &Path, timing: (&[Row], usize, Duration)) {
    println!("{}: evaluated {} solves into {}", info.spec, rows.len(), out.display());
    for summary in lamp_eval::efficiency(info, rows) {
        let percent = |value: Option<f64>| {
            value.map_or_else(|| "—".to_string(), |v| format!("{:.1} %", v * 100.0))
        };
        println!(
            "  {:>5} demos     {} ± {} solved over {} run(s)",
            summary.count,
            percent(summary.mean),
            percent(summary.std),
            summary.runs.len()
        );
    }
    let g = lamp_eval::generalization(info, rows);
    match (g.factor, g.test_objects) {
        (Some(factor), Some(test)) => println!(
            "  generalization  {factor:.1}× ({test} objects solved ÷ {} in a demonstration)",
            g.training_objects
        ),
        _ => println!("  generalization  none: no test problem solved"),
    }
    let (solved_now, from_journal, elapsed) = timing;
    println!("{}", time_line(solved_now, from_journal, elapsed));
}

/// The summary's last line: the solving time of the solves run now, the wall time of the
/// evaluation, and how many solves the journal gave (their time was spent by an earlier run).
fn time_line(solved_now: &[Row], from_journal: usize, elapsed: Duration) -> String {
    // Summed from +0.0: `Sum` for floats starts at -0.0, which prints as "-0.0 s" when no row
    // was solved (every build failed, or every row came from the journal).
    let solving =
        solved_now.iter().filter_map(|row| row.result.seconds_solving).fold(0.0, |sum, s| sum + s);
    let journal = match from_journal {
        0 => String::new(),
        n => format!("; {n} from the journal"),
    };
    format!(
        "  time            {:.1} s of solving in {:.1} s ({} solve(s) run now{journal})",
        solving,
        elapsed.as_secs_f64(),
        solved_now.len()
    )
}

/// One bar for the whole evaluation on a terminal, nothing otherwise.
fn progress_bar(length: u64) -> ProgressBar {
    let bar = crate::terminal::progress_bar(
        length,
        "evaluating [{bar:30}] {pos}/{len} {elapsed} (eta {eta}) {wide_msg}",
    );
    if !bar.is_hidden() {
        bar.enable_steady_tick(Duration::from_millis(200));
    }
    bar
}

#[cfg(test)]
mod tests {
    use super::*;
    use lamp_eval::{Outcome, SolveResult};

    #[test]
    fn rows_without_a_solving_time_add_up_to_zero_seconds_not_minus_zero() {
        let failed = SolveResult::failed(Outcome::BuildFailed, "learning failed");
        let rows = [Row::new(30, 1, "pack2", 2, "fnv1a64:0", failed, Some(0.5))];
        let line = time_line(&rows, 0, Duration::from_millis(1500));
        assert_eq!(line, "  time            0.0 s of solving in 1.5 s (1 solve(s) run now)");
        let line = time_line(&[], 3, Duration::ZERO);
        assert_eq!(
            line,
            "  time            0.0 s of solving in 0.0 s (0 solve(s) run now; 3 from the journal)"
        );
    }
}
