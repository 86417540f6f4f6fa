//! Scenes built from the bundled specs: validity, contacts with names, grabbing and releasing.

#![allow(clippy::unwrap_used)] // a failed step is a failed test

mod support;

use std::f64::consts::PI;

use lamp_world::Contact;
use support::{domain, pose};

#[test]
fn packing_problem_scene_is_valid_and_names_contacts() {
    let (spec, world) = domain("packing");
    let scene = world.problem_scene(&spec.problems[0]).unwrap();
    assert!(scene.body_contacts().is_empty(), "{:?}", scene.body_contacts());
    let gripper = scene.robot_index("gripper").unwrap();
    let q = scene.robots()[gripper].configuration().to_vec();
    assert!(scene.is_valid(gripper, &q));

    // Put the gripper into can1: the contact names the link and the can.
    let can = scene.body_index("can1").unwrap();
    let can_pose = scene.body_pose(can);
    let robot = scene.robots()[gripper].robot().clone();
    let mut inside = q.clone();
    robot.mount().write_coordinates(&(can_pose * pose(0.0, 0.0, 0.1, PI, 0.0, 0.0)), &mut inside);
    assert_eq!(
        scene.first_contact(gripper, &inside),
        Some(Contact::LinkBody { link: "gripper_link".into(), body: "can1".into() })
    );
}

#[test]
fn a_held_can_moves_with_the_gripper_and_is_checked() {
    let (mut scene, gripper, can, mut q, grasp_in_can) = support::gripper_over_can();
    let robot = scene.robots()[gripper].robot().clone();
    let can_pose = scene.body_pose(can);
    assert!(scene.is_valid(gripper, &q), "{:?}", scene.first_contact(gripper, &q));
    scene.grab(gripper, can).unwrap();
    assert!(scene.grab(gripper, can).is_err(), "a second grab must be refused");

    // Lift by 10 cm: the can follows rigidly.
    let lifted_pose = pose(0.0, 0.0, 0.1, 0.0, 0.0, 0.0) * can_pose * grasp_in_can;
    robot.mount().write_coordinates(&lifted_pose, &mut q);
    assert!(scene.is_valid(gripper, &q));
    scene.set_configuration(gripper, &q);
    let moved = scene.body_pose(can);
    assert!((moved.translation.vector - can_pose.translation.vector).z - 0.1 < 1e-9);
    assert!(((moved.translation.vector - can_pose.translation.vector).z - 0.1).abs() < 1e-9);

    // Lowering the held can into the table is a held-object contact.
    let sunk = pose(0.0, 0.0, -0.05, 0.0, 0.0, 0.0) * can_pose * grasp_in_can;
    robot.mount().write_coordinates(&sunk, &mut q);
    assert_eq!(
        scene.first_contact(gripper, &q),
        Some(Contact::HeldBody { held: "can1".into(), body: "table1".into() })
    );

    // Release: the can stays where it was put and collides with the gripper again.
    assert_eq!(scene.release(gripper), Some(can));
    assert_eq!(scene.held(gripper), None);
    assert_eq!(scene.body_pose(can), moved);
}

#[test]
fn static_bodies_cannot_be_grabbed() {
    let (spec, world) = domain("packing");
    let mut scene = world.problem_scene(&spec.problems[0]).unwrap();
    let gripper = scene.robot_index("gripper").unwrap();
    let table = scene.body_index("table1").unwrap();
    let error = scene.grab(gripper, table).unwrap_err().to_string();
    assert!(error.contains("static"), "{error}");
}

#[test]
fn fetch_in_the_cafe_detects_table_and_self_collisions() {
    let (spec, world) = domain("cafe");
    let scene = world.problem_scene(&spec.problems[0]).unwrap();
    let fetch = scene.robot_index("fetch").unwrap();
    let q = scene.robots()[fetch].configuration().to_vec();
    assert!(
        scene.is_valid(fetch, &q),
        "tucked at the origin: {:?}",
        scene.first_contact(fetch, &q)
    );

    // Drive the base into table1: its leg (world scenery) or its top.
    let robot = scene.robots()[fetch].robot().clone();
    let table = scene.body_pose(scene.body_index("table1").unwrap());
    let mut into_table = q.clone();
    robot.mount().write_coordinates(
        &pose(table.translation.x, table.translation.y, 0.0, 0.0, 0.0, 0.0),
        &mut into_table,
    );
    match scene.first_contact(fetch, &into_table) {
        Some(Contact::LinkBody { body, .. }) => {
            assert!(body == "table1" || body == "table1_leg", "{body}")
        }
        other => panic!("expected a contact with table1, got {other:?}"),
    }

    // The arm hanging straight down in front of the torso goes through the base, whose
    // cylinder (radius 0.28 m, top at 0.36 m) the shoulder (x ≈ 0.24 m) is above.
    let mut hanging = q.clone();
    let straight = [
        ("torso_lift_joint", 0.2),
        ("shoulder_pan_joint", 0.0),
        ("shoulder_lift_joint", 1.5),
        ("upperarm_roll_joint", 0.0),
        ("elbow_flex_joint", 0.0),
        ("forearm_roll_joint", 0.0),
        ("wrist_flex_joint", 0.0),
    ];
    robot.apply_named_configuration(straight, &mut hanging).unwrap();
    // Alone, without the floor the fingers would reach first.
    let mut alone = lamp_world::Scene::new();
    let fetch = world.add_robot(&mut alone, "fetch", q.clone()).unwrap();
    assert!(alone.is_valid(fetch, &q));
    match alone.first_contact(fetch, &hanging) {
        Some(Contact::SelfCollision { a, .. }) => assert_eq!(a, "base_link"),
        other => panic!("expected the arm to hit the base, got {other:?}"),
    }

    // Out of limits is reported before any geometry.
    let mut beyond = q.clone();
    let torso = robot.coordinate_index("torso_lift_joint").unwrap();
    beyond[torso] = 5.0;
    assert_eq!(scene.first_contact(fetch, &beyond), Some(Contact::OutOfLimits));
}
