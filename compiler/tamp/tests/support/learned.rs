//! The set-ups shared by the end-to-end tests and the solve benchmark: a bundled domain's real
//! demonstrations made in memory, learned with lamp-build, and a solve with the first-party
//! plugins linked in, configured as the spec configures them.
#![allow(dead_code)]

use std::path::Path;
use std::sync::LazyLock;

use lamp_build::{Artifacts, DemoFile, SamplersFile};
use lamp_demonstrators::{Simulation, file_name, generate_all};
use lamp_geometry::Pose;
use lamp_motion_rrt::{RrtConnectPlanner, RrtOptions};
use lamp_participants::ParticipantMap;
use lamp_planner_builtin::{BuiltinAlgorithm, BuiltinPlanner};
use lamp_plugin_api::{MotionBudget, PlanBudget, Planner};
use lamp_refiner_gmm::{GmmRefiner, RefinerOptions};
use lamp_spec::Spec;
use lamp_tamp::MotionSettings;
use lamp_tamp::{Plugins, Solution, SolveError, SolveInput, SolveSettings, solve};
use lamp_world::{MotionConfig, Scene, SpecWorld, trajectory_header};

/// A bundled domain learned from its own demonstrations.
pub struct Learned {
    pub spec: Spec,
    pub world: SpecWorld,
    pub artifacts: Artifacts,
    /// The spec's `refiner gmm { … }` settings.
    pub refiner: RefinerOptions,
}

/// Packing from the spec's own 200 demonstrations: the model a user's `lampc build` learns.
pub static PACKING: LazyLock<Learned> =
    LazyLock::new(|| learn("packing", None, RefinerOptions::default()));

/// Café from the first 100 of the spec's demonstrations (long ones: thousands of steps each),
/// which learn the same regions and actions as the 200 (`compiler/build/tests/learned_cafe.rs`).
pub static CAFE: LazyLock<Learned> = LazyLock::new(|| {
    learn("cafe", Some(100), RefinerOptions { draws: 300, ..RefinerOptions::default() })
});

/// Dinner from the first 80 of the spec's demonstrations (each moves one glass or bowl from a
/// start marker to a target marker), with the spec's refiner settings.
pub static DINNER: LazyLock<Learned> = LazyLock::new(|| {
    learn("dinner", Some(80), RefinerOptions { draws: 300, ..RefinerOptions::default() })
});

/// Jenga from the spec's own 160 demonstrations of at most three blocks (short ones: under a
/// thousand steps each).
pub static JENGA: LazyLock<Learned> =
    LazyLock::new(|| learn("jenga", None, RefinerOptions::default()));

/// Keva from the spec's own 160 demonstrations of at most three planks, made with the free
/// gripper; the problems are solved with the YuMi.
pub static KEVA: LazyLock<Learned> =
    LazyLock::new(|| learn("keva", None, RefinerOptions::default()));

fn learn(domain: &str, count: Option<u32>, refiner: RefinerOptions) -> Learned {
    let (spec, world) = lamp_test_support::load(&lamp_test_support::spec_path(domain));
    let mut simulation = Simulation::from_spec(&spec).expect("the spec simulates its domain");
    if let Some(count) = count {
        simulation.count = count;
    }
    let files: Vec<DemoFile> = generate_all(&world, &simulation, |_| {})
        .expect("the demonstrator runs")
        .into_iter()
        .map(|demo| DemoFile {
            name: file_name(domain, demo.index),
            bytes: demo.to_bytes().expect("encodes"),
        })
        .collect();
    let (_, artifacts) = lamp_build::build(&spec, &format!("{domain}.lamp"), &world, &files)
        .expect("the demonstrations build");
    Learned { spec, world, artifacts, refiner }
}

