//! Shared test support: the Packing spec from disk, real Packing demonstrations made in memory by
//! lamp-demonstrators, and the synthetic fixture files for tests that need hand-made input.
#![allow(dead_code)]

pub mod fixture;

use std::path::Path;
use std::sync::LazyLock;

use lamp_build::{Artifacts, DemoFile};
use lamp_demonstrators::{Demonstration, Simulation, file_name, generate_all};
use lamp_learn::{Action, LiftedAtom, Model, Region};
use lamp_spec::Spec;
use lamp_world::SpecWorld;

pub use lamp_test_support::load;

/// The Packing spec and world.
pub fn packing() -> (Spec, SpecWorld) {
    load(&fixture::packing_spec_path())
}

/// `count` synthetic fixture files as build inputs (hand-made input for error cases).
pub fn packing_files(count: usize, seed: u64) -> Vec<DemoFile> {
    fixture::packing_fixture(count, seed, &fixture::packing_gripper())
        .into_iter()
        .map(|(name, bytes)| DemoFile { name, bytes })
        .collect()
}

/// How many real demonstrations the pipeline tests learn from. The spec asks for 200; the first
/// 100 of its seed learn the same relations and the same five kinds of action in a fraction of the
/// time, while smaller sets may add a rarely seen action (a held can leaving the box).
pub const DEMOS: usize = 100;

/// The first [`DEMOS`] demonstrations of the Packing spec's own `simulate` source (its seed and
/// cut fraction), named as `lampc demos` names them.
pub static PACKING_DEMOS: LazyLock<Vec<DemoFile>> = LazyLock::new(|| {
    let (spec, world) = packing();
    let count = u32::try_from(DEMOS).expect("a small count");
    demo_files("packing", simulated(&spec, &world, count))
});

/// The first `count` demonstrations of a spec's own `simulate` source, made in memory.
pub fn simulated(spec: &Spec, world: &SpecWorld, count: u32) -> Vec<Demonstration> {
    let mut simulation = Simulation::from_spec(spec).expect("the spec simulates its domain");
    simulation.count = count;
    generate_all(world, &simulation, |_| {})
        .unwrap_or_else(|error| panic!("the demonstrator runs: {error}"))
}

/// Demonstrations as build inputs, named as `lampc demos` names them.
pub fn demo_files(domain: &str, demonstrations: Vec<Demonstration>) -> Vec<DemoFile> {
    demonstrations
        .into_iter()
        .map(|demonstration| DemoFile {
            name: file_name(domain, demonstration.index),
            bytes: demonstration.to_bytes().expect("a demonstration encodes"),
        })
        .collect()
}

/// The real demonstrations built once per test binary.
pub static PACKING_BUILD: LazyLock<(Model, Artifacts)> = LazyLock::new(|| {
    build_with(|_| {}).unwrap_or_else(|error| panic!("the demonstrations build: {error}"))
});

/// The real demonstrations built with an edited Packing spec.
pub fn build_with(
    edit: impl FnOnce(&mut Spec),
) -> Result<(Model, Artifacts), lamp_build::BuildError> {
    let (mut spec, world) = packing();
    edit(&mut spec);
    lamp_build::build(&spec, "packing.lamp", &world, &PACKING_DEMOS)
}

/// The text of an artifact of a build.
pub fn artifact<'a>(artifacts: &'a Artifacts, path: &str) -> &'a str {
    artifacts
        .files
        .iter()
        .find(|file| file.path == Path::new(path))
        .map(|file| file.contents.as_str())
        .unwrap_or_else(|| panic!("no artifact {path}"))
}

/// The regions of one type pair of a model.
/// The build's warnings that a structure's objects rest on others with no learned relation.
pub fn unrelated_rests(artifacts: &Artifacts) -> Vec<&lamp_build::GoalWarning> {
    artifacts
        .summary
        .warnings
        .iter()
        .filter(|warning| matches!(warning, lamp_build::GoalWarning::UnrelatedRest { .. }))
        .collect()
}

pub fn regions<'a>(model: &'a Model, primary: &str, secondary: &str) -> Vec<&'a Region> {
    model
        .pairs
        .iter()
        .filter(|pair| pair.pair.pair.primary == primary && pair.pair.pair.secondary == secondary)
        .flat_map(|pair| &pair.regions)
        .collect()
}

/// Whether an atom list names `predicate`.
pub fn has(atoms: &[LiftedAtom], predicate: &str) -> bool {
    atoms.iter().any(|atom| atom.predicate == predicate)
}

/// The actions that turn `from` into `to`: `from` a precondition and deleted, `to` added. (Deletes
/// alone do not tell: an action also deletes the other relations of the pair it changes.)
pub fn actions_changing<'a>(model: &'a Model, from: &str, to: &str) -> Vec<&'a Action> {
    model
        .actions
        .iter()
        .filter(|action| {
            has(&action.preconditions, from) && has(&action.delete, from) && has(&action.add, to)
        })
        .collect()
}
