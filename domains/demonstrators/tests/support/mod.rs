//! Loading the bundled specs from disk for the demonstrators' tests and benches.

#![allow(dead_code)]

pub use lamp_test_support::domain;

use lamp_trajectory::Trajectory;
use lamp_world::{Scene, SpecWorld};

/// Replays a recording in a scene rebuilt from its first step: grabs and releases where the
/// held flag changes; every state must be valid (the held can may touch only its gripper) and
/// bodies must be where the file says.
pub fn replay(world: &SpecWorld, trajectory: &Trajectory) {
    let header = &trajectory.header;
    let first = &trajectory.steps[0];
    let mut scene = Scene::new();
    for (body, pose) in header.bodies.iter().zip(&first.body_poses) {
        let template = world.body(&body.name, &body.type_name).expect("a declared type");
        scene.add_body(template, *pose).expect("unique names");
    }
    assert_eq!(header.robots.len(), 1);
    assert_eq!(header.robots[0].grippers, vec!["gripper".to_string()]);
    let robot = world
        .add_robot(&mut scene, &header.robots[0].name, first.robots[0].positions.clone())
        .expect("the spec's robot");
    let mut held = None;
    for (index, step) in trajectory.steps.iter().enumerate() {
        let state = &step.robots[0];
        scene.set_configuration(robot, &state.positions);
        if state.held[0] != held {
            match state.held[0] {
                Some(body) => scene.grab(robot, body).expect("a movable body"),
                None => assert!(scene.release_at_rest(robot).expect("it rests").is_some()),
            }
            held = state.held[0];
        }
        assert!(
            scene.is_valid(robot, &state.positions),
            "step {index}: {:?}",
            scene.first_contact(robot, &state.positions)
        );
        for (body, pose) in step.body_poses.iter().enumerate() {
            let error = (scene.body_pose(body).translation.vector - pose.translation.vector).norm();
            assert!(error < 1e-6, "step {index}: body {body} is {error} m off");
        }
        assert_eq!(step.time_nanoseconds, index as u64 * 10_000_000);
    }
}
