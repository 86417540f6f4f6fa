//! Arm motion queries from two bundled domains, planned by lamp's RRT-Connect and written out
//! so that another planner can be run on the very same problems (`domains/tools/ompl_compare.py`,
//! docs/benchmarks.md, "Arm motion planning beside OMPL").
//!
//! ```sh
//! cargo run --release -p lamp-world --example arm_queries -- /tmp/queries.json
//! ```
//!
//! Three scenes: the Fetch parked before a café table with five cans on it, planning its `arm`
//! group (torso and seven joints) to side grasps and pre-grasps of the cans, then to the
//! pre-grasps alone; and the YuMi's left arm over a Keva table with a built pi, standing planks
//! and flat planks, to top grasps and pre-grasps.
//! Each scene keeps 20 queries whose straight joint-space segment collides (the planner's own
//! edge check decides), and each query is planned with 5 seeds. The file holds what the other
//! side needs: the robot's URDF, base pose, checked self-collision pairs, the group's joints,
//! every obstacle as a primitive at its world pose, and the queries with lamp's results; and a
//! set of sampled states with lamp's verdict on each, on which both sides time one check and
//! compare their verdicts.

// A failed step means the bundled domains changed under the example: stopping is the answer.
#![allow(clippy::unwrap_used, clippy::print_stdout, clippy::print_stderr)]

use std::cell::Cell;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use lamp_geometry::{Pose, Shape};
use lamp_robot::{CoordinateKind, IkConfig};
use lamp_world::{
    LinkGoal, MotionConfig, RobotSpace, Scene, Space, plan_motion, reach, rrt_connect, shortcut,
};
use nalgebra::{Translation3, UnitQuaternion};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const QUERIES: usize = 20;
const SEEDS: u64 = 5;
const TIMED_CHECKS: usize = 2_000;

fn pose(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> Pose {
    Pose::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(roll, pitch, yaw),
    )
}

/// A scene with one robot, its planning group and the configurations goals are reached from.
struct Setup {
    name: &'static str,
    urdf: String,
    scene: Scene,
    robot: usize,
    group: &'static str,
    start: Vec<f64>,
    /// Gripper link targets, tried in order; those IK reaches become goals.
    targets: Vec<Pose>,
}

/// The Fetch before table1 of the café, with five cans on the table; goals at grasps and
/// pre-grasps, or at pre-grasps only.
fn cafe(grasps: bool) -> Setup {
    let (spec, world) = lamp_test_support::domain("cafe");
    let problem = &spec.problems[0];
    let mut scene = Scene::new();
    for object in &problem.scene.objects {
        let keep = object.type_name == "floor" || object.name.starts_with("table1");
        if keep {
            scene
                .add_body(world.body(&object.name, &object.type_name).unwrap(), object.pose)
                .unwrap();
        }
    }
    // table1's top is centred at (2, -1) and 0.73 m high; the cans stand across its near half,
    // where the parked Fetch reaches, close enough to be in each other's way.
    let cans = [(1.78, -1.22), (1.80, -1.0), (1.76, -0.80), (1.95, -1.10), (1.97, -0.88)];
    for (index, &(x, y)) in cans.iter().enumerate() {
        let body = world.body(&format!("can{}", index + 1), "can").unwrap();
        scene.add_body(body, pose(x, y, 0.731, 0.0, 0.0, 0.0)).unwrap();
    }
    let placement = &problem.scene.robots[0];
    let base = pose(1.3, -1.0, 0.0, 0.0, 0.0, 0.0);
    let tucked = world
        .placement_configuration("fetch", Some(&base), placement.configuration.as_deref())
        .unwrap();
    let robot = world.add_robot(&mut scene, "fetch", tucked.clone()).unwrap();
    assert!(scene.is_valid(robot, &tucked), "{:?}", scene.first_contact(robot, &tucked));
    // A side grasp holds a can at mid-height, approaching horizontally from the base, with
    // gripper_link 1.5 cm short of the can's axis (the palm begins 3.5 cm behind it, the can's
    // side is 4.5 cm from its axis); a pre-grasp stands 9 cm back. Three approach directions
    // per can make 30 targets, some of them unreachable. A grasp puts the open fingers 9 mm from
    // either side of the can, a narrow passage the solver enters by a straight line from the
    // pre-grasp, never by planning; the pre-grasps alone are the queries it plans.
    let backs: &[f64] = if grasps { &[0.015, 0.09] } else { &[0.09] };
    let mut targets = Vec::new();
    for &(x, y) in &cans {
        let toward = f64::atan2(y - base.translation.y, x - base.translation.x);
        for turn in [0.0, -0.35, 0.35] {
            for back in backs {
                let yaw = toward + turn;
                let (bx, by) = (x - back * yaw.cos(), y - back * yaw.sin());
                targets.push(pose(bx, by, 0.731 + 0.10, 0.0, 0.0, yaw));
            }
        }
    }
    Setup {
        name: if grasps { "Café" } else { "Café, pre-grasps" },
        urdf: urdf_path("cafe", &spec, "fetch"),
        scene,
        robot,
        group: "arm",
        start: tucked,
        targets,
    }
}

