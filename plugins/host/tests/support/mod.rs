//! Builds the example plugin libraries once per test run and finds them.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The package holding the example plugin and the fixture libraries (its `examples/`).
const FIXTURE_PACKAGE: &str = "echo-planner";

/// The profile folder holding this test binary (`<target>/<profile>/deps/<test>`).
fn profile_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary knows its path");
    exe.parent()
        .and_then(Path::parent)
        .expect("test binaries live in <target>/<profile>/deps")
        .to_path_buf()
}

/// Builds the fixture libraries with the same cargo, target folder and profile as this test, once.
fn build_fixtures() -> &'static PathBuf {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(|| {
        let profile_dir = profile_dir();
        let target_dir = profile_dir.parent().expect("<target>/<profile>").to_path_buf();
        let profile = profile_dir.file_name().and_then(|name| name.to_str()).unwrap_or("debug");
        let mut command = Command::new(env!("CARGO"));
        command
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .args(["build", "--quiet", "--package", FIXTURE_PACKAGE, "--lib", "--examples"])
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
        assert!(status.success(), "building the fixture plugins failed: {status}");
        profile_dir
    })
}

fn library_file(stem: &str) -> String {
    format!("{}{stem}{}", std::env::consts::DLL_PREFIX, std::env::consts::DLL_SUFFIX)
}

/// The echo-planner shared library.
pub fn echo_planner() -> PathBuf {
    build_fixtures().join(library_file("echo_planner"))
}

/// A fixture library from echo-planner's `examples/`.
pub fn fixture(name: &str) -> PathBuf {
    build_fixtures().join("examples").join(library_file(name))
}
