//! Test and bench support shared by the crates: the bundled specs under `domains/`, read from
//! disk, checked, with their worlds loaded; the check that a trajectory keeps its robots'
//! velocity limits; the oracle rule for Python references; and packages
//! built as shared libraries with the calling test's cargo and profile. Only
//! dev-dependencies name this crate.

use std::path::{Path, PathBuf};

use lamp_robot::{CoordinateKind, Robot};
use lamp_spec::Spec;
use lamp_trajectory::Trajectory;
use lamp_world::SpecWorld;

/// Reads spec files and robot files from disk. A demonstration pattern stands for the files it
/// would match: recorded demonstrations are generated (`domains/cubes/record.py`), never bundled,
/// so a spec's `files` source checks whether or not they have been recorded, and tests pass files
/// explicitly.
pub struct Disk;

impl lamp_lang::Loader for Disk {
    fn read_to_string(&self, path: &Path) -> Result<String, String> {
        std::fs::read_to_string(path).map_err(|error| error.to_string())
    }

    fn file_kind(&self, path: &Path) -> lamp_lang::FileKind {
        match std::fs::metadata(path) {
            Ok(metadata) if metadata.is_file() => lamp_lang::FileKind::File,
            Ok(_) => lamp_lang::FileKind::NotAFile("not a regular file".to_string()),
            Err(_) => lamp_lang::FileKind::Missing,
        }
    }

    fn glob(&self, pattern: &Path) -> Vec<PathBuf> {
        vec![pattern.to_path_buf()]
    }

    fn robot_names(
        &self,
        path: &Path,
        kind: lamp_spec::RobotKind,
    ) -> Result<Option<lamp_spec::RobotNames>, String> {
        lamp_world::robot_names(path, kind).map(Some).map_err(|error| error.to_string())
    }
}

/// The `domains/` folder of the workspace.
pub fn domains_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains")
}

/// The spec file of a bundled domain (`domains/<name>/<name>.lamp`).
pub fn spec_path(name: &str) -> PathBuf {
    domains_dir().join(name).join(format!("{name}.lamp"))
}

/// A spec file, checked; panics with every diagnostic if it does not check.
pub fn check(path: &Path) -> Spec {
    let outcome = lamp_lang::check(path, &Disk);
    let messages: Vec<String> =
        outcome.diagnostics.iter().map(|d| format!("{:?}", d.error)).collect();
    outcome
        .spec
        .unwrap_or_else(|| panic!("{} does not check:\n{}", path.display(), messages.join("\n")))
}

/// A spec file, checked, with its world (robots and object types) loaded.
pub fn load(path: &Path) -> (Spec, SpecWorld) {
    let spec = check(path);
    let dir = path.parent().unwrap_or(Path::new("."));
    let world =
        SpecWorld::load(dir, &spec).unwrap_or_else(|error| panic!("{}: {error}", path.display()));
    (spec, world)
}

/// A bundled domain, checked, with its world loaded.
pub fn domain(name: &str) -> (Spec, SpecWorld) {
    load(&spec_path(name))
}

/// Asserts that a robot can follow `trajectory` as it is stamped: between consecutive steps no
/// coordinate of `robots` (the models of its robots, in order) moves faster than its velocity
/// limit, no wrapped angle (a continuous joint, a planar yaw) jumps by a turn where it crosses
/// ±π, and steps with the same stamp have the same positions. Returns the largest ratio of a
/// recorded velocity to its limit.
pub fn assert_within_velocity_limits(trajectory: &Trajectory, robots: &[&Robot]) -> f64 {
    let mut worst: f64 = 0.0;
    for (index, pair) in trajectory.steps.windows(2).enumerate() {
        let seconds = (pair[1].time_nanoseconds - pair[0].time_nanoseconds) as f64 * 1e-9;
        for ((from, to), robot) in pair[0].robots.iter().zip(&pair[1].robots).zip(robots) {
            let mut moved = vec![0.0; robot.dof()];
            robot.displacement(&from.positions, &to.positions, &mut moved);
            for (j, coordinate) in robot.coordinates().iter().enumerate() {
                let raw = to.positions[j] - from.positions[j];
                let change = match coordinate.kind {
                    CoordinateKind::Rotation(_) => moved[j],
                    CoordinateKind::WrappedAngle => {
                        assert!(
                            (raw - moved[j]).abs() < 1e-9,
                            "step {}: {} jumps by {raw} rad, the short way is {} rad",
                            index + 1,
                            coordinate.name,
                            moved[j]
                        );
                        raw
                    }
                    CoordinateKind::Linear | CoordinateKind::Angle => raw,
                };
                if seconds == 0.0 {
                    assert!(
                        change == 0.0,
                        "step {}: {} moves in no time",
                        index + 1,
                        coordinate.name
                    );
                    continue;
                }
                let ratio = change.abs() / seconds / coordinate.velocity;
                assert!(
                    ratio <= 1.0 + 1e-6,
                    "step {}: {} moves at {} times its limit of {}",
                    index + 1,
                    coordinate.name,
                    ratio,
                    coordinate.velocity
                );
                worst = worst.max(ratio);
            }
        }
    }
    worst
}

/// Whether CI demands every external reference (`LAMP_REQUIRE_ORACLES=1`).
pub fn oracles_required() -> bool {
    std::env::var("LAMP_REQUIRE_ORACLES").is_ok_and(|value| value == "1")
}

/// Whether `python3` can import `module` (an oracle installed with `pip install {package}`).
/// Missing: the test is skipped with a message, or fails when oracles are required.
// The test harness shows a skipped test's stdout; that is where the note belongs.
#[allow(clippy::print_stdout)]
pub fn python_oracle(module: &str, package: &str) -> bool {
    let available = std::process::Command::new("python3")
        .args(["-c", &format!("import {module}")])
        .output()
        .is_ok_and(|output| output.status.success());
    if !available {
        assert!(!oracles_required(), "the oracle `{module}` (pip {package}) is required");
        println!("skipped: python3 cannot import {module} (pip install {package})");
    }
    available
}

/// Builds packages of the workspace with the same cargo, target folder and profile as the
/// calling test binary (`cargo build --quiet` plus `arguments`, such as `--package` and
/// `--features`), and returns the profile folder the libraries land in. Tests that load plugins
/// as shared libraries call it once (behind a `OnceLock`).
pub fn cargo_build_like_this_test(arguments: &[&str]) -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary knows its path");
    let profile_dir = exe
        .parent()
        .and_then(Path::parent)
        .expect("test binaries live in <target>/<profile>/deps")
        .to_path_buf();
    let target_dir = profile_dir.parent().expect("<target>/<profile>").to_path_buf();
    let profile = profile_dir.file_name().and_then(|name| name.to_str()).unwrap_or("debug");
    let mut command = std::process::Command::new(env!("CARGO"));
    command
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")))
        .args(["build", "--quiet"])
        .args(arguments)
        .arg("--target-dir")
        .arg(&target_dir);
    match profile {
        "debug" => {}
        "release" => {
            command.arg("--release");
        }
        other => {
            command.args(["--profile", other]);
        }
    }
    let status = command.status().expect("cargo runs");
    assert!(status.success(), "cargo build {arguments:?} failed: {status}");
    profile_dir
}

/// The file name of a shared library built from `crate_name` (`lib<name>.so` on Linux).
pub fn shared_library_file(crate_name: &str) -> String {
    format!(
        "{}{}{}",
        std::env::consts::DLL_PREFIX,
        crate_name.replace('-', "_"),
        std::env::consts::DLL_SUFFIX
    )
}