/// The YuMi's left arm over a Keva table: `pi_tower_3` built at its anchor, three planks
/// standing beside it and three lying flat in the supply.
fn keva() -> Setup {
    let (spec, world) = lamp_test_support::domain("keva");
    let problem = spec.problems.iter().find(|p| p.name == "pi_tower_3").unwrap();
    let mut scene = world.problem_scene(problem).unwrap();
    for (name, target) in world.structure_targets(problem).unwrap() {
        let body = scene.body_index(&name).unwrap();
        scene.set_body_pose(body, target);
    }
    // Upright planks (a pi's leg pose: the plank's frame is its bottom face's centre, 1 mm above
    // the table) between the supply and the tower, where an arm moving between them must go
    // around; flat planks in the supply to be picked.
    let standing = [(-0.20, 0.02), (-0.20, 0.16), (-0.12, -0.08)];
    for (index, &(x, y)) in standing.iter().enumerate() {
        let body = world.body(&format!("s{}", index + 1), "plank").unwrap();
        scene.add_body(body, pose(x, y, 0.0595, 0.0, -90f64.to_radians(), 0.0)).unwrap();
    }
    let flat = [(-0.35, -0.06), (-0.35, 0.06), (-0.30, 0.20)];
    for (index, &(x, y)) in flat.iter().enumerate() {
        let body = world.body(&format!("f{}", index + 1), "plank").unwrap();
        scene.add_body(body, pose(x, y, 0.001, 0.0, 0.0, 0.0)).unwrap();
    }
    let robot = scene.robot_index("yumi").unwrap();
    let home = scene.robots()[robot].configuration().to_vec();
    // A top grasp has the gripper pointing down with a plank's bottom face 13.5 cm along its
    // approach axis (the middle of the spec's grab distance), fingers across the plank's width;
    // a pre-grasp is 6 cm higher.
    let mut targets = Vec::new();
    let mut grasp = |frame: Pose, thickness: f64| {
        for lift in [0.0, 0.06] {
            for turn in [0.0, std::f64::consts::PI] {
                let top = frame * pose(0.0, 0.0, 0.135 - 0.007 + thickness + lift, 0.0, 0.0, 0.0);
                targets.push(top * pose(0.0, 0.0, 0.0, std::f64::consts::PI, 0.0, turn));
            }
        }
    };
    for name in ["p3", "f1", "f2", "f3"] {
        grasp(scene.body_pose(scene.body_index(name).unwrap()), 0.007);
    }
    for &(x, y) in &standing {
        // A standing plank's top is its end face, 0.117 m up.
        grasp(pose(x, y, 0.001, 0.0, 0.0, 0.0), 0.117);
    }
    Setup {
        name: "Keva",
        urdf: urdf_path("keva", &spec, "yumi"),
        scene,
        robot,
        group: "arm",
        start: home,
        targets,
    }
}