/// Replays `solution` of problem `name` in a fresh scene, asserting that no step collides (the
/// held object included); returns the scene.
pub fn replay_collision_free(learned: &Learned, name: &str, solution: &Solution) -> Scene {
    let problem =
        learned.spec.problems.iter().find(|p| p.name == name).expect("the problem exists");
    let mut scene = learned.world.problem_scene(problem).expect("the scene loads");
    for (index, step) in solution.trajectory.steps.iter().enumerate() {
        let held = step.robots[0].held.first().copied().flatten();
        if scene.held(0).map(|h| h.body) != held {
            scene.release_at_rest(0).expect("the released object rests");
            if let Some(body) = held {
                scene.grab(0, body).expect("a legal grab");
            }
        }
        let q = &step.robots[0].positions;
        scene.set_configuration(0, q);
        assert!(scene.first_contact(0, q).is_none(), "{name}: step {index} collides");
    }
    scene
}

/// Asserts that a robot can execute `solution` as its file is stamped, reading the trajectory
/// back from its encoded bytes: within every velocity limit, continuous joints turning the short
/// way, and the summary's execution time the last stamp. Returns the largest ratio of a recorded
/// velocity to its limit.
pub fn assert_executable(learned: &Learned, name: &str, solution: &Solution) -> f64 {
    let problem =
        learned.spec.problems.iter().find(|p| p.name == name).expect("the problem exists");
    let scene = learned.world.problem_scene(problem).expect("the scene loads");
    let robots: Vec<&lamp_robot::Robot> =
        scene.robots().iter().map(|robot| robot.robot().as_ref()).collect();
    let bytes = solution.trajectory.to_bytes().expect("the trajectory encodes");
    let written = lamp_trajectory::Trajectory::from_bytes(&bytes, format!("{name}.mcap"))
        .expect("the trajectory reads back");
    let worst = lamp_test_support::assert_within_velocity_limits(&written, &robots);
    let last = written.steps.last().expect("a trajectory").time_nanoseconds;
    assert_eq!(solution.summary.execution_seconds, last as f64 / 1e9, "{name}: execution time");
    worst
}

pub fn artifact<'a>(artifacts: &'a Artifacts, path: &str) -> &'a str {
    artifacts
        .files
        .iter()
        .find(|file| file.path == Path::new(path))
        .map(|file| file.contents.as_str())
        .unwrap_or_else(|| panic!("no artifact {path}"))
}

pub fn solve_problem(learned: &Learned, name: &str, seed: u64) -> Result<Solution, SolveError> {
    solve_with_planner(learned, name, seed, &mut BuiltinPlanner::new(BuiltinAlgorithm::GbfsFf))
}

/// [`solve_problem`] with another planner.
pub fn solve_with_planner(
    learned: &Learned,
    name: &str,
    seed: u64,
    planner: &mut dyn Planner,
) -> Result<Solution, SolveError> {
    let artifacts = &learned.artifacts;
    let domain = artifact(artifacts, "domain.pddl");
    let problem = artifact(artifacts, &format!("problems/{name}.pddl"));
    solve_texts(learned, name, seed, planner, (domain, problem), false)
}

/// [`solve_with_planner`] with goal relaxation on, as `lampc solve` runs by default.
pub fn solve_relaxing_with_planner(
    learned: &Learned,
    name: &str,
    planner: &mut dyn Planner,
) -> Result<Solution, SolveError> {
    let artifacts = &learned.artifacts;
    let domain = artifact(artifacts, "domain.pddl");
    let problem = artifact(artifacts, &format!("problems/{name}.pddl"));
    solve_texts(learned, name, 1, planner, (domain, problem), true)
}

/// [`solve_problem`] of PDDL edited by hand, with goal relaxation on or off.
pub fn solve_edited(
    learned: &Learned,
    name: &str,
    (domain, problem): (&str, &str),
    relax_goal: bool,
) -> Result<Solution, SolveError> {
    let mut planner = BuiltinPlanner::new(BuiltinAlgorithm::GbfsFf);
    solve_texts(learned, name, 1, &mut planner, (domain, problem), relax_goal)
}

