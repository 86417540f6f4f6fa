//! Forward kinematics of the shipped arms against hand-derived values and an independent
//! homogeneous-matrix evaluation of the URDF chain.

mod common;

use std::f64::consts::FRAC_PI_2;

use approx::assert_relative_eq;
use lamp_robot::{Mount, Pose};
use nalgebra::{Matrix4, Vector3};

/// Tolerance for poses computed two ways in double precision (metres, or unit-vector components).
const POSE_TOLERANCE: f64 = 1e-9;

// Public Fetch offsets along the arm (fetch.urdf comments).
const TORSO_X: f64 = -0.086875;
const TORSO_Z: f64 = 0.37743;
const PAN_X: f64 = 0.119525;
const PAN_Z: f64 = 0.34858;
const LIFT_X: f64 = 0.117;
const LIFT_Z: f64 = 0.06;
/// From the shoulder-lift axis to the gripper frame along the stretched arm.
const LIFT_TO_GRIPPER: f64 = 0.219 + 0.133 + 0.197 + 0.1245 + 0.1385 + 0.16645;

fn fetch_q(robot: &lamp_robot::Robot, values: &[(&str, f64)]) -> Vec<f64> {
    let mut q = robot.neutral_configuration();
    robot.apply_named_configuration(values.iter().copied(), &mut q).expect("joint names exist");
    q
}

#[test]
fn fetch_gripper_at_zero_is_the_sum_of_offsets() {
    let robot = common::fetch_fixed();
    let gripper = robot.link_id("gripper_link").expect("gripper_link");
    let pose = robot.link_pose(&robot.neutral_configuration(), gripper);
    let expected =
        Vector3::new(TORSO_X + PAN_X + LIFT_X + LIFT_TO_GRIPPER, 0.0, TORSO_Z + PAN_Z + LIFT_Z);
    assert_relative_eq!(pose.translation.vector, expected, epsilon = POSE_TOLERANCE);
    assert_relative_eq!(pose.rotation.angle(), 0.0, epsilon = POSE_TOLERANCE);
}

#[test]
fn fetch_single_joint_motions_match_hand_derivation() {
    let robot = common::fetch_fixed();
    let gripper = robot.link_id("gripper_link").expect("gripper_link");

    // Torso lift raises everything by the joint value.
    let q = fetch_q(&robot, &[("torso_lift_joint", 0.3)]);
    let pose = robot.link_pose(&q, gripper);
    assert_relative_eq!(
        pose.translation.z,
        TORSO_Z + PAN_Z + LIFT_Z + 0.3,
        epsilon = POSE_TOLERANCE
    );

    // Shoulder pan by +90°: the arm beyond the pan axis points along +y.
    let q = fetch_q(&robot, &[("shoulder_pan_joint", FRAC_PI_2)]);
    let pose = robot.link_pose(&q, gripper);
    let expected =
        Vector3::new(TORSO_X + PAN_X, LIFT_X + LIFT_TO_GRIPPER, TORSO_Z + PAN_Z + LIFT_Z);
    assert_relative_eq!(pose.translation.vector, expected, epsilon = POSE_TOLERANCE);
    assert_relative_eq!(pose.rotation * Vector3::x(), Vector3::y(), epsilon = POSE_TOLERANCE);

    // Shoulder lift by θ about +y tilts the arm down: x → (cos θ, 0, −sin θ).
    let theta = 0.7;
    let q = fetch_q(&robot, &[("shoulder_lift_joint", theta)]);
    let pose = robot.link_pose(&q, gripper);
    let lift = Vector3::new(TORSO_X + PAN_X + LIFT_X, 0.0, TORSO_Z + PAN_Z + LIFT_Z);
    let expected = lift + LIFT_TO_GRIPPER * Vector3::new(theta.cos(), 0.0, -theta.sin());
    assert_relative_eq!(pose.translation.vector, expected, epsilon = POSE_TOLERANCE);

    // Elbow flex by −90°: the forearm points straight up from the elbow.
    let q = fetch_q(&robot, &[("elbow_flex_joint", -FRAC_PI_2)]);
    let pose = robot.link_pose(&q, gripper);
    let elbow_x = TORSO_X + PAN_X + LIFT_X + 0.219 + 0.133;
    let expected =
        Vector3::new(elbow_x, 0.0, TORSO_Z + PAN_Z + LIFT_Z + 0.197 + 0.1245 + 0.1385 + 0.16645);
    assert_relative_eq!(pose.translation.vector, expected, epsilon = POSE_TOLERANCE);

    // Rolls about the arm axis leave the stretched arm's gripper position unchanged but turn it.
    let q = fetch_q(
        &robot,
        &[("wrist_roll_joint", 1.0), ("forearm_roll_joint", -0.5), ("upperarm_roll_joint", 0.25)],
    );
    let pose = robot.link_pose(&q, gripper);
    let expected =
        Vector3::new(TORSO_X + PAN_X + LIFT_X + LIFT_TO_GRIPPER, 0.0, TORSO_Z + PAN_Z + LIFT_Z);
    assert_relative_eq!(pose.translation.vector, expected, epsilon = POSE_TOLERANCE);
    assert_relative_eq!(
        pose.rotation.scaled_axis(),
        Vector3::new(0.75, 0.0, 0.0),
        epsilon = POSE_TOLERANCE
    );

    // Fingers slide along ±y of the gripper by the joint value plus the 4 mm closed gap.
    let q = fetch_q(&robot, &[("l_gripper_finger_joint", 0.03), ("r_gripper_finger_joint", 0.02)]);
    let gripper_pose = robot.link_pose(&q, gripper);
    let left = robot.link_pose(&q, robot.link_id("l_gripper_finger_link").expect("left finger"));
    let right = robot.link_pose(&q, robot.link_id("r_gripper_finger_link").expect("right finger"));
    assert_relative_eq!(
        (gripper_pose.inverse() * left).translation.vector,
        Vector3::new(0.0, 0.034, 0.0),
        epsilon = POSE_TOLERANCE
    );
    assert_relative_eq!(
        (gripper_pose.inverse() * right).translation.vector,
        Vector3::new(0.0, -0.024, 0.0),
        epsilon = POSE_TOLERANCE
    );
}

