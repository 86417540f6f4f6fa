//! A gripper without fingers comes straight to contact before it takes hold: the Packing magnet
//! over a can, tilted, already touching, and too far away.

mod support;

use lamp_world::{CONTACT_GAP, MAX_CONTACT_APPROACH, MotionConfig, contact_approach};
use nalgebra::{Translation3, UnitQuaternion, Vector3};

#[test]
fn a_magnet_comes_straight_down_to_within_a_millimetre_of_the_can() {
    let (mut scene, gripper, can, q, _) = support::gripper_over_can();
    assert!(scene.holds_by_contact(gripper), "the magnet has no fingers");
    let before = scene.gripper_gap(gripper, can).expect("a gap");
    assert!((before - 0.009).abs() < 1e-3, "its face 9 mm above the can: {before}");
    let start_pose = scene.gripper_pose(gripper, &q).expect("a gripper");

    let states = contact_approach(&scene, gripper, can, &MotionConfig::default()).expect("reached");
    assert_eq!(states[0], q, "from where the gripper is");
    assert!(states.len() > 2, "densified at the checking resolution: {}", states.len());
    for state in &states {
        assert!(scene.is_valid(gripper, state), "the approach touches nothing on the way");
        let pose = scene.gripper_pose(gripper, state).expect("a gripper");
        let moved = pose.translation.vector - start_pose.translation.vector;
        assert!(moved.x.abs() < 1e-6 && moved.y.abs() < 1e-6, "straight down: {moved}");
        assert!(pose.rotation.angle_to(&start_pose.rotation) < 1e-6, "without turning");
    }
    scene.set_configuration(gripper, states.last().expect("states"));
    let after = scene.gripper_gap(gripper, can).expect("a gap");
    assert!(after > 0.0 && after <= CONTACT_GAP, "within a millimetre, apart: {after}");

    // Already there: nothing to move.
    let again = contact_approach(&scene, gripper, can, &MotionConfig::default()).expect("there");
    assert_eq!(again.len(), 1);
    scene.grab(gripper, can).expect("the magnet takes the can it touches");
}

#[test]
fn a_tilted_magnet_comes_to_the_can_along_the_nearest_points() {
    let (mut scene, gripper, can, mut q, _) = support::gripper_over_can();
    let robot = scene.robots()[gripper].robot().clone();
    let tilt = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.2);
    let grasp = scene.body_pose(can)
        * Translation3::new(0.0, 0.01, 0.22)
        * UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0)
        * tilt;
    robot.mount().write_coordinates(&grasp, &mut q);
    scene.set_configuration(gripper, &q);
    let states = contact_approach(&scene, gripper, can, &MotionConfig::default()).expect("reached");
    scene.set_configuration(gripper, states.last().expect("states"));
    let gap = scene.gripper_gap(gripper, can).expect("a gap");
    assert!(gap > 0.0 && gap <= CONTACT_GAP, "{gap}");
}

#[test]
fn a_magnet_touching_or_far_from_the_can_is_refused_by_name() {
    let (mut scene, gripper, can, q, _) = support::gripper_over_can();
    let robot = scene.robots()[gripper].robot().clone();
    let can_pose = scene.body_pose(can);
    let at_height = |height: f64| {
        let mut moved = q.clone();
        let pose = can_pose
            * Translation3::new(0.0, 0.0, height)
            * UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
        robot.mount().write_coordinates(&pose, &mut moved);
        moved
    };
    // The magnet's box is 0.1117 m tall, centred on its link: its face touches the 0.15 m can
    // with the link 0.2058 m above the can's origin.
    let far = at_height(0.2059 + MAX_CONTACT_APPROACH + 0.005);
    scene.set_configuration(gripper, &far);
    let message = contact_approach(&scene, gripper, can, &MotionConfig::default())
        .expect_err("too far")
        .to_string();
    assert!(message.contains("cannot bring its gripper to `can1`"), "{message}");
    assert!(message.contains("more than the 30 mm"), "{message}");

    let inside = at_height(0.2);
    scene.set_configuration(gripper, &inside);
    let message = contact_approach(&scene, gripper, can, &MotionConfig::default())
        .expect_err("touching")
        .to_string();
    assert!(message.contains("already touches"), "{message}");
}