/// [`solve_problem`] with the robot started with its mount (a mobile base, a free-flying
/// gripper) at `start` in the world instead of where the problem puts it. The problem file is
/// the bundled one: a start that changes the initial abstract state is refused as stale.
pub fn solve_from(learned: &Learned, name: &str, start: &Pose) -> Result<Solution, SolveError> {
    let artifacts = &learned.artifacts;
    let texts =
        (artifact(artifacts, "domain.pddl"), artifact(artifacts, &format!("problems/{name}.pddl")));
    let mut planner = BuiltinPlanner::new(BuiltinAlgorithm::GbfsFf);
    let moved = |scene: &mut Scene| {
        let robot = &scene.robots()[0];
        let mut q = robot.configuration().to_vec();
        robot.robot().mount().write_coordinates(start, &mut q);
        scene.set_configuration(0, &q);
    };
    solve_scene(learned, name, 1, &mut planner, texts, false, &moved)
}

/// [`solve_from`] a mobile base at each `(x, y, yaw in degrees)` of `starts` on the floor: each
/// solve succeeds and its trajectory starts there. The solutions, for the caller's own checks.
pub fn solve_from_floor_starts(
    learned: &Learned,
    name: &str,
    starts: &[(f64, f64, f64)],
) -> Vec<Solution> {
    let mut solutions = Vec::new();
    for &(x, y, yaw) in starts {
        let start = nalgebra::Isometry3::new(
            nalgebra::Vector3::new(x, y, 0.0),
            nalgebra::Vector3::z() * yaw.to_radians(),
        );
        let solution = solve_from(learned, name, &start)
            .unwrap_or_else(|error| panic!("{name} from ({x}, {y}) at {yaw}°: {error}"));
        assert!(solution.summary.success, "{name} from ({x}, {y}) at {yaw}°");
        let first = &solution.trajectory.steps[0].robots[0].positions;
        let turned = (first[2] - yaw.to_radians()).sin().abs();
        assert!((first[0] - x).abs() < 1e-9 && (first[1] - y).abs() < 1e-9 && turned < 1e-9);
        solutions.push(solution);
    }
    solutions
}

fn solve_texts(
    learned: &Learned,
    name: &str,
    seed: u64,
    planner: &mut dyn Planner,
    texts: (&str, &str),
    relax_goal: bool,
) -> Result<Solution, SolveError> {
    solve_scene(learned, name, seed, planner, texts, relax_goal, &|_| {})
}

fn solve_scene(
    learned: &Learned,
    name: &str,
    seed: u64,
    planner: &mut dyn Planner,
    (domain, problem_text): (&str, &str),
    relax_goal: bool,
    edit: &dyn Fn(&mut Scene),
) -> Result<Solution, SolveError> {
    let Learned { spec, world, artifacts, refiner } = learned;
    let problem = spec.problems.iter().find(|p| p.name == name).expect("the problem exists");
    let mut scene = world.problem_scene(problem).expect("the scene loads");
    edit(&mut scene);
    let participants = ParticipantMap::new(spec, &world.robots).expect("a participant map");
    let samplers = SamplersFile::from_json(artifact(artifacts, "samplers.json")).expect("samplers");
    let never = || false;
    let settings = SolveSettings {
        seed,
        plan_count: 1,
        planner_budget: PlanBudget::default(),
        rounds: 20,
        max_refused: 100,
        motion: MotionSettings {
            config: MotionConfig::default(),
            budget: MotionBudget { max_iterations: Some(4000), time_limit: None },
            grab_ranges: lamp_tamp::grab_ranges(spec),
        },
        relax_goal,
        cancelled: &never,
    };
    let input = SolveInput {
        scene: &scene,
        domain,
        problem: problem_text,
        artifact: &samplers.artifact,
        participants: &participants,
        targets: &world.placement_targets(problem).expect("the targets"),
        header: trajectory_header(spec, &scene, seed),
    };
    let mut refiner = GmmRefiner::new(samplers.artifact.clone(), *refiner).expect("valid");
    let mut motion = RrtConnectPlanner::new(RrtOptions::default());
    let mut plugins = Plugins { planner, refiner: &mut refiner, motion: &mut motion };
    solve(&input, &mut plugins, &settings, &|_| {})
}

