//! Throughput of full robot-versus-scene collision checks (Fetch among 30 objects) and the
//! median time of RRT-Connect for the Fetch arm reaching into a shelf.
//!
//! `cargo bench -p lamp-world`. The shelf figure is a median over 31 seeds, printed before
//! criterion's own runs.

#![allow(clippy::print_stderr, clippy::unwrap_used)]

#[path = "../tests/support/mod.rs"]
mod support;

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use lamp_geometry::{Shape, Vec3};
use lamp_robot::IkConfig;
use lamp_world::{Body, LinkGoal, MotionConfig, Scene, plan_motion, reach};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use support::{domain, pose};

fn board(name: &str, x: f64, y: f64, z: f64, size: [f64; 3]) -> (Body, lamp_geometry::Pose) {
    let body = Body {
        name: name.to_string(),
        type_name: "shelf".to_string(),
        movable: false,
        world: false,
        parts: vec![(
            lamp_geometry::Pose::identity(),
            Shape::Box { half_extents: Vec3::new(size[0], size[1], size[2]) * 0.5 },
        )],
    };
    (body, pose(x, y, z, 0.0, 0.0, 0.0))
}

/// The café scene plus cans scattered on the floor and tables until there are 30 objects.
fn cluttered() -> (Scene, usize, Vec<Vec<f64>>) {
    let (spec, world) = domain("cafe");
    let mut scene = world.problem_scene(&spec.problems[0]).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut index = 0;
    while scene.bodies().len() < 30 {
        let (x, y) = (rng.random_range(-2.0..5.0), rng.random_range(-2.5..3.5));
        if f64::hypot(x, y) < 1.2 {
            continue;
        }
        let body = world.body(&format!("clutter{index}"), "can").unwrap();
        scene.add_body(body, pose(x, y, 0.001, 0.0, 0.0, 0.0)).unwrap();
        index += 1;
    }
    let fetch = scene.robot_index("fetch").unwrap();
    let robot = scene.robots()[fetch].robot().clone();
    let tucked = scene.robots()[fetch].configuration().to_vec();
    let group = robot.group("all").unwrap().clone();
    let mut configurations = Vec::new();
    let mut out = tucked.clone();
    while configurations.len() < 512 {
        robot.sample_uniform(&group, &tucked, &mut rng, &mut out);
        configurations.push(out.clone());
    }
    (scene, fetch, configurations)
}

/// The Fetch at the origin facing a three-level shelf, and the arm goal inside the middle level.
fn shelf() -> (Scene, usize, Vec<f64>, Vec<f64>) {
    let (spec, world) = domain("cafe");
    let problem = &spec.problems[0];
    let mut scene = Scene::new();
    for object in problem.scene.objects.iter().filter(|o| o.type_name == "floor") {
        scene.add_body(world.body(&object.name, &object.type_name).unwrap(), object.pose).unwrap();
    }
    let boards = [
        board("side_left", 0.95, 0.42, 0.75, [0.4, 0.02, 1.5]),
        board("side_right", 0.95, -0.42, 0.75, [0.4, 0.02, 1.5]),
        board("back", 1.16, 0.0, 0.75, [0.02, 0.86, 1.5]),
        board("level0", 0.95, 0.0, 0.40, [0.4, 0.86, 0.02]),
        board("level1", 0.95, 0.0, 0.78, [0.4, 0.86, 0.02]),
        board("level2", 0.95, 0.0, 1.16, [0.4, 0.86, 0.02]),
    ];
    for (body, at) in boards {
        scene.add_body(body, at).unwrap();
    }
    let placement = &problem.scene.robots[0];
    let tucked =
        world.placement_configuration("fetch", None, placement.configuration.as_deref()).unwrap();
    let fetch = world.add_robot(&mut scene, "fetch", tucked.clone()).unwrap();
    assert!(scene.is_valid(fetch, &tucked), "{:?}", scene.first_contact(fetch, &tucked));
    let target = pose(0.95, 0.0, 0.92, 0.0, 0.0, 0.0);
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let goal = reach(
        &scene,
        &LinkGoal { robot: fetch, group: "arm", link: None, target: &target, start: &tucked },
        &IkConfig::new(),
        &mut rng,
    )
    .unwrap();
    (scene, fetch, tucked, goal)
}

fn shelf_median() {
    shelf_median_with("default", MotionConfig::default());
    let mut no_shortcut = MotionConfig::default();
    no_shortcut.rrt.shortcut_attempts = 0;
    shelf_median_with("no shortcut", no_shortcut);
}

fn shelf_median_with(label: &str, config: MotionConfig) {
    let (scene, fetch, start, goal) = shelf();
    let mut times = Vec::new();
    let mut failures = 0;
    for seed in 0..31 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let began = Instant::now();
        let result = plan_motion(&scene, fetch, "arm", &start, &goal, &config, &mut rng);
        times.push(began.elapsed().as_secs_f64() * 1e3);
        failures += usize::from(result.is_err());
    }
    times.sort_by(f64::total_cmp);
    eprintln!(
        "rrt-connect fetch arm into shelf ({label}): median {:.1} ms, min {:.1} ms, max {:.1} ms, {} of 31 failed",
        times[15], times[0], times[30], failures
    );
}

fn benches(c: &mut Criterion) {
    shelf_median();
    let (scene, fetch, configurations) = cluttered();
    let valid = configurations.iter().filter(|q| scene.is_valid(fetch, q)).count();
    eprintln!(
        "collision bench: {} objects, {valid} of {} random configurations valid",
        scene.bodies().len(),
        configurations.len()
    );
    let mut next = 0;
    c.bench_function("fetch vs 30 objects: full check", |b| {
        b.iter(|| {
            next = (next + 1) % configurations.len();
            black_box(scene.is_valid(fetch, black_box(&configurations[next])))
        })
    });
    let (scene, fetch, start, goal) = shelf();
    let config = MotionConfig::default();
    let mut seed = 0;
    let mut group = c.benchmark_group("rrt-connect");
    group.sample_size(20);
    group.bench_function("fetch arm into shelf", |b| {
        b.iter(|| {
            seed += 1;
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            black_box(plan_motion(&scene, fetch, "arm", &start, &goal, &config, &mut rng).ok())
        })
    });
    group.finish();
}

criterion_group!(world_benches, benches);
criterion_main!(world_benches);