fn urdf_path(domain: &str, spec: &lamp_spec::Spec, robot: &str) -> String {
    let dir = lamp_test_support::spec_path(domain).parent().unwrap().to_path_buf();
    let path = dir.join(&spec.robot(robot).unwrap().urdf);
    path.canonicalize().unwrap().display().to_string()
}

/// A space that counts the states it checks, answering exactly as the space it wraps (the
/// same trees grow from the same seed).
struct Counting<'a> {
    space: RobotSpace<'a>,
    checks: Cell<usize>,
}

impl Space for Counting<'_> {
    fn sample(&self, rng: &mut ChaCha8Rng, out: &mut [f64]) {
        self.space.sample(rng, out);
    }
    fn distance(&self, a: &[f64], b: &[f64]) -> f64 {
        self.space.distance(a, b)
    }
    fn distance_form(&self, q: &[f64]) -> Vec<f64> {
        self.space.distance_form(q)
    }
    fn nearest(&self, forms: &[Vec<f64>], form: &[f64]) -> usize {
        self.space.nearest(forms, form)
    }
    fn interpolate(&self, a: &[f64], b: &[f64], t: f64, out: &mut [f64]) {
        self.space.interpolate(a, b, t, out);
    }
    fn is_valid(&self, q: &[f64]) -> bool {
        self.checks.set(self.checks.get() + 1);
        self.space.is_valid(q)
    }
    fn edge_steps(&self, a: &[f64], b: &[f64]) -> usize {
        self.space.edge_steps(a, b)
    }
}

struct Run {
    seed: u64,
    success: bool,
    ms: f64,
    raw_length: f64,
    length: f64,
    checks: usize,
    search_checks: usize,
    /// Why a failed run failed.
    error: String,
}

struct Query {
    start: Vec<f64>,
    goal: Vec<f64>,
    straight: f64,
    runs: Vec<Run>,
}

fn path_length(setup: &Setup, path: &[Vec<f64>]) -> f64 {
    let robot = setup.scene.robots()[setup.robot].robot();
    path.windows(2).map(|pair| robot.distance(&pair[0], &pair[1])).sum()
}

fn plan(setup: &Setup, start: &[f64], goal: &[f64], seed: u64) -> Run {
    let config = MotionConfig::default();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let began = Instant::now();
    let planned =
        plan_motion(&setup.scene, setup.robot, setup.group, start, goal, &config, &mut rng);
    let ms = began.elapsed().as_secs_f64() * 1e3;
    let planned = match planned {
        Ok(planned) => planned,
        Err(error) => {
            let error = error.to_string();
            return Run {
                seed,
                success: false,
                ms,
                raw_length: 0.0,
                length: 0.0,
                checks: 0,
                search_checks: 0,
                error,
            };
        }
    };
    // The same run again, split where plan_motion shortcuts, for the path before shortcutting
    // and the checks each part makes; it must end on the path plan_motion returned.
    let space = RobotSpace::new(&setup.scene, setup.robot, setup.group, start, goal, &config);
    let counting = Counting { space: space.unwrap(), checks: Cell::new(0) };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let search = lamp_world::RrtConfig { shortcut_attempts: 0, ..config.rrt.clone() };
    let (raw, _) = rrt_connect(&counting, start, goal, &search, &mut rng).unwrap();
    let search_checks = counting.checks.get();
    let shortened = shortcut(&counting, raw.clone(), config.rrt.shortcut_attempts, &mut rng);
    assert_eq!(shortened, planned.waypoints, "the split run follows plan_motion");
    Run {
        seed,
        success: true,
        ms,
        raw_length: path_length(setup, &raw),
        length: path_length(setup, &planned.waypoints),
        checks: counting.checks.get(),
        search_checks,
        error: String::new(),
    }
}

