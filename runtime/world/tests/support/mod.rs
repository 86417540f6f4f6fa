//! Loading the bundled specs from disk for the world's tests.

#![allow(dead_code, clippy::unwrap_used)]

pub use lamp_test_support::domain;

/// A pose from a translation and roll, pitch, yaw (radians).
pub fn pose(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> lamp_geometry::Pose {
    lamp_geometry::Pose::from_parts(
        nalgebra::Translation3::new(x, y, z),
        nalgebra::UnitQuaternion::from_euler_angles(roll, pitch, yaw),
    )
}

/// The Packing problem's scene with the gripper pointing down over `can1` at the grasp height
/// (its box's lower face 9 mm above the can's top): the scene, the gripper's index, the can's
/// index, the configuration and the grasp (gripper pose in the can's frame).
pub fn gripper_over_can() -> (lamp_world::Scene, usize, usize, Vec<f64>, lamp_geometry::Pose) {
    let (spec, world) = domain("packing");
    let mut scene = world.problem_scene(&spec.problems[0]).unwrap();
    let gripper = scene.robot_index("gripper").unwrap();
    let robot = scene.robots()[gripper].robot().clone();
    let can = scene.body_index("can1").unwrap();
    let grasp = pose(0.0, 0.0, 0.215, std::f64::consts::PI, 0.0, 0.0);
    let mut q = scene.robots()[gripper].configuration().to_vec();
    robot.mount().write_coordinates(&(scene.body_pose(can) * grasp), &mut q);
    scene.set_configuration(gripper, &q);
    (scene, gripper, can, q, grasp)
}
