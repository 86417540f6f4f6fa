//! The channels a controller executes: a synthetic Café trajectory (the Fetch drives, reaches,
//! grasps, carries and releases), timed as a solution is, written and read back.

use lamp_trajectory::{
    BASE_TRAJECTORY_TOPIC, BagGripperCommand, BagJointTrajectory, GRIPPER_COMMAND_TOPIC,
    JOINT_TRAJECTORY_TOPIC, RobotState, Step, Trajectory, read_standard_channels,
};
use lamp_world::{execution_channels, motion_segments, standard_channels, time_steps};

/// The Fetch's start configuration moved by `fraction` of a fixed displacement of the base, the
/// torso and three arm joints.
fn configuration(start: &[f64], names: &[String], fraction: f64) -> Vec<f64> {
    let mut q = start.to_vec();
    let moves = [
        ("base_x", 0.3),
        ("base_yaw", 0.4),
        ("torso_lift_joint", 0.05),
        ("shoulder_pan_joint", -0.5),
        ("elbow_flex_joint", 0.3),
        ("wrist_roll_joint", 1.0),
    ];
    for (name, change) in moves {
        let index = names.iter().position(|n| n == name).expect("a Fetch coordinate");
        q[index] += fraction * change;
    }
    q
}

struct Fixture {
    trajectory: Trajectory,
    bytes: Vec<u8>,
    robot: std::sync::Arc<lamp_robot::Robot>,
    can: usize,
    world: lamp_world::SpecWorld,
}

/// Drive and reach in 20 steps, grasp, carry back in 15, release, move on in 10.
fn fixture() -> Fixture {
    fixture_with(0)
}

/// [`fixture`], with `fingers` steps after the grasp in which the fingers close onto the can
/// (to 4 cm) and as many before the release in which they open again, as the solver records
/// them.
fn fixture_with(fingers: usize) -> Fixture {
    let (spec, world) = lamp_test_support::domain("cafe");
    let scene = world.problem_scene(&spec.problems[0]).expect("the scene loads");
    let header = lamp_world::trajectory_header(&spec, &scene, 1);
    let state = &scene.robots()[0];
    let robot = state.robot().clone();
    let names = robot.coordinate_names().to_vec();
    let start = state.configuration().to_vec();
    let can = scene.bodies().iter().position(|body| body.type_name == "can").expect("a can");
    let mut poses: Vec<_> = (0..scene.bodies().len()).map(|body| scene.body_pose(body)).collect();
    // The can (0.2 m tall, its frame at its bottom) stands centred between the open fingers
    // where the reach ends, upright in the gripper's frame.
    let gripper = robot.end_effector().expect("a gripper link");
    let reached = robot.link_pose(&configuration(&start, &names, 1.0), gripper);
    poses[can] = reached * nalgebra::Translation3::new(0.0, 0.0, -0.1);
    let finger_joints = ["l_gripper_finger_joint", "r_gripper_finger_joint"]
        .map(|name| names.iter().position(|n| n == name).expect("a finger"));
    let step_with = |fraction: f64, held: Option<usize>, finger: f64| {
        let mut positions = configuration(&start, &names, fraction);
        for joint in finger_joints {
            positions[joint] = finger;
        }
        Step {
            time_nanoseconds: 0,
            body_poses: poses.clone(),
            robots: vec![RobotState { positions, held: vec![held] }],
        }
    };
    let (open, closed) = (start[finger_joints[0]], 0.04);
    let gripped = if fingers > 0 { closed } else { open };
    let step = |fraction: f64, held: Option<usize>| step_with(fraction, held, open);
    let finger = |k: usize| (k as f64 / fingers as f64) * (closed - open);
    let mut steps: Vec<Step> = (0..=20).map(|k| step(k as f64 / 20.0, None)).collect();
    steps.push(step(1.0, Some(can)));
    steps.extend((1..=fingers).map(|k| step_with(1.0, Some(can), open + finger(k))));
    steps.extend((1..=15).map(|k| step_with(1.0 - k as f64 / 30.0, Some(can), gripped)));
    steps.extend((1..=fingers).map(|k| step_with(0.5, Some(can), closed - finger(k))));
    steps.extend((0..=10).map(|k| step(0.5 - k as f64 / 20.0, None)));
    time_steps(&mut steps, &[robot.as_ref()]).expect("the steps are timed");
    let trajectory = Trajectory { header, steps };
    let (mut channels, mut values) = standard_channels(&world, &trajectory).expect("channels");
    execution_channels(&world, &trajectory, &mut channels, &mut values).expect("channels");
    let bytes = trajectory.to_bytes_with(&channels, &values).expect("the file is written");
    Fixture { trajectory, bytes, robot, can, world }
}

