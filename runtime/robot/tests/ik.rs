//! Inverse kinematics round trips and failure modes.

mod common;

use lamp_robot::{IkConfig, IkError, IkGoal, Mount, Pose, Robot, pose_error_norms, solve_ik};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Solves IK for the FK of `count` random configurations of `group`, each from a fresh random seed
/// configuration, and returns the number of successes (checked independently with FK).
fn round_trips(robot: &Robot, group_name: &str, count: usize, seed: u64) -> usize {
    let group = robot.group(group_name).expect("group exists").clone();
    let link = robot.end_effector().expect("robot has an end effector");
    let config = IkConfig::new();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let neutral = robot.neutral_configuration();
    let mut goal = neutral.clone();
    let mut start = neutral.clone();
    let mut successes = 0;
    for _ in 0..count {
        robot.sample_uniform(&group, &neutral, &mut rng, &mut goal);
        robot.sample_uniform(&group, &neutral, &mut rng, &mut start);
        let target = robot.link_pose(&goal, link);
        if let Ok(solution) = solve_ik(
            &IkGoal { robot, group: &group, link, target: &target, seed: &start },
            &config,
            &mut rng,
            &mut |_| true,
        ) {
            let (position, orientation) =
                pose_error_norms(&robot.link_pose(&solution, link), &target);
            assert!(
                position <= config.position_tolerance
                    && orientation <= config.orientation_tolerance
            );
            assert!(robot.within_limits(&solution), "IK solution violates joint limits");
            for index in 0..robot.dof() {
                if !group.coordinates.contains(&index) {
                    assert_eq!(
                        solution[index], start[index],
                        "IK changed a coordinate outside the group"
                    );
                }
            }
            successes += 1;
        }
    }
    successes
}

#[test]
fn fetch_arm_with_torso_round_trips_at_least_99_percent() {
    let robot = common::fetch_fixed();
    let successes = round_trips(&robot, "arm", 1000, 7);
    println!("fetch arm (torso + 7 DoF): {successes}/1000");
    assert!(successes >= 990, "only {successes}/1000 IK round trips succeeded");
}

