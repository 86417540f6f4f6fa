//! Configuration space: layout, groups, named configurations, wrap-aware distance and interpolation,
//! rotation slerp, sampling and limits.

mod common;

use std::f64::consts::PI;

use approx::assert_relative_eq;
use lamp_geometry::{Rotation, Vec3};
use lamp_robot::{
    ALL_GROUP, CoordinateKind, DEFAULT_ACCELERATION, DEFAULT_JOINT_VELOCITY,
    MOUNT_ANGULAR_VELOCITY, MOUNT_LINEAR_VELOCITY, Mount, wrap_angle,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const TOLERANCE: f64 = 1e-12;

#[test]
fn fetch_layout_and_groups() {
    let robot = common::load("fetch.urdf", Mount::Planar);
    let expected = [
        "base_x",
        "base_y",
        "base_yaw",
        "torso_lift_joint",
        "shoulder_pan_joint",
        "shoulder_lift_joint",
        "upperarm_roll_joint",
        "elbow_flex_joint",
        "forearm_roll_joint",
        "wrist_flex_joint",
        "wrist_roll_joint",
        "l_gripper_finger_joint",
        "r_gripper_finger_joint",
    ];
    assert_eq!(robot.coordinate_names(), expected);
    assert_eq!(robot.group("base").expect("base").coordinates, [0, 1, 2]);
    assert_eq!(robot.group("arm").expect("arm").coordinates, [3, 4, 5, 6, 7, 8, 9, 10]);
    assert_eq!(robot.group("gripper").expect("gripper").coordinates, [11, 12]);
    assert_eq!(robot.end_effector(), robot.link_id("gripper_link"));
    let fixed = common::fetch_fixed();
    assert!(fixed.group("base").is_none(), "a fixed mount has no base group");
    let custom = fixed
        .with_group("hand", &["r_gripper_finger_joint", "l_gripper_finger_joint"])
        .expect("group");
    assert_eq!(custom.group("hand").expect("hand").coordinates, [8, 9]);
    assert!(
        custom.clone().with_group("arm", &["torso_lift_joint"]).is_err(),
        "built-in groups are reserved"
    );
    assert!(custom.with_group("bad", &["no_such_joint"]).is_err());
}

#[test]
fn named_configuration_sets_joints_and_rejects_unknown_names() {
    let robot = common::fetch_fixed();
    let tuck = [
        ("torso_lift_joint", 0.0),
        ("shoulder_pan_joint", 1.32),
        ("shoulder_lift_joint", 1.40),
        ("upperarm_roll_joint", -0.20),
        ("elbow_flex_joint", 1.72),
        ("forearm_roll_joint", 0.0),
        ("wrist_flex_joint", 1.66),
        ("wrist_roll_joint", 0.0),
    ];
    let mut q = robot.neutral_configuration();
    robot.apply_named_configuration(tuck, &mut q).expect("tuck joints exist");
    assert_eq!(&q[..8], [0.0, 1.32, 1.40, -0.20, 1.72, 0.0, 1.66, 0.0]);
    assert!(robot.within_limits(&q));
    assert!(robot.apply_named_configuration([("elbow", 1.0)], &mut q).is_err());
}

#[test]
fn yaw_interpolates_across_pi_not_through_zero() {
    let robot = common::load("magnetic_gripper.urdf", Mount::Planar);
    let a = [0.0, 0.0, 3.0];
    let b = [0.0, 0.0, -3.0];
    let mut middle = [0.0; 3];
    robot.interpolate(&a, &b, 0.5, &mut middle);
    assert_relative_eq!(wrap_angle(middle[2] - PI), 0.0, epsilon = TOLERANCE);
    assert_relative_eq!(robot.distance(&a, &b), 2.0 * PI - 6.0, epsilon = TOLERANCE);
    robot.interpolate(&a, &b, 0.25, &mut middle);
    assert_relative_eq!(middle[2], 3.0 + 0.25 * (2.0 * PI - 6.0), epsilon = TOLERANCE);
    robot.interpolate(&a, &b, 1.0, &mut middle);
    assert_relative_eq!(middle[2], -3.0, epsilon = 1e-9);
    // Translation is plain Euclidean.
    assert_relative_eq!(
        robot.distance(&[0.0, 0.0, 0.0], &[3.0, 4.0, 0.0]),
        5.0,
        epsilon = TOLERANCE
    );
}

#[test]
fn continuous_joints_wrap_and_bounded_joints_do_not() {
    let robot = common::fetch_fixed();
    let roll = robot.coordinate_index("upperarm_roll_joint").expect("continuous joint");
    let elbow = robot.coordinate_index("elbow_flex_joint").expect("revolute joint");
    let mut a = robot.neutral_configuration();
    let mut b = a.clone();
    a[roll] = PI - 0.1;
    b[roll] = -PI + 0.1;
    assert_relative_eq!(robot.distance(&a, &b), 0.2, epsilon = 1e-12);
    a[roll] = 0.0;
    b[roll] = 0.0;
    a[elbow] = -2.0;
    b[elbow] = 2.0;
    assert_relative_eq!(robot.distance(&a, &b), 4.0, epsilon = 1e-12);
    let mut middle = a.clone();
    robot.interpolate(&a, &b, 0.5, &mut middle);
    assert_relative_eq!(middle[elbow], 0.0, epsilon = 1e-12);
}

#[test]
fn floating_rotation_interpolates_by_slerp_without_wrap_problems() {
    let robot = common::load("magnetic_gripper.urdf", Mount::Floating);
    let gripper = robot.link_id("gripper_link").expect("gripper_link");
    // Two rotations about z at ±(π − 0.1): as rotation vectors they point in opposite directions,
    // but they are only 0.2 rad apart.
    let a = [0.0, 0.0, 0.0, 0.0, 0.0, PI - 0.1];
    let b = [1.0, 0.0, 0.0, 0.0, 0.0, -(PI - 0.1)];
    assert_relative_eq!(robot.distance(&a, &b), (1.0f64 + 0.04).sqrt(), epsilon = 1e-9);
    let mut middle = [0.0; 6];
    robot.interpolate(&a, &b, 0.5, &mut middle);
    let rotation = robot.link_pose(&middle, gripper).rotation;
    assert_relative_eq!(
        rotation.angle_to(&Rotation::from_axis_angle(&Vec3::z_axis(), PI)),
        0.0,
        epsilon = 1e-9
    );
    assert_relative_eq!(middle[0], 0.5, epsilon = TOLERANCE);
    // Every interpolated rotation lies on the geodesic: angles from a grow linearly.
    let (ra, rb) = (robot.link_pose(&a, gripper).rotation, robot.link_pose(&b, gripper).rotation);
    for step in 0..=10 {
        let t = f64::from(step) / 10.0;
        robot.interpolate(&a, &b, t, &mut middle);
        let r = robot.link_pose(&middle, gripper).rotation;
        assert_relative_eq!(ra.angle_to(&r), t * ra.angle_to(&rb), epsilon = 1e-9);
        assert!(
            Vec3::new(middle[3], middle[4], middle[5]).norm() <= PI + 1e-12,
            "rotation vector stays canonical"
        );
    }
    // A general pair: slerp midpoint is equidistant from both ends.
    let c = [0.0, 0.0, 0.0, 2.0, -1.0, 0.5];
    let d = [0.0, 0.0, 0.0, -1.0, 0.3, 2.2];
    robot.interpolate(&c, &d, 0.5, &mut middle);
    let (rc, rd, rm) = (
        robot.link_pose(&c, gripper).rotation,
        robot.link_pose(&d, gripper).rotation,
        robot.link_pose(&middle, gripper).rotation,
    );
    assert_relative_eq!(rc.angle_to(&rm), rd.angle_to(&rm), epsilon = 1e-9);
    assert_relative_eq!(rc.angle_to(&rm) * 2.0, rc.angle_to(&rd), epsilon = 1e-9);
}

#[test]
fn sampling_respects_limits_groups_and_is_deterministic() {
    let robot = common::load("fetch.urdf", Mount::Planar)
        .with_coordinate_limits("base_x", -1.0, 3.0)
        .expect("base_x exists");
    let arm = robot.group("arm").expect("arm").clone();
    let all = robot.group("all").expect("all").clone();
    let mut reference = robot.neutral_configuration();
    reference[0] = 0.5;
    reference[11] = 0.02;
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let mut q = reference.clone();
    let mut minimum = vec![f64::INFINITY; robot.dof()];
    let mut maximum = vec![f64::NEG_INFINITY; robot.dof()];
    for _ in 0..2000 {
        robot.sample_uniform(&arm, &reference, &mut rng, &mut q);
        assert!(robot.within_limits(&q));
        for index in 0..robot.dof() {
            if !arm.coordinates.contains(&index) {
                assert_eq!(
                    q[index], reference[index],
                    "coordinate {index} outside the group changed"
                );
            }
        }
        robot.sample_uniform(&all, &reference, &mut rng, &mut q);
        assert!(robot.within_limits(&q));
        for index in 0..robot.dof() {
            minimum[index] = minimum[index].min(q[index]);
            maximum[index] = maximum[index].max(q[index]);
        }
    }
    // Samples cover the limits: base_x in [-1, 3], shoulder pan close to ±1.6056, yaw the full circle.
    assert!(minimum[0] >= -1.0 && minimum[0] < -0.9 && maximum[0] <= 3.0 && maximum[0] > 2.9);
    assert!(minimum[4] < -1.55 && maximum[4] > 1.55);
    assert!(minimum[2] < -3.0 && maximum[2] > 3.0);
    // Unbounded base_y samples stay within the documented half width around the reference.
    assert!(
        minimum[1] >= -lamp_robot::UNBOUNDED_SAMPLE_HALF_WIDTH
            && maximum[1] <= lamp_robot::UNBOUNDED_SAMPLE_HALF_WIDTH
    );

    let mut first = reference.clone();
    let mut second = reference.clone();
    robot.sample_uniform(&all, &reference, &mut ChaCha8Rng::seed_from_u64(3), &mut first);
    robot.sample_uniform(&all, &reference, &mut ChaCha8Rng::seed_from_u64(3), &mut second);
    assert_eq!(first, second);
}

#[test]
fn clamp_and_limits() {
    let robot = common::load("fetch.urdf", Mount::Planar);
    let mut q = robot.neutral_configuration();
    q[2] = 4.0; // yaw
    q[3] = 1.0; // torso beyond 0.38615
    q[4] = -3.0; // shoulder pan below -1.6056
    assert!(!robot.within_limits(&q));
    // The yaw wraps, so the torso is the first coordinate outside its limits.
    assert_eq!(robot.first_outside_limits(&q), Some(3));
    robot.clamp(&mut q);
    assert_eq!(robot.first_outside_limits(&q), None);
    assert!(robot.within_limits(&q));
    assert_relative_eq!(q[2], 4.0 - 2.0 * PI, epsilon = TOLERANCE);
    assert_relative_eq!(q[3], 0.38615, epsilon = TOLERANCE);
    assert_relative_eq!(q[4], -1.6056, epsilon = TOLERANCE);
    q[5] = f64::NAN;
    assert!(!robot.within_limits(&q));
    assert_eq!(robot.first_outside_limits(&q), Some(5));
    assert!(
        !robot.within_limits(&q[..4]),
        "a configuration of the wrong length is not within limits"
    );
    assert!(robot.clone().with_coordinate_limits("base_x", 1.0, -1.0).is_err());
    assert!(robot.with_coordinate_limits("nope", 0.0, 1.0).is_err());
}

#[test]
fn uniform_rotation_sampling_covers_so3_evenly() {
    // The mean of R·e_z over uniform rotations is 0 and its z component is uniform on [-1, 1].
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let samples = 20_000;
    let mut mean = Vec3::zeros();
    let mut below = 0;
    for _ in 0..samples {
        let direction = lamp_robot::uniform_rotation(&mut rng) * Vec3::z();
        mean += direction;
        if direction.z < -0.5 {
            below += 1;
        }
    }
    mean /= f64::from(samples);
    assert!(mean.norm() < 0.02, "mean direction {mean:?}");
    let fraction = f64::from(below) / f64::from(samples);
    assert!((fraction - 0.25).abs() < 0.015, "P(z < -0.5) = {fraction}");
}

#[test]
fn velocity_limits_come_from_the_urdf_and_the_mount_from_documented_defaults() {
    let robot = common::load("fetch.urdf", Mount::Planar);
    let limit = |name: &str| {
        let coordinate = &robot.coordinates()[robot.coordinate_index(name).expect(name)];
        (coordinate.velocity, coordinate.acceleration)
    };
    // fetch.urdf: torso 0.1 m/s, upper-arm roll 1.571 rad/s, wrist roll 2.268 rad/s.
    assert_eq!(limit("torso_lift_joint"), (0.1, DEFAULT_ACCELERATION));
    assert_eq!(limit("upperarm_roll_joint"), (1.571, DEFAULT_ACCELERATION));
    assert_eq!(limit("wrist_roll_joint"), (2.268, DEFAULT_ACCELERATION));
    assert_eq!(limit("base_x"), (MOUNT_LINEAR_VELOCITY, DEFAULT_ACCELERATION));
    assert_eq!(limit("base_yaw"), (MOUNT_ANGULAR_VELOCITY, DEFAULT_ACCELERATION));
    let gripper = common::load("magnetic_gripper.urdf", Mount::Floating);
    let velocities: Vec<f64> = gripper.coordinates().iter().map(|c| c.velocity).collect();
    assert_eq!(velocities[..3], [MOUNT_LINEAR_VELOCITY; 3]);
    assert_eq!(velocities[3..], [MOUNT_ANGULAR_VELOCITY; 3]);
    // A joint whose <limit> gives no speed (urdf-rs reads it as 0) moves at the default.
    let unlimited = r#"<robot name="r"><link name="a"/><link name="b"/>
        <joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint></robot>"#;
    let robot = lamp_robot::Robot::from_urdf_str(unlimited, None, Mount::Fixed(Default::default()))
        .expect("loads");
    assert_eq!(robot.coordinates()[0].velocity, DEFAULT_JOINT_VELOCITY);
}

#[test]
fn displacements_take_the_short_way_and_unwrapping_keeps_the_configuration() {
    let robot = common::load("fetch.urdf", Mount::Planar);
    let roll = robot.coordinate_index("upperarm_roll_joint").expect("continuous joint");
    let yaw = robot.coordinate_index("base_yaw").expect("planar yaw");
    let mut a = robot.neutral_configuration();
    a[roll] = PI - 0.1;
    a[yaw] = -PI + 0.05;
    let mut b = a.clone();
    b[roll] = -PI + 0.1;
    b[yaw] = PI - 0.05;
    let mut moved = vec![0.0; a.len()];
    robot.displacement(&a, &b, &mut moved);
    assert_relative_eq!(moved[roll], 0.2, epsilon = TOLERANCE);
    assert_relative_eq!(moved[yaw], -0.1, epsilon = TOLERANCE);
    // Unwrapped next to a, b is a + the short way: no 2π jump, the same link poses.
    let mut unwrapped = b.clone();
    robot.unwrap_towards(&a, &mut unwrapped);
    assert_relative_eq!(unwrapped[roll], PI + 0.1, epsilon = TOLERANCE);
    assert_relative_eq!(unwrapped[yaw], -PI - 0.05, epsilon = TOLERANCE);
    for link in 0..robot.link_count() {
        let (wrapped, turned) = (robot.link_pose(&b, link), robot.link_pose(&unwrapped, link));
        assert!((wrapped.translation.vector - turned.translation.vector).norm() < 1e-12);
        assert!(wrapped.rotation.angle_to(&turned.rotation) < 1e-12);
    }
    // A free-flying rotation's displacement is its geodesic turn, about world axes.
    let gripper = common::load("magnetic_gripper.urdf", Mount::Floating);
    let c = [0.0, 0.0, 0.0, 0.0, 0.0, PI - 0.1];
    let d = [0.0, 0.0, 0.0, 0.0, 0.0, -(PI - 0.1)];
    let mut turn = [0.0; 6];
    gripper.displacement(&c, &d, &mut turn);
    assert_relative_eq!(turn[5], 0.2, epsilon = 1e-9);
    assert_relative_eq!(Vec3::new(turn[3], turn[4], turn[5]).norm(), 0.2, epsilon = 1e-9);
}

#[test]
fn nearest_form_picks_the_node_a_scan_of_distances_picks() {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    for robot in [
        common::load("magnetic_gripper.urdf", Mount::Floating),
        common::load("fetch.urdf", Mount::Planar),
    ] {
        let group = robot.group(ALL_GROUP).expect("every robot has the all group");
        let reference = vec![0.0; robot.dof()];
        let mut q = reference.clone();
        let mut nodes = Vec::new();
        for _ in 0..300 {
            robot.sample_uniform(group, &reference, &mut rng, &mut q);
            nodes.push(q.clone());
        }
        // Ties and near ties: repeated nodes, and nodes a hair from others in one coordinate
        // (a rotation's included), where only the exact arithmetic tells them apart.
        for index in [3, 50, 200] {
            nodes.push(nodes[index].clone());
            for coordinate in 0..robot.dof() {
                let mut nudged = nodes[index].clone();
                nudged[coordinate] += 1e-12;
                nodes.push(nudged);
            }
        }
        let forms: Vec<Vec<f64>> = nodes.iter().map(|node| robot.distance_form(node)).collect();
        assert!(forms.iter().all(|form| form.len() == robot.distance_form_len()));
        for trial in 0..400 {
            // Every fourth query is a node, the near ties first.
            let query = if trial % 4 == 0 {
                nodes[nodes.len() - 1 - trial / 4].clone()
            } else {
                robot.sample_uniform(group, &reference, &mut rng, &mut q);
                q.clone()
            };
            let mut scan = (0, f64::INFINITY);
            for (index, node) in nodes.iter().enumerate() {
                let distance = robot.distance(node, &query);
                if distance < scan.1 {
                    scan = (index, distance);
                }
            }
            let nearest = robot.nearest_form(&forms, &robot.distance_form(&query));
            assert_eq!(nearest, scan.0, "{} at trial {trial}", robot.name());
        }
    }
}

#[test]
fn nearest_form_tells_apart_rotations_a_hair_apart() {
    let robot = common::load("magnetic_gripper.urdf", Mount::Floating);
    let rotation = robot
        .coordinates()
        .iter()
        .position(|coordinate| coordinate.kind == CoordinateKind::Rotation(0))
        .expect("a floating mount has a rotation");
    let query = vec![0.0; robot.dof()];
    // Each rung turns a relative 1e-8 less than the one before, so each is strictly nearer the
    // query than any listed before it, and only by a little of its rotation term. The turns are
    // small, where a lower bound on a rotation's angle is at its tightest.
    let nodes: Vec<Vec<f64>> = (0..5)
        .map(|rung| {
            let mut node = query.clone();
            let scale = 1.0 - 1e-8 * f64::from(rung);
            node[rotation..rotation + 3].copy_from_slice(&[
                0.007 * scale,
                -0.004 * scale,
                0.011 * scale,
            ]);
            node
        })
        .collect();
    let forms: Vec<Vec<f64>> = nodes.iter().map(|node| robot.distance_form(node)).collect();
    let distances: Vec<f64> = nodes.iter().map(|node| robot.distance(node, &query)).collect();
    assert!(distances.windows(2).all(|pair| pair[1] < pair[0]), "{distances:?}");
    assert_eq!(robot.nearest_form(&forms, &robot.distance_form(&query)), nodes.len() - 1);
}
