//! The fingers close onto what the gripper holds and open again before it lets go: a Fetch in
//! the Café scene holding a can centred between its open fingers, and the Packing magnet.

mod support;

use lamp_geometry::{CollisionShape, distance};
use lamp_world::{FingerMove, MotionConfig, Scene, finger_path, grasp_position};
use nalgebra::Translation3;

/// The Café scene with the can `can` standing centred between the Fetch's open fingers where the
/// robot starts, held; the scene, the robot's index and the can's.
fn fetch_holding_can() -> (Scene, usize, usize, lamp_world::SpecWorld) {
    let (spec, world) = support::domain("cafe");
    let mut scene = world.problem_scene(&spec.problems[0]).expect("the scene loads");
    let fetch = 0;
    let can = scene.bodies().iter().position(|body| body.type_name == "can").expect("a can");
    let q = scene.robots()[fetch].configuration().to_vec();
    let gripper = scene.gripper_pose(fetch, &q).expect("a gripper");
    // The can is 0.2 m tall with its frame at its bottom: held at mid-height.
    scene.set_body_pose(can, gripper * Translation3::new(0.0, 0.0, -0.1));
    scene.grab(fetch, can).expect("the can is grabbed");
    assert_eq!(scene.first_contact(fetch, &q), None, "the held can touches nothing else");
    (scene, fetch, can, world)
}

/// The collision shape of link `link`.
fn link_shape(robot: &lamp_robot::Robot, link: &str) -> CollisionShape {
    let id = robot.link_id(link).expect("the link");
    let parts: Vec<_> = robot
        .collision_geometry()
        .iter()
        .filter(|geometry| geometry.link == id)
        .map(|geometry| (geometry.origin, geometry.shape.clone()))
        .collect();
    CollisionShape::compound(&parts).expect("a shape")
}

#[test]
fn fingers_close_onto_the_held_object_and_open_back() {
    let (mut scene, fetch, can, world) = fetch_holding_can();
    let config = MotionConfig::default();
    let robot = scene.robots()[fetch].robot().clone();
    let open = scene.robots()[fetch].configuration().to_vec();
    let can_pose = scene.body_pose(can);
    let can_shape = CollisionShape::compound(&world.type_parts["can"]).expect("a shape");

    let closing =
        finger_path(&scene, fetch, FingerMove::Close, &config).expect("the fingers close");
    assert_eq!(closing[0], open, "from where the fingers are");
    assert!(closing.len() > 2, "densified at the checking resolution: {}", closing.len());
    let closed = closing.last().expect("states").clone();
    let fingers = [
        ("l_gripper_finger_joint", "l_gripper_finger_link"),
        ("r_gripper_finger_joint", "r_gripper_finger_link"),
    ];
    let finger_indices: Vec<usize> =
        fingers.iter().map(|(joint, _)| robot.coordinate_index(joint).expect("a finger")).collect();
    for (index, value) in closed.iter().enumerate() {
        if !finger_indices.contains(&index) {
            assert_eq!(*value, open[index], "only the fingers move (coordinate {index})");
        }
    }
    for ((_, link), &finger) in fingers.iter().zip(&finger_indices) {
        let stop = grasp_position(&robot, finger, &open, &can_shape, &can_pose).expect("known");
        assert!(stop.touches, "the finger touches the can");
        let target = stop.position;
        assert!((closed[finger] - target).abs() < 1e-6, "{} not at {target}", closed[finger]);
        assert!(target < open[finger] - 0.005, "the finger closes: {target} from {}", open[finger]);
        let pose = robot.link_pose(&closed, robot.link_id(link).expect("the link"));
        let gap = distance(&link_shape(&robot, link), &pose, &can_shape, &can_pose);
        assert!(gap.abs() < 1e-6, "`{link}` is {gap} m from the can");
    }
    for q in &closing {
        assert_eq!(scene.first_contact(fetch, q), None, "touching only what it holds");
        for pair in closing.windows(2) {
            let step = (0..q.len()).map(|c| (pair[1][c] - pair[0][c]).abs()).fold(0.0, f64::max);
            assert!(step <= config.linear_resolution + 1e-12);
        }
    }
    scene.set_configuration(fetch, &closed);
    assert_eq!(scene.body_pose(can), can_pose, "the can does not move");

    let opening = finger_path(&scene, fetch, FingerMove::Open, &config).expect("the fingers open");
    assert_eq!(opening[0], closed);
    assert_eq!(opening.last(), Some(&open), "back to the open values");
    scene.set_configuration(fetch, &open);
    assert_eq!(scene.body_pose(can), can_pose, "the can does not move");
}

