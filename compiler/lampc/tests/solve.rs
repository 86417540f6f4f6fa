//! `lampc solve` as a user runs it: demonstrations, a build, then a solve of a four-can Packing
//! problem into a scratch folder; the files are there and say what happened.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::Duration;

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
/// makes it; made once and shared by the tests of this file.
fn built() -> &'static Path {
    static BUILT: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();
    let (_, build) = BUILT.get_or_init(|| {
        let scratch = tempfile::tempdir().expect("a scratch directory");
        let build = scratch.path().join("build");
        let demos = scratch.path().join("demos");
        run(lampc().arg("demos").arg(spec()).arg("--out").arg(&demos));
        run(lampc().arg("build").arg(spec()).arg("--demos").arg(&demos).arg("--out").arg(&build));
        (scratch, build)
    });
    build
}

#[test]
fn solve_writes_a_validated_trajectory_plan_summary_and_picture() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let build = built();
    let out = scratch.path().join("solution");
    let output = run(lampc()
        .arg("solve")
        .arg(spec())
        .args(["--problem", "pack4_03", "--build"])
        .arg(build)
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

#[test]
fn a_time_limit_stops_the_search_reports_how_far_it_got_and_writes_nothing() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let out = scratch.path().join("solution");
    let output = lampc()
        .arg("solve")
        .arg(spec())
        .args(["--problem", "pack4_03", "--timeout", "0.000001", "--build"])
        .arg(built())
        .arg("--out")
        .arg(&out)
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("lamp::solve::cancelled"), "{stderr}");
    assert!(stderr.contains("before any plan was refined"), "{stderr}");
    assert!(stderr.contains("the time limit of 0.000001 s (`--timeout`) ran out"), "{stderr}");
    assert!(!out.exists(), "nothing is written");

    let refused = lampc()
        .arg("solve")
        .arg(spec())
        .args(["--problem", "pack4_03", "--timeout", "0"])
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("`0` is not a positive number of seconds"), "{stderr}");
}

/// A copy of the Packing spec with one more problem: six cans for a box that holds four, which
/// plans (the learned model does not count) but never refines, so its search runs its full
/// budget — many seconds — unless it is stopped.
fn overfull_spec(scratch: &Path) -> PathBuf {
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/robots/");
    let mut text = std::fs::read_to_string(spec())
        .expect("the bundled spec")
        .replace("\"../robots/", &format!("\"{}/", robots.display()));
    text.push_str(
        "problem pack6 {\n  scene {\n    table table1 at (0, 0, 0) m\n    surface box1 at (0.25, 0.15, 0) m\n",
    );
    for (index, (x, y)) in
        [(-0.3, -0.3), (-0.15, -0.3), (0.0, -0.3), (-0.3, -0.1), (-0.15, -0.1), (-0.3, 0.1)]
            .iter()
            .enumerate()
    {
        text.push_str(&format!("    can can{} at ({x}, {y}, 0.001) m\n", index + 1));
    }
    text.push_str("    robot gripper at (0, 0, 0.45) m rpy (180, 0, 0) deg\n  }\n  goal {\n");
    for index in 1..=6 {
        text.push_str(&format!("    in_box(can{index}, box1)\n"));
    }
    text.push_str("  }\n}\n");
    let path = scratch.join("overfull.lamp");
    std::fs::write(&path, text).expect("writes the spec");
    let demos = built().parent().expect("the scratch folder").join("demos");
    run(lampc().arg("build").arg(&path).arg("--demos").arg(&demos));
    path
}

/// Ctrl-C stops the search at its next check: the process says so and how far it got, writes
/// nothing, and exits as interrupted (130) instead of dying with the signal.
#[cfg(unix)]
#[test]
fn ctrl_c_stops_the_search_and_writes_nothing() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = overfull_spec(scratch.path());
    let out = scratch.path().join("solution");
    let child = lampc()
        .arg("solve")
        .arg(&spec)
        .args(["--problem", "pack6", "--out"])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    std::thread::sleep(Duration::from_secs(1));
    let pid = child.id().to_string();
    let kill = Command::new("kill").args(["-INT", &pid]).status().expect("kill runs");
    assert!(kill.success());
    let output = child.wait_with_output().expect("ends");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("lamp::solve::cancelled"), "{stderr}");
    assert!(stderr.contains("candidates, deepest step"), "{stderr}");
    assert!(stderr.contains("lampc solve: interrupted"), "{stderr}");
    assert!(!out.exists(), "nothing is written");
}
