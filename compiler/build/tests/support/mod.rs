//! Shared test support: loading bundled specs from disk, and the Packing fixture demonstrations.
#![allow(dead_code)]

pub mod fixture;

use std::path::Path;
use std::sync::LazyLock;

use lamp_build::{Artifacts, DemoFile};
use lamp_learn::Model;
use lamp_spec::Spec;
use lamp_world::SpecWorld;

pub use lamp_test_support::load;

/// The Packing spec and world.
pub fn packing() -> (Spec, SpecWorld) {
    load(&fixture::packing_spec_path())
}

/// `count` fixture files as build inputs.
pub fn packing_files(count: usize, seed: u64) -> Vec<DemoFile> {
    fixture::packing_fixture(count, seed, &fixture::packing_gripper())
        .into_iter()
        .map(|(name, bytes)| DemoFile { name, bytes })
        .collect()
}

/// The demonstration count of the snapshot fixture.
pub const FIXTURE_DEMOS: usize = 40;
/// The synthetic demonstrator's seed of the snapshot fixture.
pub const FIXTURE_SEED: u64 = 11;

/// The fixture built once per test binary: Packing spec, 40 demonstrations.
pub static PACKING_BUILD: LazyLock<(Model, Artifacts)> = LazyLock::new(|| {
    let (spec, world) = packing();
    lamp_build::build(&spec, "packing.lamp", &world, &packing_files(FIXTURE_DEMOS, FIXTURE_SEED))
        .unwrap_or_else(|error| panic!("the fixture builds: {error}"))
});

/// The fixture built with an edited Packing spec.
pub fn build_with(
    edit: impl FnOnce(&mut Spec),
) -> Result<(Model, Artifacts), lamp_build::BuildError> {
    let (mut spec, world) = packing();
    edit(&mut spec);
    lamp_build::build(&spec, "packing.lamp", &world, &packing_files(FIXTURE_DEMOS, FIXTURE_SEED))
}

/// The text of an artifact of the fixture build.
pub fn artifact<'a>(artifacts: &'a Artifacts, path: &str) -> &'a str {
    artifacts
        .files
        .iter()
        .find(|file| file.path == Path::new(path))
        .map(|file| file.contents.as_str())
        .unwrap_or_else(|| panic!("no artifact {path}"))
}