#[test]
fn fingers_that_would_touch_something_else_are_refused() {
    let (mut scene, fetch, _, _) = fetch_holding_can();
    let config = MotionConfig::default();
    let closing =
        finger_path(&scene, fetch, FingerMove::Close, &config).expect("the fingers close");
    scene.set_configuration(fetch, closing.last().expect("states"));
    // Another can just outside the left finger's open pad.
    let other = scene
        .bodies()
        .iter()
        .enumerate()
        .filter(|(_, body)| body.type_name == "can")
        .map(|(index, _)| index)
        .nth(1)
        .expect("a second can");
    let robot = scene.robots()[fetch].robot().clone();
    let finger = robot.link_id("l_gripper_finger_link").expect("the left finger");
    let q = scene.robots()[fetch].configuration().to_vec();
    let pad = robot.link_pose(&q, finger);
    // The pad moves along the gripper's y axis: the other can (4.5 cm in radius), upright, stands
    // as close outside the closed finger as it can without touching it, at the most 1 mm more.
    let gripper = scene.gripper_pose(fetch, &q).expect("a gripper");
    let out = (pad.translation.vector - gripper.translation.vector).normalize();
    let mut pose = scene.body_pose(other);
    pose.rotation = gripper.rotation;
    let clear = (0..150).map(|k| 0.045 + 0.001 * k as f64).find(|side| {
        pose.translation.vector =
            gripper.translation.vector + out * (side + 0.045) - nalgebra::Vector3::z() * 0.1;
        scene.set_body_pose(other, pose);
        scene.first_contact(fetch, &q).is_none()
    });
    assert!(clear.is_some_and(|side| side < 0.08), "{clear:?}");
    let error = finger_path(&scene, fetch, FingerMove::Open, &config).expect_err("refused");
    let message = error.to_string();
    assert!(message.contains("cannot open its fingers"), "{message}");
    assert!(message.contains("touches `can"), "{message}");
}

#[test]
fn a_grasp_whose_fingers_close_past_the_object_is_refused() {
    let (mut scene, fetch, can, world) = fetch_holding_can();
    let q = scene.robots()[fetch].configuration().to_vec();
    let gripper = scene.gripper_pose(fetch, &q).expect("a gripper");
    // The can held by the gripper but wholly beyond its fingertips, along its approach axis: the
    // fingers would close on air, and a robot could not carry the can so.
    scene.release(fetch).expect("released");
    let robot = scene.robots()[fetch].robot().clone();
    let finger = robot.coordinates().iter().position(|c| c.name == "l_gripper_finger_joint");
    let finger = finger.expect("the left finger joint");
    let beyond = gripper * Translation3::new(0.25, 0.0, -0.1);
    scene.set_body_pose(can, beyond);
    scene.grab(fetch, can).expect("the can is grabbed");
    let can_shape = CollisionShape::compound(&world.type_parts["can"]).expect("a shape");
    let stop = grasp_position(&robot, finger, &q, &can_shape, &beyond).expect("a finger");
    assert!(!stop.touches, "the finger meets no can");
    assert_eq!(stop.position, robot.coordinates()[finger].lower, "closed to its limit");
    let error = finger_path(&scene, fetch, FingerMove::Close, &MotionConfig::default())
        .expect_err("refused");
    let message = error.to_string();
    assert!(message.contains("cannot close its fingers"), "{message}");
    assert!(message.contains("closes past `can"), "{message}");
}

#[test]
fn a_gripper_without_fingers_moves_nothing() {
    let (mut scene, gripper, can, q, _) = support::gripper_over_can();
    scene.grab(gripper, can).expect("grabbed");
    for movement in [FingerMove::Close, FingerMove::Open] {
        let states = finger_path(&scene, gripper, movement, &MotionConfig::default()).expect("ok");
        assert_eq!(states, std::slice::from_ref(&q));
    }
}