/// Goals reached by IK, then queries between the start and the goals and between goals, in a
/// fixed order, keeping those whose straight segment collides.
fn queries(setup: &Setup) -> (usize, Vec<Query>) {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut goals = Vec::new();
    for target in &setup.targets {
        let goal = LinkGoal {
            robot: setup.robot,
            group: setup.group,
            link: None,
            target,
            start: &setup.start,
        };
        if let Ok(q) = reach(&setup.scene, &goal, &IkConfig::new(), &mut rng) {
            goals.push(q);
        }
    }
    let reached = goals.len();
    let config = MotionConfig::default();
    let mut pairs: Vec<(Vec<f64>, Vec<f64>)> =
        goals.iter().map(|goal| (setup.start.clone(), goal.clone())).collect();
    // Goal-to-goal pairs interleaved by distance in the list, so that the kept ones are spread
    // over the targets rather than all starting at the first goal.
    for gap in 1..goals.len() {
        for i in 0..goals.len() - gap {
            pairs.push((goals[i].clone(), goals[i + gap].clone()));
        }
    }
    let robot = setup.scene.robots()[setup.robot].robot();
    let mut kept = Vec::new();
    for (index, (start, goal)) in pairs.into_iter().enumerate() {
        if kept.len() == QUERIES {
            break;
        }
        // Every other start-to-goal query, then goal-to-goal ones, for a mix of both.
        if index < reached && index % 2 == 1 {
            continue;
        }
        let space = RobotSpace::new(&setup.scene, setup.robot, setup.group, &start, &goal, &config)
            .unwrap();
        if space.edge_is_valid(&start, &goal) {
            continue;
        }
        let straight = robot.distance(&start, &goal);
        kept.push(Query { start, goal, straight, runs: Vec::new() });
    }
    assert_eq!(kept.len(), QUERIES, "{}: too few colliding queries", setup.name);
    (reached, kept)
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    if values.is_empty() { f64::NAN } else { values[values.len() / 2] }
}

fn percentile(mut values: Vec<f64>, p: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    if values.is_empty() {
        return f64::NAN;
    }
    let rank = (p * (values.len() - 1) as f64).round() as usize;
    values[rank]
}

fn json_numbers(values: &[f64]) -> String {
    let inner: Vec<String> = values.iter().map(|v| format!("{v:?}")).collect();
    format!("[{}]", inner.join(", "))
}

fn json_pose(pose: &Pose) -> String {
    let t = pose.translation.vector;
    let q = pose.rotation.quaternion();
    format!(
        "{{\"position\": {}, \"orientation\": {}}}",
        json_numbers(&[t.x, t.y, t.z]),
        json_numbers(&[q.i, q.j, q.k, q.w])
    )
}

/// Every body's shapes as primitives at world poses; meshes, which the bundled scenes here do
/// not have, are counted and left out.
fn obstacles(scene: &Scene) -> (Vec<String>, usize) {
    let mut out = Vec::new();
    let mut skipped = 0;
    for (index, body) in scene.bodies().iter().enumerate() {
        let at = scene.body_pose(index);
        for (origin, shape) in &body.parts {
            let world = at * origin;
            let geometry = match shape {
                Shape::Box { half_extents } => format!(
                    "\"shape\": \"box\", \"half_extents\": {}",
                    json_numbers(&[half_extents.x, half_extents.y, half_extents.z])
                ),
                Shape::Cylinder { radius, half_height } => format!(
                    "\"shape\": \"cylinder\", \"radius\": {radius:?}, \"length\": {:?}",
                    half_height * 2.0
                ),
                Shape::Sphere { radius } => {
                    format!("\"shape\": \"sphere\", \"radius\": {radius:?}")
                }
                _ => {
                    skipped += 1;
                    continue;
                }
            };
            out.push(format!(
                "{{\"body\": \"{}\", {geometry}, \"pose\": {}}}",
                body.name,
                json_pose(&world)
            ));
        }
    }
    (out, skipped)
}

