//! Geometric Jacobians against central finite differences of forward kinematics.

mod common;

use lamp_robot::{Mount, Robot};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const STEP: f64 = 1e-6;
const TOLERANCE: f64 = 1e-6;

/// A URDF exercising every joint type lamp supports, including planar and floating joints.
const ALL_JOINTS: &str = r#"<robot name="all_joints">
  <link name="root"/><link name="slider"/><link name="plane"/><link name="free"/><link name="spin"/><link name="tip"/>
  <joint name="p" type="prismatic"><parent link="root"/><child link="slider"/><origin xyz="0.1 0 0.2" rpy="0.1 0.2 0.3"/><axis xyz="1 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="pl" type="planar"><parent link="slider"/><child link="plane"/><origin xyz="0 0.3 0" rpy="0.4 0 0"/><axis xyz="0 0 1"/></joint>
  <joint name="f" type="floating"><parent link="plane"/><child link="free"/><origin xyz="0.2 0 0" rpy="0 0.5 0"/></joint>
  <joint name="c" type="continuous"><parent link="free"/><child link="spin"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/></joint>
  <joint name="t" type="fixed"><parent link="spin"/><child link="tip"/><origin xyz="0.25 0.05 0"/></joint>
</robot>"#;

fn check(robot: &Robot, link_name: &str, seed: u64) {
    let link = robot.link_id(link_name).expect("link exists");
    let group = robot.group("all").expect("all").clone();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let neutral = robot.neutral_configuration();
    let mut q = neutral.clone();
    for _ in 0..10 {
        robot.sample_uniform(&group, &neutral, &mut rng, &mut q);
        let jacobian = robot.jacobian(&q, link);
        for column in 0..robot.dof() {
            let mut step = vec![0.0; robot.dof()];
            step[column] = STEP;
            let mut plus = q.clone();
            robot.integrate(&mut plus, &step);
            step[column] = -STEP;
            let mut minus = q.clone();
            robot.integrate(&mut minus, &step);
            let (pose_plus, pose_minus) =
                (robot.link_pose(&plus, link), robot.link_pose(&minus, link));
            let linear =
                (pose_plus.translation.vector - pose_minus.translation.vector) / (2.0 * STEP);
            let angular =
                (pose_plus.rotation * pose_minus.rotation.inverse()).scaled_axis() / (2.0 * STEP);
            for row in 0..3 {
                let (expected_linear, expected_angular) = (linear[row], angular[row]);
                assert!(
                    (jacobian[(row, column)] - expected_linear).abs() < TOLERANCE
                        && (jacobian[(row + 3, column)] - expected_angular).abs() < TOLERANCE,
                    "{} column {} ({}) row {row}: analytic ({}, {}) vs finite difference ({expected_linear}, {expected_angular})",
                    robot.name(),
                    column,
                    robot.coordinate_names()[column],
                    jacobian[(row, column)],
                    jacobian[(row + 3, column)],
                );
            }
        }
    }
}

#[test]
fn fetch_on_a_planar_base_matches_finite_differences() {
    check(&common::load("fetch.urdf", Mount::Planar), "gripper_link", 1);
    check(&common::load("fetch.urdf", Mount::Planar), "l_gripper_finger_link", 2);
}

#[test]
fn yumi_matches_finite_differences() {
    check(&common::yumi_fixed(), "gripper_l_base", 3);
}

#[test]
fn floating_mount_matches_finite_differences() {
    check(&common::load("two_finger_gripper.urdf", Mount::Floating), "r_finger_link", 4);
}

#[test]
fn planar_floating_and_continuous_urdf_joints_match_finite_differences() {
    let robot = Robot::from_urdf_str(ALL_JOINTS, None, Mount::Floating).expect("valid URDF");
    assert_eq!(robot.dof(), 6 + 1 + 3 + 6 + 1);
    check(&robot, "tip", 5);
}