#[test]
fn planar_mount_moves_and_turns_the_whole_robot() {
    let robot = common::load("fetch.urdf", Mount::Planar);
    let fixed = common::fetch_fixed();
    assert_eq!(robot.dof(), fixed.dof() + 3);
    assert_eq!(&robot.coordinate_names()[..3], ["base_x", "base_y", "base_yaw"]);
    let gripper = robot.link_id("gripper_link").expect("gripper_link");
    let mut q = robot.neutral_configuration();
    q[0] = 1.0;
    q[1] = -2.0;
    q[2] = FRAC_PI_2;
    let pose = robot.link_pose(&q, gripper);
    let reach = TORSO_X + PAN_X + LIFT_X + LIFT_TO_GRIPPER;
    assert_relative_eq!(
        pose.translation.vector,
        Vector3::new(1.0, -2.0 + reach, TORSO_Z + PAN_Z + LIFT_Z),
        epsilon = POSE_TOLERANCE
    );
}

#[test]
fn fixed_mount_pose_is_applied_to_the_root() {
    let mount = Pose::translation(-0.46, 0.0, -0.08);
    let robot = common::load("yumi.urdf", Mount::Fixed(mount));
    let reference = common::yumi_fixed();
    let q = robot.neutral_configuration();
    for link in 0..robot.link_count() {
        let expected = mount * reference.link_pose(&q, link);
        assert_relative_eq!(
            robot.link_pose(&q, link).to_homogeneous(),
            expected.to_homogeneous(),
            epsilon = POSE_TOLERANCE
        );
    }
}

/// URDF rpy as an explicit matrix Rz(yaw)·Ry(pitch)·Rx(roll), written out independently.
fn rpy_matrix(xyz: [f64; 3], rpy: [f64; 3]) -> Matrix4<f64> {
    let (sr, cr) = rpy[0].sin_cos();
    let (sp, cp) = rpy[1].sin_cos();
    let (sy, cy) = rpy[2].sin_cos();
    Matrix4::new(
        cy * cp,
        cy * sp * sr - sy * cr,
        cy * sp * cr + sy * sr,
        xyz[0],
        sy * cp,
        sy * sp * sr + cy * cr,
        sy * sp * cr - cy * sr,
        xyz[1],
        -sp,
        cp * sr,
        cp * cr,
        xyz[2],
        0.0,
        0.0,
        0.0,
        1.0,
    )
}

fn rot_z(angle: f64) -> Matrix4<f64> {
    rpy_matrix([0.0; 3], [0.0, 0.0, angle])
}