/// Times `RobotSpace::is_valid` (what the planner calls: the group's moving links) and
/// `Scene::is_valid` (the whole robot) on uniformly sampled group configurations; returns the
/// states, lamp's verdicts, and microseconds per check of each.
fn timed_checks(setup: &Setup) -> Checks {
    let robot = setup.scene.robots()[setup.robot].robot();
    let group = robot.group(setup.group).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut states = Vec::new();
    let mut q = setup.start.clone();
    for _ in 0..TIMED_CHECKS {
        robot.sample_uniform(group, &setup.start, &mut rng, &mut q);
        states.push(q.clone());
    }
    let config = MotionConfig::default();
    let space = RobotSpace::new(
        &setup.scene,
        setup.robot,
        setup.group,
        &setup.start,
        &setup.start,
        &config,
    )
    .unwrap();
    let began = Instant::now();
    let verdicts: Vec<bool> = states.iter().map(|q| space.is_valid(q)).collect();
    let moving_us = began.elapsed().as_secs_f64() * 1e6 / TIMED_CHECKS as f64;
    let began = Instant::now();
    let whole: Vec<bool> = states.iter().map(|q| setup.scene.is_valid(setup.robot, q)).collect();
    let whole_us = began.elapsed().as_secs_f64() * 1e6 / TIMED_CHECKS as f64;
    assert_eq!(verdicts, whole, "a valid start makes both checks agree");
    (states, verdicts, moving_us, whole_us)
}

type Checks = (Vec<Vec<f64>>, Vec<bool>, f64, f64);

fn scene_json(setup: &Setup, reached: usize, queries: &[Query], checks: &Checks) -> String {
    let scene_robot = &setup.scene.robots()[setup.robot];
    let robot = scene_robot.robot();
    let group = robot.group(setup.group).unwrap();
    let base = robot.mount().root_pose(&setup.start);
    let names = robot.coordinate_names();
    let mount = robot.mount().coordinate_count();
    let joints: Vec<String> = group
        .coordinates
        .iter()
        .map(|&index| {
            let c = &robot.coordinates()[index];
            let kind = match c.kind {
                CoordinateKind::Linear => "linear",
                CoordinateKind::Angle => "angle",
                CoordinateKind::WrappedAngle => "wrapped",
                CoordinateKind::Rotation(_) => "rotation",
            };
            format!(
                "{{\"name\": \"{}\", \"index\": {index}, \"kind\": \"{kind}\", \"lower\": {:?}, \"upper\": {:?}, \"weight\": {:?}}}",
                c.name, c.lower, c.upper, c.weight
            )
        })
        .collect();
    // Joints outside the group stay at the start's values for every query.
    let held: Vec<String> = (mount..names.len())
        .filter(|index| !group.coordinates.contains(index))
        .map(|index| format!("\"{}\": {:?}", names[index], setup.start[index]))
        .collect();
    let pairs: Vec<String> = robot
        .self_collision_pairs()
        .iter()
        .map(|&(a, b)| format!("[\"{}\", \"{}\"]", robot.link_name(a), robot.link_name(b)))
        .collect();
    let (shapes, skipped) = obstacles(&setup.scene);
    let (states, verdicts, moving_us, whole_us) = checks;
    let group_values =
        |q: &[f64]| -> Vec<f64> { group.coordinates.iter().map(|&i| q[i]).collect() };
    let mut out = String::new();
    let _ = write!(
        out,
        "{{\"name\": \"{}\", \"urdf\": \"{}\", \"base\": {}, \"joints\": [{}], \"other_joints\": {{{}}}, \"self_collision_pairs\": [{}], \"margin\": {:?}, \"obstacles\": [{}], \"skipped_meshes\": {skipped}, \"goals_reached\": {reached}, \"goal_targets\": {}, ",
        setup.name,
        setup.urdf,
        json_pose(&base),
        joints.join(", "),
        held.join(", "),
        pairs.join(", "),
        setup.scene.margin(),
        shapes.join(", "),
        setup.targets.len(),
    );
    let config = MotionConfig::default();
    let _ = write!(
        out,
        "\"resolution\": {{\"linear\": {:?}, \"angular\": {:?}}}, \"step\": {:?}, \"shortcut_attempts\": {}, ",
        config.linear_resolution,
        config.angular_resolution,
        config.rrt.step,
        config.rrt.shortcut_attempts
    );
    let _ = write!(
        out,
        "\"check_us\": {{\"planner\": {moving_us:?}, \"whole_robot\": {whole_us:?}}}, \"check_states\": [{}], \"check_valid\": [{}], ",
        states.iter().map(|q| json_numbers(&group_values(q))).collect::<Vec<_>>().join(", "),
        verdicts.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(", ")
    );
    let queries: Vec<String> = queries
        .iter()
        .map(|query| {
            let runs: Vec<String> = query
                .runs
                .iter()
                .map(|run| {
                    format!(
                        "{{\"seed\": {}, \"success\": {}, \"ms\": {:?}, \"raw_length\": {:?}, \"length\": {:?}, \"checks\": {}, \"search_checks\": {}, \"error\": {:?}}}",
                        run.seed, run.success, run.ms, run.raw_length, run.length, run.checks, run.search_checks, run.error
                    )
                })
                .collect();
            format!(
                "{{\"start\": {}, \"goal\": {}, \"straight\": {:?}, \"lamp\": [{}]}}",
                json_numbers(&group_values(&query.start)),
                json_numbers(&group_values(&query.goal)),
                query.straight,
                runs.join(", ")
            )
        })
        .collect();
    let _ = write!(out, "\"queries\": [{}]}}", queries.join(",\n"));
    out
}