/// Asserts that in `solution` the fingers of robot 0 close onto every object it takes hold of
/// and open before it lets go: after each grab they come to rest (the end of the run in which
/// only they move) at each finger's `grasp_position`, within 1e-6 m, touching the object (a
/// collision distance under 1e-6 m) and nothing else; at each release they are back at their
/// open values, the problem's. Returns how many grasps were checked.
pub fn assert_fingers_grip(learned: &Learned, name: &str, solution: &Solution) -> usize {
    let problem =
        learned.spec.problems.iter().find(|p| p.name == name).expect("the problem exists");
    let initial = learned.world.problem_scene(problem).expect("the scene loads");
    let robot = initial.robots()[0].robot().clone();
    let open = initial.robots()[0].open_fingers().to_vec();
    assert!(!open.is_empty(), "{name}: the gripper has fingers");
    let steps = &solution.trajectory.steps;
    let held = |index: usize| steps[index].robots[0].held.first().copied().flatten();
    let positions = |index: usize| &steps[index].robots[0].positions;
    let fingers_move = |index: usize| {
        held(index) == held(index + 1)
            && open
                .iter()
                .any(|(finger, _)| positions(index)[*finger] != positions(index + 1)[*finger])
    };
    let mut grasps = 0;
    for index in 1..steps.len() {
        if held(index - 1) == held(index) {
            continue;
        }
        let Some(body) = held(index) else {
            for &(finger, value) in &open {
                assert_eq!(positions(index - 1)[finger], value, "{name}: open at step {index}");
            }
            continue;
        };
        for &(finger, value) in &open {
            assert_eq!(positions(index)[finger], value, "{name}: open at the grab, step {index}");
        }
        let mut closed = index;
        while closed + 1 < steps.len() && fingers_move(closed) {
            closed += 1;
        }
        assert!(closed > index, "{name}: the fingers close after the grab at step {index}");
        let q = positions(closed);
        let type_name = &initial.bodies()[body].type_name;
        let object = lamp_geometry::CollisionShape::compound(&learned.world.type_parts[type_name])
            .expect("a shape");
        let pose = steps[closed].body_poses[body];
        // Held, its pose is the gripper link's times the grasp: the same up to rounding.
        let moved = steps[index].body_poses[body].inv_mul(&pose);
        assert!(
            moved.translation.vector.norm() < 1e-12 && moved.rotation.angle() < 1e-12,
            "{name}: the object does not move as the fingers close: {moved:?}"
        );
        for &(finger, value) in &open {
            let stop = lamp_world::grasp_position(&robot, finger, positions(index), &object, &pose)
                .expect("a prismatic finger");
            assert!(stop.touches, "{name}: step {closed}: a finger closes past the object");
            let target = stop.position;
            assert!(
                (q[finger] - target).abs() < 1e-6,
                "{name}: step {closed}: {} not {target}",
                q[finger]
            );
            assert!(target < value, "{name}: the finger closes from {value} to {target}");
            let joint = &robot.coordinates()[finger].name;
            let link = (1..robot.link_count())
                .find(|link| robot.parent_joint_name(*link) == Some(joint.as_str()))
                .expect("the finger's link");
            let parts: Vec<_> = robot
                .collision_geometry()
                .iter()
                .filter(|geometry| geometry.link == link)
                .map(|geometry| (geometry.origin, geometry.shape.clone()))
                .collect();
            let shape = lamp_geometry::CollisionShape::compound(&parts).expect("a shape");
            let gap = lamp_geometry::distance(&shape, &robot.link_pose(q, link), &object, &pose);
            assert!(
                gap.abs() < 1e-6,
                "{name}: step {closed}: `{joint}` at {target} (open {value}) is {gap} m from it"
            );
        }
        let mut scene = initial.clone();
        for (other, pose) in steps[closed].body_poses.iter().enumerate() {
            scene.set_body_pose(other, *pose);
        }
        scene.set_configuration(0, positions(index));
        scene.grab(0, body).expect("a legal grab");
        assert_eq!(
            scene.first_contact(0, q),
            None,
            "{name}: step {closed} touches only the object"
        );
        grasps += 1;
    }
    grasps
}
