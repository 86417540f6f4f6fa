//! Builds the example plugin libraries once per test run and finds them.

use std::path::PathBuf;
use std::sync::OnceLock;

/// The package holding the example plugin and the fixture libraries (its `examples/`).
const FIXTURE_PACKAGE: &str = "echo-planner";

/// Builds the fixture libraries with the same cargo, target folder and profile as this test, once.
fn build_fixtures() -> &'static PathBuf {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(|| {
        lamp_test_support::cargo_build_like_this_test(&[
            "--package",
            FIXTURE_PACKAGE,
            "--lib",
            "--examples",
        ])
    })
}

/// The echo-planner shared library.
pub fn echo_planner() -> PathBuf {
    build_fixtures().join(lamp_test_support::shared_library_file(FIXTURE_PACKAGE))
}

/// A fixture library from echo-planner's `examples/`.
pub fn fixture(name: &str) -> PathBuf {
    build_fixtures().join("examples").join(lamp_test_support::shared_library_file(name))
}