/// Local solves (no restarts, from a nearby seed) of targets whose solution has the torso at its
/// lower limit: the step must not keep pushing the torso down, where clamping throws the step
/// away and the solver stalls short of the tolerance.
#[test]
fn local_solves_converge_with_a_coordinate_at_its_limit() {
    let robot = common::fetch_fixed();
    let group = robot.group("arm").expect("group exists").clone();
    let link = robot.end_effector().expect("an end effector");
    let torso = robot.coordinate_index("torso_lift_joint").expect("a torso");
    let lower = robot.coordinates()[torso].lower;
    let config = IkConfig {
        restarts: 0,
        position_tolerance: 1e-4,
        orientation_tolerance: 1e-3,
        ..IkConfig::new()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let neutral = robot.neutral_configuration();
    let mut goal = neutral.clone();
    let mut successes = 0;
    for _ in 0..200 {
        robot.sample_uniform(&group, &neutral, &mut rng, &mut goal);
        goal[torso] = lower;
        // The seed: the goal with every arm joint moved by up to 0.1 rad, the torso at its limit.
        let mut start = goal.clone();
        for &index in &group.coordinates {
            start[index] += rng.random_range(-0.1..=0.1);
        }
        start[torso] = lower;
        let target = robot.link_pose(&goal, link);
        if solve_ik(
            &IkGoal { robot: &robot, group: &group, link, target: &target, seed: &start },
            &config,
            &mut rng,
            &mut |_| true,
        )
        .is_ok()
        {
            successes += 1;
        }
    }
    println!("local solves at the torso's limit: {successes}/200");
    assert!(successes >= 190, "only {successes}/200 local solves converged");
}

#[test]
fn fetch_seven_dof_arm_round_trips_at_least_99_percent() {
    let robot = common::fetch_fixed()
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
        .expect("group of arm joints");
    let successes = round_trips(&robot, "arm7", 300, 11);
    println!("fetch arm (7 DoF): {successes}/300");
    assert!(successes >= 297, "only {successes}/300 IK round trips succeeded");
}

#[test]
fn yumi_arm_round_trips_at_least_99_percent() {
    let robot = common::yumi_fixed();
    let successes = round_trips(&robot, "arm", 300, 3);
    println!("yumi arm: {successes}/300");
    assert!(successes >= 297, "only {successes}/300 IK round trips succeeded");
}

#[test]
fn floating_gripper_ik_over_the_base_is_exact() {
    let robot = common::load("two_finger_gripper.urdf", Mount::Floating);
    let group = robot.group("base").expect("floating mount has a base group").clone();
    let link = robot.link_id("l_finger_link").expect("finger link");
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let neutral = robot.neutral_configuration();
    let mut goal = neutral.clone();
    for _ in 0..50 {
        robot.sample_uniform(&group, &neutral, &mut rng, &mut goal);
        let target = robot.link_pose(&goal, link);
        let solution = solve_ik(
            &IkGoal { robot: &robot, group: &group, link, target: &target, seed: &neutral },
            &IkConfig::new(),
            &mut rng,
            &mut |_| true,
        )
        .expect("exact solution");
        let (position, orientation) = pose_error_norms(&robot.link_pose(&solution, link), &target);
        assert!(position < 1e-12 && orientation < 1e-9, "{position} {orientation}");
    }
}

#[test]
fn acceptance_callback_rejections_lead_to_other_solutions_or_a_clear_error() {
    let robot = common::fetch_fixed();
    let group = robot.group("arm").expect("arm").clone();
    let link = robot.end_effector().expect("gripper");
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let neutral = robot.neutral_configuration();
    let mut goal = neutral.clone();
    robot.sample_uniform(&group, &neutral, &mut rng, &mut goal);
    let target = robot.link_pose(&goal, link);

    // Reject the first two converged solutions: the third is returned and differs from them.
    let mut seen: Vec<Vec<f64>> = Vec::new();
    let solution = solve_ik(
        &IkGoal { robot: &robot, group: &group, link, target: &target, seed: &neutral },
        &IkConfig::new(),
        &mut rng,
        &mut |q| {
            seen.push(q.to_vec());
            seen.len() > 2
        },
    )
    .expect("a third solution");
    assert_eq!(seen.len(), 3);
    assert_eq!(seen[2], solution);

    // Reject everything: NoSolution reports every rejection.
    let mut config = IkConfig::new();
    config.restarts = 4;
    let error = solve_ik(
        &IkGoal { robot: &robot, group: &group, link, target: &target, seed: &neutral },
        &config,
        &mut rng,
        &mut |_| false,
    )
    .unwrap_err();
    match error {
        IkError::NoSolution { attempts, rejected, .. } => {
            assert_eq!(attempts, 5);
            assert!(rejected >= 1);
        }
        other => panic!("unexpected error {other:?}"),
    }
}

#[test]
fn unreachable_target_is_refused_without_iterating() {
    let robot = common::fetch_fixed();
    let group = robot.group("arm").expect("arm").clone();
    let link = robot.end_effector().expect("gripper");
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let target = Pose::translation(5.0, 0.0, 1.0);
    let mut calls = 0;
    let error = solve_ik(
        &IkGoal {
            robot: &robot,
            group: &group,
            link,
            target: &target,
            seed: &robot.neutral_configuration(),
        },
        &IkConfig::new(),
        &mut rng,
        &mut |_| {
            calls += 1;
            true
        },
    )
    .unwrap_err();
    let message = error.to_string();
    assert!(message.contains("beyond the chain's reach"), "{message}");
    match error {
        IkError::OutOfReach { distance, reach, .. } => assert!(distance > reach + 3.0),
        other => panic!("unexpected error {other:?}"),
    }
    assert_eq!(calls, 0);
}

/// Every position the arm reaches (by forward kinematics at random configurations of the group)
/// lies inside the reach ball, and the ball is not much larger than the farthest of them.
#[test]
fn reach_ball_holds_every_reachable_position() {
    let robot = common::fetch_fixed();
    let group = robot.group("arm").expect("arm").clone();
    let link = robot.end_effector().expect("gripper");
    let neutral = robot.neutral_configuration();
    let (centre, radius) = robot.reach_ball(&group, link, &neutral).expect("bounded");
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut q = neutral.clone();
    let mut farthest: f64 = 0.0;
    for _ in 0..5000 {
        robot.sample_uniform(&group, &neutral, &mut rng, &mut q);
        let distance = (robot.link_pose(&q, link).translation.vector - centre).norm();
        assert!(distance <= radius + 1e-9, "{distance} > {radius}");
        farthest = farthest.max(distance);
    }
    assert!(radius < 1.5 * farthest, "a loose ball: {radius} for a reach of {farthest}");
    // A group that moves the mount has no bound.
    let base_robot = common::load("fetch.urdf", lamp_robot::Mount::Planar);
    let all = base_robot.group(lamp_robot::ALL_GROUP).expect("all group");
    assert!(base_robot.reach_ball(all, link, &base_robot.neutral_configuration()).is_none());
}

#[test]
fn malformed_requests_are_errors_not_panics() {
    let robot = common::fetch_fixed();
    let group = robot.group("arm").expect("arm").clone();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let config = IkConfig::new();
    let short_seed = vec![0.0; 3];
    let result = solve_ik(
        &IkGoal {
            robot: &robot,
            group: &group,
            link: 1,
            target: &Pose::identity(),
            seed: &short_seed,
        },
        &config,
        &mut rng,
        &mut |_| true,
    );
    assert!(matches!(result, Err(IkError::InvalidRequest { .. })));
    let seed = robot.neutral_configuration();
    let result = solve_ik(
        &IkGoal { robot: &robot, group: &group, link: 999, target: &Pose::identity(), seed: &seed },
        &config,
        &mut rng,
        &mut |_| true,
    );
    assert!(matches!(result, Err(IkError::InvalidRequest { .. })));
}
