//! `rate R Hz`: a demonstration recorded as a logger writes one, the timed motion sampled every
//! 1/R seconds. Stamps are exactly 1/R apart, joint velocities stay within the URDF's limits, a
//! held object stays rigid with the gripper, and the grab and the release are both recorded.

mod support;

use std::sync::LazyLock;

use lamp_demonstrators::{
    DemoError, Demonstration, Demonstrator, Simulation, generate, generate_all,
};
use lamp_spec::{Spec, TrackingNoise};
use lamp_trajectory::Trajectory;
use lamp_world::{Scene, SpecWorld};

static PACKING: LazyLock<(Spec, SpecWorld)> = LazyLock::new(|| support::domain("packing"));
static CAFE: LazyLock<(Spec, SpecWorld)> = LazyLock::new(|| support::domain("cafe"));

fn simulation(demonstrator: Demonstrator, rate: Option<f64>) -> Simulation {
    Simulation {
        demonstrator,
        count: 2,
        cut_fraction: 0.0,
        objects: 1,
        seed: 5,
        noise: TrackingNoise::NONE,
        rate,
    }
}

/// Packing's two demonstrations of seed 5 as the script records them and at 50 Hz.
static PACKING_DEMOS: LazyLock<(Vec<Demonstration>, Vec<Demonstration>)> = LazyLock::new(|| {
    let (_, world) = &*PACKING;
    let dense = generate_all(world, &simulation(Demonstrator::Packing, None), |_| {})
        .expect("seed 5 generates");
    let timed = generate_all(world, &simulation(Demonstrator::Packing, Some(50.0)), |_| {})
        .expect("seed 5 generates");
    (dense, timed)
});

/// The scene of a trajectory's robot at its first step, to measure its gripper.
fn scene_of(world: &SpecWorld, trajectory: &Trajectory) -> Scene {
    let mut scene = Scene::new();
    let first = &trajectory.steps[0];
    for (body, pose) in trajectory.header.bodies.iter().zip(&first.body_poses) {
        if let Some(template) = world.body(&body.name, &body.type_name) {
            scene.add_body(template, *pose).expect("unique names");
        }
    }
    world
        .add_robot(&mut scene, &trajectory.header.robots[0].name, first.robots[0].positions.clone())
        .expect("the spec's robot");
    scene
}

/// Checks everything a fixed-rate recording promises, against the same demonstration recorded
/// as the script records it.
fn check_at_rate(world: &SpecWorld, dense: &Trajectory, timed: &Trajectory, rate: f64) {
    let period = (1e9 / rate).round() as u64;
    // Exactly 1/R apart, from 0.
    for (k, step) in timed.steps.iter().enumerate() {
        assert_eq!(step.time_nanoseconds, k as u64 * period, "sample {k}");
    }
    // It starts and ends where the script did.
    assert_eq!(
        timed.steps.first().expect("a step").robots,
        dense.steps.first().expect("a step").robots
    );
    assert_eq!(
        timed.steps.last().expect("a step").robots,
        dense.steps.last().expect("a step").robots
    );
    assert_eq!(
        timed.steps.last().expect("a step").body_poses,
        dense.steps.last().expect("a step").body_poses
    );
    // The grab and the release: the same changes of what the gripper holds, in the same order.
    let changes = |trajectory: &Trajectory| {
        let mut held: Vec<Option<usize>> = Vec::new();
        for step in &trajectory.steps {
            if held.last() != Some(&step.robots[0].held[0]) {
                held.push(step.robots[0].held[0]);
            }
        }
        held
    };
    let grasps = changes(timed);
    assert_eq!(grasps, changes(dense));
    assert!(grasps.len() >= 3 && grasps[1].is_some(), "grabbed and let go of: {grasps:?}");
    let scene = scene_of(world, timed);
    let robot = scene.robots()[0].robot();
    // Velocities within the limits: every coordinate's displacement over one period.
    let mut moved = vec![0.0; robot.dof()];
    let mut fastest: f64 = 0.0;
    for (k, pair) in timed.steps.windows(2).enumerate() {
        robot.displacement(&pair[0].robots[0].positions, &pair[1].robots[0].positions, &mut moved);
        for (coordinate, distance) in robot.coordinates().iter().zip(&moved) {
            let speed = distance.abs() / (period as f64 * 1e-9);
            let ratio = speed / coordinate.velocity;
            assert!(ratio <= 1.0 + 1e-6, "sample {k}: {} at {speed} per s", coordinate.name);
            fastest = fastest.max(ratio);
        }
    }
    assert!(fastest > 0.3, "the robot moves at a good share of its limits: {fastest}");
    // A held object rigid with the gripper, in the grasp the script made.
    let grasp_in = |trajectory: &Trajectory, step: usize, body: usize| {
        let state = &trajectory.steps[step];
        let gripper = scene.gripper_pose(0, &state.robots[0].positions).expect("a gripper");
        gripper.inv_mul(&state.body_poses[body])
    };
    let held_at = |trajectory: &Trajectory| {
        trajectory.steps.iter().position(|step| step.robots[0].held[0].is_some()).expect("a grab")
    };
    let body = timed.steps[held_at(timed)].robots[0].held[0].expect("a held body");
    let grasp = grasp_in(dense, held_at(dense), body);
    let mut held_samples = 0;
    for (k, step) in timed.steps.iter().enumerate() {
        if step.robots[0].held[0] == Some(body) {
            let now = grasp_in(timed, k, body);
            let off = (now.translation.vector - grasp.translation.vector).norm();
            let turned = now.rotation.angle_to(&grasp.rotation);
            assert!(off < 1e-9 && turned < 1e-9, "sample {k}: {off} m, {turned} rad off");
            held_samples += 1;
        }
    }
    assert!(held_samples > 10, "{held_samples} held samples");
}

