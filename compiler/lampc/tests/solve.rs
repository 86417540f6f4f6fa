//! `lampc solve` as a user runs it: demonstrations, a build, then a solve of a four-can Packing
//! problem into a scratch folder; the files are there and say what happened.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn lampc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lampc"))
}

fn spec() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/packing/packing.lamp")
}

fn run(command: &mut Command) -> Output {
    let output = command.output().expect("lampc runs");
    assert!(
        output.status.success(),
        "{:?} failed:\n{}",
        command,
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// A build folder learned from the spec's own 200 demonstrations, as the README's first command
/// makes it.
fn built(scratch: &Path) -> PathBuf {
    let build = scratch.join("build");
    let demos = scratch.join("demos");
    run(lampc().arg("demos").arg(spec()).arg("--out").arg(&demos));
    run(lampc().arg("build").arg(spec()).arg("--demos").arg(&demos).arg("--out").arg(&build));
    build
}

#[test]
fn solve_writes_a_validated_trajectory_plan_summary_and_picture() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let build = built(scratch.path());
    let out = scratch.path().join("solution");
    let output = run(lampc()
        .arg("solve")
        .arg(spec())
        .args(["--problem", "pack4_03", "--build"])
        .arg(&build)
        .arg("--out")
        .arg(&out));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("pack4_03: solved"), "{stdout}");
    assert!(stdout.contains("validated by replay"), "{stdout}");
    let summary = std::fs::read_to_string(out.join("summary.json")).expect("a summary");
    assert!(summary.contains("\"success\": true"), "{summary}");
    let plan = std::fs::read_to_string(out.join("plan.txt")).expect("a plan");
    assert_eq!(plan.lines().count(), 19, "{plan}");
    let svg = std::fs::read_to_string(out.join("trajectory.svg")).expect("a picture");
    assert!(svg.starts_with("<svg") || svg.starts_with("<?xml"), "an SVG");
    let bytes = std::fs::read(out.join("trajectory.mcap")).expect("a trajectory");
    let trajectory =
        lamp_trajectory::Trajectory::from_bytes(&bytes, "trajectory.mcap").expect("it reads back");
    assert!(trajectory.steps.len() > 100);
}

#[test]
fn an_unknown_problem_is_named_with_the_ones_there_are() {
    let missing =
        lampc().arg("solve").arg(spec()).args(["--problem", "pack9"]).output().expect("runs");
    let stderr = String::from_utf8_lossy(&missing.stderr);
    assert_eq!(missing.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no problem `pack9`") && stderr.contains("pack4_01"), "{stderr}");
}