/// Checks that `messages` hold one trajectory per segment in which `coordinates` move, at the
/// segment's first stamp, one point per step with the recorded positions, times from the start
/// that increase and end when the segment ends, and velocities within the limits, zero at the
/// ends.
fn check_trajectories(
    fixture: &Fixture,
    messages: &[BagJointTrajectory],
    coordinates: &[&str],
    expected: &[(usize, usize)],
) -> usize {
    let steps = &fixture.trajectory.steps;
    let robot = &fixture.robot;
    let indices: Vec<usize> =
        coordinates.iter().map(|name| robot.coordinate_index(name).expect("known")).collect();
    let segments = motion_segments(steps);
    assert_eq!(segments, expected);
    assert_eq!(messages.len(), segments.len(), "one trajectory per motion");
    for ((first, last), message) in segments.iter().zip(messages) {
        assert_eq!(message.log_time, steps[*first].time_nanoseconds);
        assert_eq!(message.stamp_nanoseconds, 0, "start when received");
        assert_eq!(message.joint_names, coordinates);
        assert_eq!(message.points.len(), last - first + 1);
        for (point, step) in message.points.iter().zip(&steps[*first..=*last]) {
            let positions: Vec<f64> =
                indices.iter().map(|c| step.robots[0].positions[*c]).collect();
            assert_eq!(point.positions, positions);
            let since = step.time_nanoseconds - steps[*first].time_nanoseconds;
            assert_eq!(point.time_from_start_nanoseconds, since);
            for (velocity, c) in point.velocities.iter().zip(&indices) {
                let limit = robot.coordinates()[*c].velocity;
                assert!(velocity.abs() <= limit * (1.0 + 1e-9), "{velocity} over {limit}");
            }
        }
        let times: Vec<u64> =
            message.points.iter().map(|point| point.time_from_start_nanoseconds).collect();
        assert!(times.windows(2).all(|pair| pair[0] < pair[1]), "{times:?}");
        for end in [&message.points[0], message.points.last().expect("points")] {
            assert!(end.velocities.iter().all(|v| *v == 0.0), "at rest at both ends");
        }
        let moving = message.points.iter().flat_map(|point| &point.velocities);
        assert!(moving.into_iter().any(|v| v.abs() > 0.01), "the joints move");
    }
    messages.len()
}

/// The Fetch's URDF joints but the fingers.
const ARM: [&str; 8] = [
    "torso_lift_joint",
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "upperarm_roll_joint",
    "elbow_flex_joint",
    "forearm_roll_joint",
    "wrist_flex_joint",
    "wrist_roll_joint",
];

#[test]
fn every_motion_is_a_joint_trajectory_and_every_grasp_change_a_gripper_command() {
    let fixture = fixture();
    let recording =
        read_standard_channels(fixture.bytes.as_slice(), "execution.mcap", &[]).expect("reads");
    let segments = [(0, 20), (21, 36), (37, 47)];
    let trajectories = &recording.joint_trajectories;
    check_trajectories(&fixture, &trajectories[JOINT_TRAJECTORY_TOPIC], &ARM, &segments);
    let base = ["base_x", "base_y", "base_yaw"];
    check_trajectories(&fixture, &trajectories[BASE_TRAJECTORY_TOPIC], &base, &segments);

    // A grasp at the stamp of the step before the object is held, the fingers closed onto the
    // can; a release at the step before it is let go, fingers open (the Fetch's fingers: 0 to
    // 0.05 m).
    let steps = &fixture.trajectory.steps;
    let commands = &recording.gripper_commands[GRIPPER_COMMAND_TOPIC];
    assert_eq!(commands.len(), 2, "{commands:?}");
    let grasp = commands[0].position;
    let expected = [
        BagGripperCommand {
            log_time: steps[20].time_nanoseconds,
            position: grasp,
            max_effort: 0.0,
        },
        BagGripperCommand { log_time: steps[36].time_nanoseconds, position: 0.05, max_effort: 0.0 },
    ];
    assert_eq!(commands.as_slice(), expected);
    // There the left finger touches the can: its gap to the can is nothing, 1 mm wider it is
    // 1 mm, and 1 mm further in the finger would cut into the can.
    let robot = &fixture.robot;
    let finger = robot.link_id("l_gripper_finger_link").expect("the left finger");
    let joint = robot.coordinate_index("l_gripper_finger_joint").expect("its joint");
    let parts: Vec<_> = robot
        .collision_geometry()
        .iter()
        .filter(|geometry| geometry.link == finger)
        .map(|geometry| (geometry.origin, geometry.shape.clone()))
        .collect();
    let finger_shape = lamp_geometry::CollisionShape::compound(&parts).expect("a shape");
    let can_shape =
        lamp_geometry::CollisionShape::compound(&fixture.world.type_parts["can"]).expect("a shape");
    let can_pose = steps[21].body_poses[fixture.can];
    let finger_at = |position: f64| {
        let mut q = steps[20].robots[0].positions.clone();
        q[joint] = position;
        robot.link_pose(&q, finger)
    };
    let gap = lamp_geometry::distance(&finger_shape, &finger_at(grasp), &can_shape, &can_pose);
    assert!(gap.abs() < 1e-6, "the finger at {grasp} m is {gap} m from the can");
    let wider = finger_at(grasp + 0.001);
    let gap = lamp_geometry::distance(&finger_shape, &wider, &can_shape, &can_pose);
    assert!((gap - 0.001).abs() < 1e-6, "1 mm wider, the finger is {gap} m from the can");
    let deeper = finger_at(grasp - 0.001);
    assert!(lamp_geometry::intersects(&finger_shape, &deeper, &can_shape, &can_pose));
    assert!(grasp > 0.03 && grasp < 0.05, "a 9 cm can between 11 cm fingers: {grasp}");
    assert_eq!(steps[21].time_nanoseconds - steps[20].time_nanoseconds, 500_000_000);
}

