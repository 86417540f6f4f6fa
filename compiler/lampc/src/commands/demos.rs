//! `lampc demos`: generate simulated demonstrations as MCAP files.
//!
//! The demonstrations are lamp-demonstrators'; this module loads the spec, applies the command
//! line's overrides, shows progress, writes each file through a temporary file renamed into
//! place, and prints the summary.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use indicatif::ProgressBar;
use lamp_demonstrators::{DemoError, Simulation, file_name, generate_all};

use crate::commands::failure::Failure;

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

pub(crate) fn run(args: &Args) -> ExitCode {
    let colour = crate::terminal::colour();
    match demos(args, colour) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Spec) => ExitCode::from(crate::EXIT_DIAGNOSTICS),
        Err(failure @ Failure::Report(_)) => {
            failure.print(colour);
            eprintln!("lampc demos: failed; no files were written");
            ExitCode::from(crate::EXIT_DIAGNOSTICS)
        }
        Err(Failure::Message(reason)) => {
            eprintln!("lampc demos: {reason}");
            ExitCode::from(crate::EXIT_DIAGNOSTICS)
        }
    }
}

fn demos(args: &Args, colour: bool) -> Result<(), Failure> {
    let start = Instant::now();
    let Some(crate::spec_input::CheckedSpec { spec, dir: spec_dir, file_name: spec_file, .. }) =
        crate::spec_input::check_spec(&args.spec, colour)
    else {
        return Err(Failure::Spec);
    };
    let out = args.out.clone().unwrap_or_else(|| {
        spec_dir.join(lamp_build::DEFAULT_BUILD_DIR).join(lamp_build::SIMULATED_DEMOS_DIR)
    });

    let mut simulation = Simulation::from_spec(&spec).map_err(demo_failure)?;
    simulation.count = args.count.unwrap_or(simulation.count);
    simulation.seed = args.seed.unwrap_or(simulation.seed);
    let world = lamp_world::SpecWorld::load(&spec_dir, &spec).map_err(Failure::from)?;

    let progress = progress_bar(u64::from(simulation.count), simulation.demonstrator.name());
    let demonstrations =
        generate_all(&world, &simulation, |_| progress.inc(1)).map_err(demo_failure)?;
    progress.finish_and_clear();

    std::fs::create_dir_all(&out)
        .map_err(|error| Failure::Message(format!("cannot create {}: {error}", out.display())))?;
    let (mut steps, mut bytes, mut cut) = (0, 0, 0);
    for demonstration in &demonstrations {
        let contents =
            viewable_bytes(&world, &demonstration.trajectory, None).map_err(Failure::Report)?;
        write_file(&out, &file_name(&spec.domain, demonstration.index), &contents)
            .map_err(Failure::Message)?;
        steps += demonstration.trajectory.steps.len();
        bytes += contents.len();
        cut += usize::from(demonstration.cut_at.is_some());
    }
    let stale = remove_stale(&out, &spec.domain, simulation.count);
    println!(
        "{spec_file}: {} {} demonstrations ({cut} cut) of seed {} into {}: {steps} steps, {:.1} MB, {:.1} s",
        demonstrations.len(),
        simulation.demonstrator.name(),
        simulation.seed,
        out.display(),
        bytes as f64 / 1e6,
        start.elapsed().as_secs_f64()
    );
    if stale > 0 {
        println!("  removed {stale} file(s) of an earlier, larger run");
    }
    Ok(())
}

/// The file's bytes with the standard ROS 2 and Foxglove channels beside `/lamp/world`, so
/// that Foxglove and RViz show the robot and the objects (`docs/formats.md`); with `plan`
/// (each plan step's first trajectory step and its text), the step being executed on
/// `/lamp/step`.
pub(crate) fn viewable_bytes(
    world: &lamp_world::SpecWorld,
    trajectory: &lamp_trajectory::Trajectory,
    plan: Option<(&[usize], &[String])>,
) -> Result<Vec<u8>, Box<dyn miette::Diagnostic + Send + Sync>> {
    let (mut channels, mut values) = lamp_world::standard_channels(world, trajectory)?;
    if let Some((starts, steps)) = plan {
        lamp_world::label_plan_steps(&mut channels, &mut values, starts, steps);
    }
    Ok(trajectory.to_bytes_with(&channels, &values)?)
}

fn demo_failure(error: DemoError) -> Failure {
    Failure::from(error)
}

/// Writes through a temporary file renamed into place, so a file is never seen half written.
pub(crate) fn write_file(folder: &Path, name: &str, contents: &[u8]) -> Result<(), String> {
    let path = folder.join(name);
    let temporary = folder.join(format!(".{name}.tmp"));
    std::fs::write(&temporary, contents)
        .map_err(|error| format!("cannot write {}: {error}", temporary.display()))?;
    std::fs::rename(&temporary, &path).map_err(|error| {
        let _ = std::fs::remove_file(&temporary);
        format!("cannot move {} to {}: {error}", temporary.display(), path.display())
    })
}

/// Removes `<domain>_NNNN.mcap` files numbered `count` or above: left by an earlier run with a
/// larger count, `lampc build` would otherwise learn from them too.
fn remove_stale(folder: &Path, domain: &str, count: u32) -> usize {
    let Ok(entries) = std::fs::read_dir(folder) else { return 0 };
    let prefix = format!("{domain}_");
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let index = name
            .strip_prefix(&prefix)
            .and_then(|rest| rest.strip_suffix(".mcap"))
            .filter(|digits| digits.len() >= 4 && digits.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|digits| digits.parse::<u64>().ok());
        if index.is_some_and(|index| index >= u64::from(count))
            && std::fs::remove_file(entry.path()).is_ok()
        {
            removed += 1;
        }
    }
    removed
}

/// A bar on a terminal, nothing at all otherwise (CI logs stay clean).
fn progress_bar(length: u64, prefix: &'static str) -> ProgressBar {
    crate::terminal::progress_bar(length, "{prefix} [{bar:30}] {pos}/{len} {elapsed} (eta {eta})")
        .with_prefix(prefix)
}
