//! Throughput of inverse kinematics (Fetch 7-DoF arm, Fetch arm with torso, YuMi) and forward
//! kinematics, single-threaded.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use lamp_robot::{IkConfig, IkGoal, Mount, Pose, Robot, solve_ik};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const TARGETS: usize = 256;

fn load(file: &str) -> Robot {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../domains/robots").join(file);
    Robot::from_urdf_file(&path, Mount::Fixed(Pose::identity())).expect("shipped robot loads")
}

fn fetch_arm7() -> Robot {
    load("fetch.urdf")
        .with_group(
            "arm7",
            &[
                "shoulder_pan_joint",
                "shoulder_lift_joint",
                "upperarm_roll_joint",
                "elbow_flex_joint",
                "forearm_roll_joint",
                "wrist_flex_joint",
                "wrist_roll_joint",
            ],
        )
        .expect("arm joints exist")
}

/// Reachable targets (FK of random configurations) and random start configurations.
fn problems(robot: &Robot, group: &str) -> Vec<(Pose, Vec<f64>)> {
    let group = robot.group(group).expect("group exists");
    let link = robot.end_effector().expect("end effector");
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let neutral = robot.neutral_configuration();
    let (mut goal, mut start) = (neutral.clone(), neutral.clone());
    (0..TARGETS)
        .map(|_| {
            robot.sample_uniform(group, &neutral, &mut rng, &mut goal);
            robot.sample_uniform(group, &neutral, &mut rng, &mut start);
            (robot.link_pose(&goal, link), start.clone())
        })
        .collect()
}

fn bench_ik(criterion: &mut Criterion, name: &str, robot: &Robot, group_name: &str) {
    let group = robot.group(group_name).expect("group exists").clone();
    let link = robot.end_effector().expect("end effector");
    let problems = problems(robot, group_name);
    let config = IkConfig::new();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut next = 0;
    criterion.bench_function(name, |bencher| {
        bencher.iter(|| {
            let (target, start) = &problems[next % TARGETS];
            next += 1;
            black_box(
                solve_ik(
                    &IkGoal { robot, group: &group, link, target, seed: start },
                    &config,
                    &mut rng,
                    &mut |_| true,
                )
                .ok(),
            )
        })
    });
}

fn benchmarks(criterion: &mut Criterion) {
    let arm7 = fetch_arm7();
    bench_ik(criterion, "ik/fetch_arm_7dof", &arm7, "arm7");
    bench_ik(criterion, "ik/fetch_arm_torso_8dof", &arm7, "arm");
    bench_ik(criterion, "ik/yumi_arm_7dof", &load("yumi.urdf"), "arm");

    let fetch = load("fetch.urdf");
    let q = fetch.neutral_configuration();
    let mut poses = vec![Pose::identity(); fetch.link_count()];
    criterion.bench_function("fk/fetch_all_links", |bencher| {
        bencher.iter(|| fetch.forward_kinematics(black_box(&q), black_box(&mut poses)))
    });
    let gripper = fetch.end_effector().expect("gripper");
    criterion.bench_function("fk/fetch_gripper_link_pose", |bencher| {
        bencher.iter(|| black_box(fetch.link_pose(black_box(&q), gripper)))
    });
}

criterion_group!(benches, benchmarks);
criterion_main!(benches);