/// The fingers close after the grasp and open before the release, within the motions around
/// them: the arm's trajectory holds still meanwhile, the grasp's command comes where the closing
/// starts (the step before the grasp) and the release's where the opening starts, with the
/// position the fingers open to.
#[test]
fn fingers_that_close_and_open_stay_within_the_motions_and_their_commands() {
    let fixture = fixture_with(10);
    let recording =
        read_standard_channels(fixture.bytes.as_slice(), "execution.mcap", &[]).expect("reads");
    let segments = [(0, 20), (21, 56), (57, 67)];
    let trajectories = &recording.joint_trajectories;
    check_trajectories(&fixture, &trajectories[JOINT_TRAJECTORY_TOPIC], &ARM, &segments);
    let base = ["base_x", "base_y", "base_yaw"];
    check_trajectories(&fixture, &trajectories[BASE_TRAJECTORY_TOPIC], &base, &segments);
    let steps = &fixture.trajectory.steps;
    let fingers = fixture.robot.coordinate_index("l_gripper_finger_joint").expect("a finger");
    assert_eq!(steps[31].robots[0].positions[fingers], 0.04, "closed onto the can");
    assert_eq!(steps[46].robots[0].positions[fingers], 0.04, "closed until the opening");
    assert_eq!(steps[56].robots[0].positions[fingers], 0.05, "open before the release");
    let commands = &recording.gripper_commands[GRIPPER_COMMAND_TOPIC];
    let times: Vec<u64> = commands.iter().map(|command| command.log_time).collect();
    assert_eq!(times, [steps[20].time_nanoseconds, steps[46].time_nanoseconds]);
    assert_eq!(commands[1].position, 0.05);
    assert!(commands[0].position > 0.03 && commands[0].position < 0.05);
    // The fingers (0.05 m/s) take their time: 1 cm closes in more than 0.2 s.
    assert!(steps[31].time_nanoseconds - steps[21].time_nanoseconds > 200_000_000);
}

#[test]
fn the_same_trajectory_gives_the_same_bytes() {
    assert_eq!(fixture().bytes, fixture().bytes);
}

#[test]
fn steps_that_do_not_match_the_header_are_refused_not_a_panic() {
    let fixture = fixture();
    let world = &fixture.world;
    let mut trajectory = fixture.trajectory.clone();
    let (mut channels, mut values) = standard_channels(world, &trajectory).expect("channels");
    trajectory.steps[30].robots.clear();
    let error = execution_channels(world, &trajectory, &mut channels, &mut values).unwrap_err();
    assert!(error.to_string().contains("step 30"), "{error}");
    trajectory.steps[30] = fixture.trajectory.steps[30].clone();
    trajectory.steps[30].robots[0].positions.pop();
    let error = execution_channels(world, &trajectory, &mut channels, &mut values).unwrap_err();
    assert!(error.to_string().contains("coordinates"), "{error}");
}