#[test]
fn yumi_chain_matches_an_independent_matrix_product() {
    let robot = common::yumi_fixed();
    let half_pi = std::f64::consts::FRAC_PI_2;
    // (xyz, rpy) of the seven arm joints in chain order, then the fixed flange → gripper_l_base.
    let chain: [([f64; 3], [f64; 3], &str); 7] = [
        ([0.05355, 0.0725, 0.41492], [0.9781, -0.5716, 2.3180], "yumi_joint_1_l"),
        ([0.03, 0.0, 0.1], [half_pi, 0.0, 0.0], "yumi_joint_2_l"),
        ([-0.03, 0.17283, 0.0], [-half_pi, 0.0, 0.0], "yumi_joint_7_l"),
        ([-0.04188, 0.0, 0.07873], [half_pi, -half_pi, 0.0], "yumi_joint_3_l"),
        ([0.0405, 0.16461, 0.0], [-half_pi, 0.0, 0.0], "yumi_joint_4_l"),
        ([-0.027, 0.0, 0.10039], [half_pi, 0.0, 0.0], "yumi_joint_5_l"),
        ([0.027, 0.029, 0.0], [-half_pi, 0.0, 0.0], "yumi_joint_6_l"),
    ];
    let gripper = robot.link_id("gripper_l_base").expect("gripper_l_base");
    assert_eq!(robot.end_effector(), Some(gripper));
    let configurations: [[f64; 7]; 4] = [
        [0.0; 7],
        [0.3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.4, -0.9, 1.1, -0.5, 2.0, 0.6, -1.5],
    ];
    for values in configurations {
        let mut q = robot.neutral_configuration();
        let mut expected = Matrix4::identity();
        // half_pi-rounded values in the file differ from exact π/2 by < 1e-11: well inside tolerance.
        for ((xyz, rpy, name), value) in chain.iter().zip(values) {
            robot.apply_named_configuration([(*name, value)], &mut q).expect("joint exists");
            expected = expected * rpy_matrix(*xyz, *rpy) * rot_z(value);
        }
        expected *= rpy_matrix([0.0, 0.0, 0.007], [0.0, 0.0, std::f64::consts::PI]);
        let actual = robot.link_pose(&q, gripper).to_homogeneous();
        assert_relative_eq!(actual, expected, epsilon = 1e-8);
    }
}

#[test]
fn forward_kinematics_agrees_with_link_pose_for_every_link() {
    let robot = common::load("fetch.urdf", Mount::Planar);
    let mut q = robot.neutral_configuration();
    for (index, value) in q.iter_mut().enumerate() {
        *value = 0.1 * (index as f64) - 0.3;
    }
    robot.clamp(&mut q);
    let mut poses = vec![Pose::identity(); robot.link_count()];
    robot.forward_kinematics(&q, &mut poses);
    for (link, pose) in poses.iter().enumerate() {
        assert_relative_eq!(
            pose.to_homogeneous(),
            robot.link_pose(&q, link).to_homogeneous(),
            epsilon = POSE_TOLERANCE
        );
    }
}

#[test]
fn joint_transforms_compose_to_the_link_poses_and_fixed_joints_ignore_the_configuration() {
    let robot = common::fetch_fixed();
    let q = fetch_q(&robot, &[("torso_lift_joint", 0.2), ("shoulder_pan_joint", 0.7)]);
    let neutral = robot.neutral_configuration();
    assert_eq!(robot.joint_transform(&q, 0), None);
    assert!(!robot.has_fixed_joint(0));
    for link in 1..robot.link_count() {
        let parent = robot.parent_link(link).expect("a non-root link has a parent");
        let local = robot.joint_transform(&q, link).expect("a non-root link has a joint");
        let composed = robot.link_pose(&q, parent) * local;
        let direct = robot.link_pose(&q, link);
        assert_relative_eq!(
            composed.to_homogeneous(),
            direct.to_homogeneous(),
            epsilon = POSE_TOLERANCE
        );
        if robot.has_fixed_joint(link) {
            assert_eq!(Some(local), robot.joint_transform(&neutral, link));
        }
    }
    let torso = robot.link_id("torso_lift_link").expect("torso_lift_link");
    assert!(!robot.has_fixed_joint(torso));
    assert!((1..robot.link_count()).any(|link| robot.has_fixed_joint(link)));
}
