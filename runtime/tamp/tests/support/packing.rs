//! The Packing set-up shared by the end-to-end tests and the solve benchmark: real demonstrations
//! made in memory, learned with lamp-build, and a solve with the first-party plugins linked in.
#![allow(dead_code)]

use std::path::Path;
use std::sync::LazyLock;

use lamp_build::{Adapter, Artifacts, DemoFile, SamplersFile};
use lamp_demonstrators::{Simulation, file_name, generate_all};
use lamp_motion_rrt::{RrtConnectPlanner, RrtOptions};
use lamp_planner_builtin::{BuiltinAlgorithm, BuiltinPlanner};
use lamp_plugin_api::{MotionBudget, PlanBudget};
use lamp_refiner_gmm::{GmmRefiner, RefinerOptions};
use lamp_spec::Spec;
use lamp_tamp::execute::MotionSettings;
use lamp_tamp::{Plugins, Solution, SolveError, SolveInput, SolveSettings, solve};
use lamp_world::{MotionConfig, SpecWorld, trajectory_header};

pub static PACKING: LazyLock<(Spec, SpecWorld, Artifacts)> = LazyLock::new(|| {
    let (spec, world) = lamp_test_support::load(&lamp_test_support::spec_path("packing"));
    let simulation = Simulation::from_spec(&spec).expect("the spec simulates Packing");
    // The spec's own 200 demonstrations: the model a user's `lampc build` learns.
    let files: Vec<DemoFile> = generate_all(&world, &simulation, |_| {})
        .expect("the demonstrator runs")
        .into_iter()
        .map(|demo| DemoFile {
            name: file_name("packing", demo.index),
            bytes: demo.to_bytes().expect("encodes"),
        })
        .collect();
    let (_, artifacts) =
        lamp_build::build(&spec, "packing.lamp", &world, &files).expect("the demonstrations build");
    (spec, world, artifacts)
});

pub fn artifact<'a>(artifacts: &'a Artifacts, path: &str) -> &'a str {
    artifacts
        .files
        .iter()
        .find(|file| file.path == Path::new(path))
        .map(|file| file.contents.as_str())
        .unwrap_or_else(|| panic!("no artifact {path}"))
}

pub fn solve_problem(name: &str, seed: u64) -> Result<Solution, SolveError> {
    let (spec, world, artifacts) = &*PACKING;
    let problem = spec.problems.iter().find(|p| p.name == name).expect("the problem exists");
    let scene = world.problem_scene(problem).expect("the scene loads");
    let adapter = Adapter::new(spec, &world.robots).expect("an adapter");
    let samplers = SamplersFile::from_json(artifact(artifacts, "samplers.json")).expect("samplers");
    let never = || false;
    let settings = SolveSettings {
        seed,
        plan_count: 1,
        planner_budget: PlanBudget::default(),
        rounds: 20,
        max_candidates: 100,
        motion: MotionSettings {
            config: MotionConfig::default(),
            budget: MotionBudget { max_iterations: Some(4000), time_limit: None },
            grab_ranges: vec![("gripper".to_string(), (0.207, 0.23))],
            cancelled: &never,
        },
        relax_goal: false,
    };
    let input = SolveInput {
        scene: &scene,
        domain: artifact(artifacts, "domain.pddl"),
        problem: artifact(artifacts, &format!("problems/{name}.pddl")),
        artifact: &samplers.artifact,
        adapter: &adapter,
        header: trajectory_header(spec, &scene, seed),
    };
    let mut planner = BuiltinPlanner::new(BuiltinAlgorithm::GbfsFf);
    let mut refiner =
        GmmRefiner::new(samplers.artifact.clone(), RefinerOptions::default()).expect("valid");
    let mut motion = RrtConnectPlanner::new(RrtOptions::default());
    let mut plugins = Plugins { planner: &mut planner, refiner: &mut refiner, motion: &mut motion };
    solve(&input, &mut plugins, &settings, &|_| {})
}
