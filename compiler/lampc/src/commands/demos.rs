//! `lampc demos`: generate simulated demonstrations as MCAP files.
//!
//! The demonstrations are lamp-demonstrators'; this module loads the spec, applies the command
//! line's overrides, shows progress, writes the folder whole (staged beside it and swapped in,
//! under the folder's lock, as `lampc build` writes its model), and prints the summary.

use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::ProgressBar;
use lamp_demonstrators::{DemoError, Simulation, file_name, generate_all};

use crate::commands::{Failure, Finished, Outcome, Stopped};
use crate::output::{OutputError, OutputFolder};

/// Arguments of `lampc demos`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The `.lamp` spec file.
    pub(crate) spec: PathBuf,
    /// How many demonstrations, 1 to 10000 [default: the spec's `count`].
    #[arg(long, value_name = "N", value_parser = crate::flags::demonstrations)]
    pub(crate) count: Option<u32>,
    /// The seed of the demonstrations [default: the spec's `simulate … seed`].
    #[arg(long, value_name = "S")]
    pub(crate) seed: Option<u64>,
    /// The output folder [default: `build/demos/` beside the spec].
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
}

pub(crate) fn run(args: &Args) -> Outcome {
    let colour = crate::terminal::colour();
    match demos(args, colour) {
        Ok(()) => Ok(Finished::Done),
        Err(Failure::Said) => Err(Stopped::said()),
        Err(failure) => Err(Stopped::from(failure).leaving("no files were written")),
    }
}

fn demos(args: &Args, colour: bool) -> Result<(), Failure> {
    let start = Instant::now();
    let Some(crate::spec_input::CheckedSpec { spec, dir: spec_dir, file_name: spec_file, .. }) =
        crate::spec_input::check_spec(&args.spec, colour, crate::spec_input::Demonstrations::Read)
    else {
        return Err(Failure::Said);
    };
    let out = args.out.clone().unwrap_or_else(|| {
        spec_dir.join(lamp_build::DEFAULT_BUILD_DIR).join(lamp_build::SIMULATED_DEMOS_DIR)
    });

    let mut simulation = Simulation::from_spec(&spec).map_err(demo_failure)?;
    simulation.count = args.count.unwrap_or(simulation.count);
    simulation.seed = args.seed.unwrap_or(simulation.seed);
    let world = lamp_world::SpecWorld::load(&spec_dir, &spec).map_err(Failure::from)?;
    // Taken before the slow part: a second `lampc demos` into the folder is refused at once.
    let folder = OutputFolder::new(&out)?;
    let lock = folder.lock("demos")?;
    replaceable(folder.path(), &spec.domain)?;
    folder.remove_leftovers(&lock);

    let progress = progress_bar(u64::from(simulation.count), simulation.demonstrator.name());
    let demonstrations =
        generate_all(&world, &simulation, |_| progress.inc(1)).map_err(demo_failure)?;
    progress.finish_and_clear();

    let (mut steps, mut cut) = (0, 0);
    let mut files = Vec::with_capacity(demonstrations.len());
    for demonstration in &demonstrations {
        let contents = crate::viewable::mcap_bytes(&world, &demonstration.trajectory, None)
            .map_err(Failure::Report)?;
        files.push((PathBuf::from(file_name(&spec.domain, demonstration.index)), contents));
        steps += demonstration.trajectory.steps.len();
        cut += usize::from(demonstration.cut_at.is_some());
    }
    let bytes: usize = files.iter().map(|(_, contents)| contents.len()).sum();
    let listed: Vec<(&Path, &[u8])> =
        files.iter().map(|(name, contents)| (name.as_path(), contents.as_slice())).collect();
    let replaced = folder.replace(&lock, &listed)?;
    println!(
        "{spec_file}: {} {} demonstrations ({cut} cut) of seed {} into {}: {steps} steps, {:.1} MB, {:.1} s",
        demonstrations.len(),
        simulation.demonstrator.name(),
        simulation.seed,
        out.display(),
        bytes as f64 / 1e6,
        start.elapsed().as_secs_f64()
    );
    if let Some((kept, reason)) = replaced.kept {
        eprintln!(
            "lampc demos: warning: the previous demonstrations, moved to {}, could not be removed: {reason}",
            kept.display()
        );
    }
    Ok(())
}

/// Refuses to replace a folder that holds anything but the demonstrations `lampc demos` writes for
/// `domain` (`<domain>_NNNN.mcap`, and the `.<name>.tmp` files an earlier version wrote through):
/// the whole folder is replaced, and a user's own files must not go with it.
fn replaceable(folder: &Path, domain: &str) -> Result<(), OutputError> {
    let Ok(metadata) = std::fs::symlink_metadata(folder) else { return Ok(()) };
    let occupied =
        |reason: String| OutputError::Occupied { folder: folder.display().to_string(), reason };
    if !metadata.is_dir() {
        let kind = crate::output::kind_of(&metadata);
        return Err(occupied(format!("it is {kind}, not a folder of demonstrations")));
    }
    let entries = std::fs::read_dir(folder).map_err(|error| occupied(error.to_string()))?;
    let mut foreign: Vec<String> = entries
        .flatten()
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .filter(|name| !is_demonstration_name(name, domain))
        .collect();
    foreign.sort();
    match foreign.first() {
        None => Ok(()),
        Some(first) => Err(occupied(format!(
            "it holds {first}{}, which `lampc demos` did not write for {domain}",
            match foreign.len() {
                1 => String::new(),
                more => format!(" and {} more", more - 1),
            }
        ))),
    }
}

/// Whether `name` is one that `lampc demos` writes into its folder for `domain`.
fn is_demonstration_name(name: &str, domain: &str) -> bool {
    let name = name.strip_prefix('.').and_then(|rest| rest.strip_suffix(".tmp")).unwrap_or(name);
    name.strip_prefix(domain)
        .and_then(|rest| rest.strip_prefix('_'))
        .and_then(|rest| rest.strip_suffix(".mcap"))
        .is_some_and(|digits| digits.len() >= 4 && digits.bytes().all(|b| b.is_ascii_digit()))
}

fn demo_failure(error: DemoError) -> Failure {
    Failure::from(error)
}

/// A bar on a terminal, nothing at all otherwise (CI logs stay clean).
fn progress_bar(length: u64, prefix: &'static str) -> ProgressBar {
    crate::terminal::progress_bar(length, "{prefix} [{bar:30}] {pos}/{len} {elapsed} (eta {eta})")
        .with_prefix(prefix)
}