#[test]
fn packing_at_50_hz_keeps_its_promises() {
    let (_, world) = &*PACKING;
    let (dense, timed) = &*PACKING_DEMOS;
    for (dense, timed) in dense.iter().zip(timed) {
        check_at_rate(world, &dense.trajectory, &timed.trajectory, 50.0);
        assert_eq!(timed.trajectory.header.provenance["recording_rate"], "50 Hz");
        assert!(!dense.trajectory.header.provenance.contains_key("recording_rate"));
        // The release is the last step a cut may keep, at the rate too.
        let release = &timed.trajectory.steps[timed.retreat_at - 1];
        let before = &timed.trajectory.steps[timed.retreat_at - 2];
        assert_eq!(release.robots[0].held[0], None);
        assert!(before.robots[0].held[0].is_some());
    }
}

#[test]
fn packing_at_100_hz_and_cafe_at_50_hz_keep_their_promises() {
    let (_, world) = &*PACKING;
    let (dense, _) = &*PACKING_DEMOS;
    let fast = generate(world, &simulation(Demonstrator::Packing, Some(100.0)), 0).unwrap();
    check_at_rate(world, &dense[0].trajectory, &fast.trajectory, 100.0);
    let (_, world) = &*CAFE;
    let dense = generate(world, &simulation(Demonstrator::Cafe, None), 0).unwrap();
    let timed = generate(world, &simulation(Demonstrator::Cafe, Some(50.0)), 0).unwrap();
    check_at_rate(world, &dense.trajectory, &timed.trajectory, 50.0);
    // A real logger's count: a Café demonstration takes tens of seconds.
    let seconds = timed.trajectory.steps.last().unwrap().time_nanoseconds as f64 * 1e-9;
    assert!(seconds > 10.0, "{seconds} s");
}

#[test]
fn cut_demonstrations_at_a_rate_are_prefixes_that_stop_by_the_release() {
    let (_, world) = &*PACKING;
    let cut =
        Simulation { count: 4, cut_fraction: 1.0, ..simulation(Demonstrator::Packing, Some(50.0)) };
    let whole = Simulation { cut_fraction: 0.0, ..cut.clone() };
    let cut = generate_all(world, &cut, |_| {}).unwrap();
    let whole = generate_all(world, &whole, |_| {}).unwrap();
    for (cut, whole) in cut.iter().zip(&whole) {
        let kept = cut.cut_at.expect("every one is cut");
        assert!(kept <= whole.retreat_at);
        assert_eq!(cut.trajectory.steps[..], whole.trajectory.steps[..kept]);
    }
}

#[test]
fn the_bytes_depend_on_the_seed_alone_and_a_rate_out_of_range_is_refused() {
    let (_, world) = &*PACKING;
    let (_, timed) = &*PACKING_DEMOS;
    let alone = generate(world, &simulation(Demonstrator::Packing, Some(50.0)), 1).unwrap();
    assert_eq!(alone.to_bytes().unwrap(), timed[1].to_bytes().unwrap());
    for rate in [0.5, 1001.0, f64::NAN] {
        let error = generate(world, &simulation(Demonstrator::Packing, Some(rate)), 0).unwrap_err();
        assert!(matches!(error, DemoError::Unsupported { .. }), "{rate}: {error}");
        assert!(error.to_string().contains("recording rate"), "{error}");
    }
}