fn main() {
    let Some(output) = std::env::args().nth(1) else {
        eprintln!("usage: arm_queries OUTPUT.json");
        std::process::exit(2);
    };
    let mut scenes = Vec::new();
    println!(
        "| scene | planner | success | median / p90 time | length raw / shortcut | checks (search) | one check |"
    );
    println!("|---|---|---|---|---|---|---|");
    for setup in [cafe(true), cafe(false), keva()] {
        let (reached, mut queries) = queries(&setup);
        for query in &mut queries {
            query.runs =
                (0..SEEDS).map(|seed| plan(&setup, &query.start, &query.goal, seed)).collect();
        }
        let runs: Vec<(&Query, &Run)> =
            queries.iter().flat_map(|q| q.runs.iter().map(move |r| (q, r))).collect();
        let solved: Vec<&(&Query, &Run)> = runs.iter().filter(|(_, r)| r.success).collect();
        let times: Vec<f64> = runs.iter().map(|(_, r)| r.ms).collect();
        let raw = median(solved.iter().map(|(q, r)| r.raw_length / q.straight).collect());
        let short = median(solved.iter().map(|(q, r)| r.length / q.straight).collect());
        let checks = median(solved.iter().map(|(_, r)| r.checks as f64).collect());
        let search = median(solved.iter().map(|(_, r)| r.search_checks as f64).collect());
        let timed = timed_checks(&setup);
        let moving_us = timed.2;
        let json = scene_json(&setup, reached, &queries, &timed);
        println!(
            "| {} | lamp | {}/{} | {:.1} / {:.1} ms | {raw:.2} / {short:.2} | {checks:.0} ({search:.0}) | {moving_us:.1} µs |",
            setup.name,
            solved.len(),
            runs.len(),
            median(times.clone()),
            percentile(times, 0.9),
        );
        eprintln!(
            "{}: {} of {} goal targets reached by IK, {QUERIES} queries",
            setup.name,
            reached,
            setup.targets.len()
        );
        let mut failures: Vec<&str> =
            runs.iter().filter(|(_, r)| !r.success).map(|(_, r)| r.error.as_str()).collect();
        failures.sort_unstable();
        failures.dedup();
        for failure in failures {
            eprintln!("  failed: {failure}");
        }
        scenes.push(json);
    }
    let text = format!("{{\"scenes\": [\n{}\n]}}\n", scenes.join(",\n"));
    std::fs::write(Path::new(&output), text).unwrap();
}
