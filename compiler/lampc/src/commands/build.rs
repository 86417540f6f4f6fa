//! `lampc build`: learn regions, relations and actions from demonstration files; write the PDDL
//! domain and problems, the sampler file and the vocabulary report into the build folder.
//!
//! The work is lamp-build's; this module finds and reads the files, shows progress, and prints the
//! summary. The artifacts and their manifest make up the model folder `<build>/model/`, which is
//! replaced as a whole once every artifact is computed (written into a staging folder beside it,
//! then swapped in), under a lock that refuses a second build into the same folder.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use indicatif::ProgressBar;
use lamp_build::{Adapter, ArtifactFile, Artifacts, BuildContext, BuildError, DemoFile};

use crate::commands::{Failure, Finished, Outcome, Stopped};
use crate::output::{FolderLock, OutputError, OutputFolder, Replaced};

/// Arguments of `lampc build`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The `.lamp` spec file.
    pub(crate) spec: PathBuf,
    /// The build folder [default: `build/` beside the spec].
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    /// Read demonstrations from `DIR/*.mcap` instead of the spec's sources.
    #[arg(long, value_name = "DIR")]
    pub(crate) demos: Option<PathBuf>,
}

/// Wall-clock time per phase, for the summary.
#[derive(Default)]
struct Timings(Vec<(&'static str, Duration)>);

impl Timings {
    fn time<T>(&mut self, phase: &'static str, work: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let result = work();
        self.0.push((phase, start.elapsed()));
        result
    }
}

pub(crate) fn run(args: &Args) -> Outcome {
    let colour = crate::terminal::colour();
    let mut model = None;
    let stopped = match build(args, colour, &mut model) {
        Ok(()) => return Ok(Finished::Done),
        Err(stopped) if stopped.left.is_some() || matches!(stopped.failure, Failure::Said) => {
            return Err(stopped);
        }
        Err(stopped) => stopped,
    };
    let outcome = match model {
        Some(model) if model.is_dir() => format!("the model in {} is unchanged", model.display()),
        _ => "no model was written".to_string(),
    };
    Err(stopped.leaving(outcome))
}

/// Reads the demonstration files at `paths` (named relative to `names_base`), bags of standard
/// messages through the spec's mappings, with a progress bar: the files and the learner's
/// demonstrations made from them.
fn read_demonstrations(
    paths: &[PathBuf],
    names_base: &Path,
    bags: &mut BagMappings<'_>,
    world: &lamp_world::SpecWorld,
    adapter: &Adapter,
) -> Result<(Vec<DemoFile>, Vec<lamp_learn::Demonstration>), BuildError> {
    let progress = progress_bar(paths.len() as u64, "reading demonstrations");
    let mut files = Vec::with_capacity(paths.len());
    let mut demonstrations = Vec::with_capacity(paths.len());
    for path in paths {
        let name = lamp_build::demo_name(path, names_base);
        progress.set_message(name.clone());
        let limit = crate::files::DEMONSTRATION_FILE_LIMIT;
        let read = crate::files::read_limited(path, limit, "demonstration file");
        let bytes = read.map_err(|error| BuildError::Read {
            file: path.display().to_string(),
            reason: error.to_string(),
        })?;
        let file = bags.read(world, path, DemoFile { name, bytes })?;
        demonstrations.push(adapter.demonstration(&file)?);
        files.push(file);
        progress.inc(1);
    }
    progress.finish_and_clear();
    Ok((files, demonstrations))
}

/// Runs the build; `model` is set to the model folder as soon as it is known, for the last message.
fn build(args: &Args, colour: bool, model: &mut Option<PathBuf>) -> Result<(), Stopped> {
    let mut timings = Timings::default();
    // With `--demos DIR` the spec's own sources are not read, so their patterns need not match.
    let demonstrations = match args.demos {
        Some(_) => crate::spec_input::Demonstrations::Unread,
        None => crate::spec_input::Demonstrations::Read,
    };
    let checked =
        timings.time("check", || crate::spec_input::check_spec(&args.spec, colour, demonstrations));
    let Some(crate::spec_input::CheckedSpec {
        spec,
        dir: spec_dir,
        file_name: spec_file,
        sources,
        places,
    }) = checked
    else {
        return Err(Stopped::said());
    };
    let build_dir =
        args.out.clone().unwrap_or_else(|| spec_dir.join(lamp_build::DEFAULT_BUILD_DIR));

    let world = timings
        .time("load", || lamp_world::SpecWorld::load(&spec_dir, &spec).map_err(BuildError::from))?;
    let adapter = Adapter::new(&spec, &world.robots)?;
    // Before any demonstration is read: a scene the solver cannot start from is a broken spec.
    let refused =
        crate::spec_input::refuse_scenes(&spec, (&places, &sources), &world, None, colour);
    if refused > 0 {
        eprintln!(
            "lampc build: {refused} finding(s) in the problems' initial scenes, which the solver cannot start from; no model was written"
        );
        return Err(Stopped::said());
    }
    let paths = find_demonstrations(&spec, &spec_dir, &build_dir, args.demos.as_deref())?;
    let mut bags = BagMappings::new(&spec, &spec_dir, args.demos.as_deref());
    let folder = OutputFolder::new(&build_dir.join(lamp_build::MODEL_DIR))?;
    *model = Some(folder.path().to_path_buf());
    let lock = folder.lock("build")?;
    replaceable(folder.path())?;
    folder.remove_leftovers(&lock);
    let names_base = args.demos.clone().unwrap_or_else(|| spec_dir.clone());

    let (files, demonstrations) = timings
        .time("read", || read_demonstrations(&paths, &names_base, &mut bags, &world, &adapter))?;
    if let Err((source, error)) = bags.check() {
        let place = match &error {
            lamp_build::Ros2Error::FrameInNoBag { object, .. } => {
                places.mapped_object(source, object)
            }
            _ => None,
        };
        let rendered = crate::diagnostics::render_frame_in_no_bag(&error, place, &sources, colour);
        eprint!("{rendered}");
        return Err(Stopped::said().leaving("no model was written"));
    }

    let model = timings.time("learn", || {
        let spinner = spinner("learning regions, relations and actions");
        let model = lamp_build::learn_model(&spec, &world, &demonstrations);
        spinner.finish_and_clear();
        model
    })?;

    let context = BuildContext {
        spec: &spec,
        spec_file: &spec_file,
        world: &world,
        adapter: &adapter,
        model_file_limit: crate::files::MODEL_FILE_LIMIT,
    };
    let digest = lamp_build::demonstration_digest(&files);
    let emitted =
        timings.time("emit", || lamp_build::artifacts(&context, &model, &demonstrations, digest));
    if emitted.is_err() {
        // The model was learned but cannot be written as it is: what it holds says why.
        let report = lamp_build::learned_vocabulary(&context, &model, &demonstrations, digest);
        write_failed_report(&build_dir, &report);
    }
    let artifacts = match emitted {
        Err(BuildError::Structures { problems, issues }) => {
            eprintln!(
                "lampc build: {problems} problem(s) have structure goals that cannot be written:\n"
            );
            for issue in &issues {
                let rendered =
                    crate::diagnostics::render_structure_issue(issue, &places, &sources, colour);
                eprint!("{rendered}");
            }
            return Err(Stopped::said().leaving("the model folder was not changed"));
        }
        emitted => emitted?,
    };
    let replaced =
        timings.time("write", || write_all(&folder, &lock, &artifacts.files)).map_err(|error| {
            // A swap that failed half way says itself what became of the model folder.
            let state = match &error {
                OutputError::Swap { state, .. } => Some(state.clone()),
                _ => None,
            };
            let stopped = Stopped::from(error);
            match state {
                Some(state) => stopped.leaving(state),
                None => stopped,
            }
        })?;
    remove_failed_report(&build_dir);
    print_summary(&spec_file, folder.path(), &artifacts, &bags.absences(), &timings);
    for warning in &artifacts.summary.grab_warnings {
        eprint!("{}", crate::diagnostics::render_grab_warning(warning, &places, &sources, colour));
    }
    for warning in &artifacts.summary.warnings {
        eprint!("{}", crate::diagnostics::render_goal_warning(warning, &places, &sources, colour));
    }
    if let Some((kept, reason)) = replaced.kept {
        eprintln!(
            "lampc build: warning: the previous model, moved to {}, could not be removed: {reason}",
            kept.display()
        );
    }
    Ok(())
}

/// Every demonstration file of the spec (or of `--demos`), sorted and without duplicates; what
/// else the patterns match (a folder, a link to nothing) is skipped with a warning.
pub(crate) fn find_demonstrations(
    spec: &lamp_spec::Spec,
    spec_dir: &Path,
    build_dir: &Path,
    demos: Option<&Path>,
) -> Result<Vec<PathBuf>, BuildError> {
    let patterns = lamp_build::demo_patterns(spec, spec_dir, build_dir, demos);
    let mut paths = BTreeSet::new();
    for pattern in &patterns {
        let (files, warnings) = crate::files::glob_files(pattern);
        for warning in warnings {
            eprintln!("lampc build: warning: {warning}");
        }
        paths.extend(files);
    }
    if paths.is_empty() {
        let searched: Vec<String> =
            patterns.iter().map(|pattern| format!("`{}`", pattern.display())).collect();
        let searched = if searched.is_empty() {
            "the spec declares no demonstration source".to_string()
        } else {
            searched.join(", ")
        };
        return Err(BuildError::NoDemonstrations { searched });
    }
    Ok(paths.into_iter().collect())
}

/// Which demonstration files are ROS 2 bags read through a frame mapping: those a
/// `files … as ros2 { … }` source matches (the first such source's mapping), and, with
/// `--demos DIR`, every file of DIR that holds no `lamp` record when the spec has exactly one
/// such source; and, per source, what the bags read so far lacked.
pub(crate) struct BagMappings<'a> {
    /// Each `files … as ros2` source: its pattern, its mapping, and what its bags lacked.
    sources: Vec<(&'a str, &'a lamp_spec::Ros2Mapping, lamp_build::BagTally)>,
    /// Per bag a source matches, the index of that source.
    by_path: BTreeMap<PathBuf, usize>,
    fallback: Option<usize>,
    /// With `--demos DIR`, `DIR/*.mcap`: where the bags came from, for messages.
    read_from: Option<String>,
}

impl<'a> BagMappings<'a> {
    /// The bags of `spec`'s sources, or with `demos` (`--demos DIR`), those of DIR.
    pub(crate) fn new(spec: &'a lamp_spec::Spec, spec_dir: &Path, demos: Option<&Path>) -> Self {
        let sources: Vec<_> = spec
            .demonstrations
            .iter()
            .filter_map(|source| match source {
                lamp_spec::DemoSource::Files { pattern, ros2: Some(mapping) } => {
                    Some((pattern.as_str(), mapping, lamp_build::BagTally::new(mapping)))
                }
                _ => None,
            })
            .collect();
        let mut by_path = BTreeMap::new();
        let mut fallback = None;
        if demos.is_some() {
            fallback = (sources.len() == 1).then_some(0);
        } else {
            for (index, (pattern, _, _)) in sources.iter().enumerate() {
                for path in crate::files::glob_files(&spec_dir.join(pattern)).0 {
                    by_path.entry(path).or_insert(index);
                }
            }
        }
        let read_from = demos.map(|dir| dir.join("*.mcap").display().to_string());
        BagMappings { sources, by_path, fallback, read_from }
    }

    /// The file as the adapter reads it: a bag converted to a lamp file, others unchanged.
    pub(crate) fn read(
        &mut self,
        world: &lamp_world::SpecWorld,
        path: &Path,
        file: DemoFile,
    ) -> Result<DemoFile, BuildError> {
        let source = self.by_path.get(path).copied().or_else(|| {
            let reader = lamp_trajectory::TrajectoryReader::from_bytes(&file.bytes, "");
            let no_lamp_record =
                matches!(reader, Err(lamp_trajectory::TrajectoryError::Schema { .. }));
            self.fallback.filter(|_| no_lamp_record)
        });
        let Some((_, mapping, tally)) = source.and_then(|index| self.sources.get_mut(index)) else {
            return Ok(file);
        };
        let (file, absent) = lamp_build::ros2_demo_file(world, mapping, &file)?;
        tally.add(&absent);
        Ok(file)
    }

    /// Refuses a mapped object that no bag of its source records, once every bag is read; the
    /// error comes with the source's pattern as the spec stores it (where its mapping is).
    pub(crate) fn check(&self) -> Result<(), (&'a str, lamp_build::Ros2Error)> {
        self.sources.iter().try_for_each(|(pattern, mapping, tally)| {
            let shown = self.read_from.as_deref().unwrap_or(pattern);
            tally.check(shown, mapping).map_err(|error| (*pattern, error))
        })
    }

    /// One line per mapped object some bags lacked: `OBJECT (frame `FRAME`) in N of M bags of
    /// `PATTERN``.
    pub(crate) fn absences(&self) -> Vec<String> {
        let mut lines = Vec::new();
        for (pattern, mapping, tally) in &self.sources {
            let pattern = self.read_from.as_deref().unwrap_or(pattern);
            for (object, absent) in tally.absences(mapping) {
                lines.push(format!(
                    "{} (frame `{}`) in {absent} of {} bags of `{pattern}`",
                    object.name, object.frame, tally.bags
                ));
            }
        }
        lines
    }
}

/// A bar on a terminal, nothing at all otherwise (CI logs stay clean).
fn progress_bar(length: u64, prefix: &'static str) -> ProgressBar {
    crate::terminal::progress_bar(length, "{prefix} [{bar:30}] {pos}/{len} {wide_msg}")
        .with_prefix(prefix)
}

fn spinner(message: &'static str) -> ProgressBar {
    crate::terminal::spinner().with_message(message)
}

/// Refuses to replace a `model` that is not a folder `lampc build` wrote (no manifest in it).
fn replaceable(model: &Path) -> Result<(), OutputError> {
    let Ok(metadata) = std::fs::symlink_metadata(model) else { return Ok(()) };
    let reason = if !metadata.is_dir() {
        format!("it is {}, not a model folder", crate::output::kind_of(&metadata))
    } else if !model.join(lamp_build::MANIFEST_FILE).is_file() {
        format!("it holds no {}, so `lampc build` did not write it", lamp_build::MANIFEST_FILE)
    } else {
        return Ok(());
    };
    Err(OutputError::Occupied { folder: model.display().to_string(), reason })
}

/// Writes the vocabulary report of a model that could not be written to `<build>/failed/`, and
/// says where; a report that cannot be written is only mentioned, as the build's own failure is
/// what the user needs to read.
fn write_failed_report(build_dir: &Path, report: &str) {
    let folder = build_dir.join(lamp_build::FAILED_DIR);
    let written = OutputFolder::new(&folder).and_then(|output| {
        let lock = output.lock("build")?;
        output.replace(&lock, &[(Path::new(lamp_build::VOCABULARY_FILE), report.as_bytes())])
    });
    match written {
        Ok(_) => eprintln!(
            "lampc build: what was learned is in {}",
            folder.join(lamp_build::VOCABULARY_FILE).display()
        ),
        Err(error) => eprintln!("lampc build: what was learned could not be written: {error}"),
    }
}

/// Removes the report of an earlier failed build once a build succeeds, so that it is never read
/// as the report of the model beside it. Only a folder holding nothing but the report is removed.
fn remove_failed_report(build_dir: &Path) {
    let folder = build_dir.join(lamp_build::FAILED_DIR);
    crate::output::remove_if_only(&folder, &[lamp_build::VOCABULARY_FILE]);
}

/// Replaces the model folder with the artifacts.
fn write_all(
    folder: &OutputFolder,
    lock: &FolderLock,
    files: &[ArtifactFile],
) -> Result<Replaced, OutputError> {
    let files: Vec<(&Path, &[u8])> =
        files.iter().map(|file| (file.path.as_path(), file.contents.as_bytes())).collect();
    folder.replace(lock, &files)
}

fn print_summary(
    spec_file: &str,
    model: &Path,
    artifacts: &Artifacts,
    absences: &[String],
    timings: &Timings,
) {
    let summary = &artifacts.summary;
    println!("{spec_file}: built into {}", model.display());
    println!(
        "  demonstrations  {} files, {} steps ({})",
        summary.demonstrations, summary.steps, summary.digest
    );
    for absence in absences {
        println!("  absent          {absence}");
    }
    println!(
        "  learned         {} regions, {} relations, {} actions",
        summary.regions, summary.relations, summary.actions
    );
    if !summary.pairs_without_regions.is_empty() {
        println!("  no regions      {}", summary.pairs_without_regions.join(", "));
    }
    for (alias, relation) in &summary.aliases {
        println!("  alias           {alias} = {relation}");
    }
    println!(
        "  problems        {} written, {} skipped",
        summary.problems_written.len(),
        summary.problems_skipped.len()
    );
    for (problem, reason) in &summary.problems_skipped {
        println!("  skipped         {problem}: {reason}");
    }
    let written: Vec<String> =
        artifacts.files.iter().map(|file| file.path.display().to_string()).collect();
    println!("  wrote           {}", written.join(", "));
    let phases: Vec<String> = timings
        .0
        .iter()
        .map(|(phase, duration)| format!("{phase} {:.2} s", duration.as_secs_f64()))
        .collect();
    println!("  time            {}", phases.join(", "));
}
