//! The adapter: demonstration files become the learner's demonstrations, checked against the spec.

mod support;

use std::collections::BTreeMap;

use lamp_abstraction::{Pose, Role};
use lamp_build::{Adapter, BuildError, DemoFile};
use lamp_trajectory::{
    BodyDescription, RobotDescription, RobotState, Step, Trajectory, TrajectoryError,
    TrajectoryHeader,
};
use nalgebra::{Translation3, UnitQuaternion, Vector3};

use support::fixture;

fn packing_adapter() -> Adapter {
    let (spec, world) = support::packing();
    Adapter::new(&spec, &world.robots).expect("the packing adapter")
}

/// One hand-written Packing file: the gripper at a pose holding `held`, a can, a box and the table.
fn packing_file(edit: impl FnOnce(&mut TrajectoryHeader, &mut Step)) -> DemoFile {
    let gripper = fixture::packing_gripper();
    let mut header = TrajectoryHeader {
        domain: "packing".into(),
        seed: 0,
        provenance: BTreeMap::new(),
        bodies: vec![
            BodyDescription { name: "table1".into(), type_name: "table".into() },
            BodyDescription { name: "can1".into(), type_name: "can".into() },
            BodyDescription { name: "box1".into(), type_name: "surface".into() },
        ],
        robots: vec![RobotDescription {
            name: "gripper".into(),
            coordinates: gripper.coordinate_names().to_vec(),
            grippers: vec!["gripper".into()],
        }],
    };
    let mut q = gripper.neutral_configuration();
    gripper.mount().write_coordinates(&gripper_pose(), &mut q);
    let mut step = Step {
        time_nanoseconds: 0,
        body_poses: vec![
            Pose::identity(),
            Pose::translation(0.1, 0.0, 0.001),
            Pose::translation(0.3, 0.2, 0.0),
        ],
        robots: vec![RobotState { positions: q, held: vec![Some(1)] }],
    };
    edit(&mut header, &mut step);
    let bytes = Trajectory { header, steps: vec![step] }.to_bytes().expect("encodes");
    DemoFile { name: "hand/written.mcap".into(), bytes }
}

fn gripper_pose() -> Pose {
    Pose::from_parts(
        Translation3::new(0.1, 0.0, 0.211),
        UnitQuaternion::from_euler_angles(0.3, -0.2, 2.5),
    )
}

#[test]
fn participants_roles_and_held_pairs_follow_the_spec() {
    let demonstration = packing_adapter().demonstration(&packing_file(|_, _| {})).expect("adapts");
    let participants: Vec<(&str, &str, Role)> = demonstration
        .participants
        .iter()
        .map(|p| (p.name.as_str(), p.type_name.as_str(), p.role))
        .collect();
    assert_eq!(
        participants,
        [
            ("gripper_gripper", "gripper", Role::RobotPart { gripper: true }),
            ("can1", "can", Role::Object { movable: true }),
            ("box1", "surface", Role::Object { movable: false }),
        ],
        "robot parts first, then bodies in file order; the static world table is left out"
    );
    assert_eq!(demonstration.id, "hand/written.mcap");
    let step = &demonstration.steps[0];
    assert_eq!(step.held, [(0, 1)], "body 1 of the file (can1) is participant 1");
    assert!((step.poses[0].translation.vector - gripper_pose().translation.vector).norm() < 1e-12);
    assert!(step.poses[0].rotation.angle_to(&gripper_pose().rotation) < 1e-9);
    assert_eq!(step.poses[1], Pose::translation(0.1, 0.0, 0.001));
    assert_eq!(step.poses[2], Pose::translation(0.3, 0.2, 0.0));
}

#[test]
fn fixture_files_reproduce_the_synthetic_demonstrations() {
    let adapter = packing_adapter();
    let synthetic = lamp_learn::synthetic::packing_demonstrations(4, 3);
    let files = support::packing_files(4, 3);
    for (file, original) in files.iter().zip(&synthetic) {
        let adapted = adapter.demonstration(file).expect("adapts");
        assert_eq!(adapted.steps.len(), original.steps.len());
        for (a, b) in adapted.steps.iter().zip(&original.steps) {
            assert_eq!(a.held, b.held);
            let gripper_error =
                (a.poses[0].translation.vector - b.poses[0].translation.vector).norm();
            assert!(
                gripper_error < 1e-12 && a.poses[0].rotation.angle_to(&b.poses[0].rotation) < 1e-9
            );
            assert_eq!(a.poses[1], b.poses[1]);
            // The box frame is turned half a turn (see the fixture's docs).
            let turned = b.poses[2]
                * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI);
            assert!(a.poses[2].rotation.angle_to(&turned.rotation) < 1e-9);
        }
    }
}

#[test]
fn robot_parts_are_posed_by_forward_kinematics_of_their_links() {
    let (spec, world) = support::load(&fixture::workspace_root().join("domains/cafe/cafe.lamp"));
    let adapter = Adapter::new(&spec, &world.robots).expect("the cafe adapter");
    let fetch = &world.robots["fetch"];
    let mut q = fetch.neutral_configuration();
    fetch.mount().write_coordinates(
        &Pose::from_parts(
            Translation3::new(1.0, -2.0, 0.0),
            UnitQuaternion::from_euler_angles(0.0, 0.0, 0.7),
        ),
        &mut q,
    );
    for (index, value) in q.iter_mut().enumerate().skip(3) {
        *value = 0.1 * index as f64;
    }
    let header = TrajectoryHeader {
        domain: "cafe".into(),
        seed: 0,
        provenance: BTreeMap::new(),
        bodies: vec![
            BodyDescription { name: "floor1".into(), type_name: "floor".into() },
            BodyDescription { name: "table1".into(), type_name: "surface".into() },
            BodyDescription { name: "can1".into(), type_name: "can".into() },
        ],
        robots: vec![RobotDescription {
            name: "fetch".into(),
            coordinates: fetch.coordinate_names().to_vec(),
            grippers: vec!["gripper".into()],
        }],
    };
    let step = Step {
        time_nanoseconds: 0,
        body_poses: vec![
            Pose::identity(),
            Pose::translation(2.0, 0.0, 0.6),
            Pose::translation(2.0, 0.0, 0.6),
        ],
        robots: vec![RobotState { positions: q.clone(), held: vec![None] }],
    };
    let bytes = Trajectory { header, steps: vec![step] }.to_bytes().expect("encodes");
    let demonstration =
        adapter.demonstration(&DemoFile { name: "fetch.mcap".into(), bytes }).expect("adapts");
    let names: Vec<&str> = demonstration.participants.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["fetch_base", "fetch_gripper", "table1", "can1"]);
    assert_eq!(demonstration.participants[0].role, Role::RobotPart { gripper: false });
    assert_eq!(demonstration.participants[1].role, Role::RobotPart { gripper: true });
    let poses = &demonstration.steps[0].poses;
    for (participant, link) in [(0, "base_link"), (1, "gripper_link")] {
        let expected = fetch.link_pose(&q, fetch.link_id(link).expect("link"));
        assert!(
            (poses[participant].translation.vector - expected.translation.vector).norm() < 1e-12
        );
        assert!(poses[participant].rotation.angle_to(&expected.rotation) < 1e-12);
    }
    assert!(
        (poses[1].translation.vector - poses[0].translation.vector).norm() > 0.3,
        "the gripper link is not at the base"
    );
}

#[test]
fn a_single_gripper_under_another_name_is_the_spec_gripper() {
    let file = packing_file(|header, _| header.robots[0].grippers = vec!["magnet".into()]);
    let demonstration = packing_adapter().demonstration(&file).expect("adapts");
    assert_eq!(demonstration.steps[0].held, [(0, 1)]);
}

fn error_of(file: DemoFile) -> (BuildError, String) {
    let error = packing_adapter().demonstration(&file).expect_err("must be refused");
    let message = error.to_string();
    assert!(message.contains("hand/written.mcap"), "the file is named: {message}");
    (error, message)
}

fn code(error: &BuildError) -> String {
    miette::Diagnostic::code(error).map(|code| code.to_string()).unwrap_or_default()
}

#[test]
fn a_body_of_an_undeclared_type_is_refused() {
    let (error, message) =
        error_of(packing_file(|header, _| header.bodies[1].type_name = "lid".into()));
    assert_eq!(code(&error), "lamp::build::undeclared_type");
    assert!(message.contains("`can1`") && message.contains("`lid`"), "{message}");
}

#[test]
fn an_undeclared_robot_is_refused() {
    let (error, message) =
        error_of(packing_file(|header, _| header.robots[0].name = "robby".into()));
    assert_eq!(code(&error), "lamp::build::undeclared_robot");
    assert!(message.contains("`robby`"), "{message}");
}

#[test]
fn coordinates_that_differ_from_the_model_are_refused() {
    let (error, message) =
        error_of(packing_file(|header, _| header.robots[0].coordinates.swap(0, 1)));
    assert_eq!(code(&error), "lamp::build::coordinates");
    assert!(message.contains("`gripper`"), "{message}");
}

#[test]
fn an_unknown_gripper_among_several_is_refused() {
    let (error, _) = error_of(packing_file(|header, step| {
        header.robots[0].grippers = vec!["left".into(), "right".into()];
        step.robots[0].held = vec![None, None];
    }));
    assert_eq!(code(&error), "lamp::build::gripper");
}

#[test]
fn holding_the_static_world_is_refused() {
    let (error, message) = error_of(packing_file(|_, step| step.robots[0].held = vec![Some(0)]));
    assert_eq!(code(&error), "lamp::build::held_world");
    assert!(message.contains("step 0") && message.contains("`table1`"), "{message}");
}

#[test]
fn a_truncated_file_is_refused_with_its_name() {
    let mut file = support::packing_files(1, 5).remove(0);
    file.bytes.truncate(file.bytes.len() / 2);
    file.name = "hand/written.mcap".into();
    let (error, _) = error_of(file);
    assert!(
        matches!(error, BuildError::Trajectory(TrajectoryError::Truncated { .. })),
        "{error:?}"
    );
    assert_eq!(code(&error), "lamp::trajectory::truncated");
}

#[test]
fn a_demonstration_of_another_domain_is_refused_naming_both() {
    let (error, message) = error_of(packing_file(|header, _| header.domain = "cafe".into()));
    assert_eq!(code(&error), "lamp::build::other_domain");
    assert!(message.contains("`cafe`") && message.contains("`packing`"), "{message}");
}

#[test]
fn a_demonstration_without_steps_is_refused() {
    let file = packing_file(|_, _| {});
    let mut trajectory = Trajectory::from_bytes(&file.bytes, &file.name).expect("reads back");
    trajectory.steps.clear();
    let bytes = trajectory.to_bytes().expect("encodes");
    let (error, message) = error_of(DemoFile { name: file.name, bytes });
    assert_eq!(code(&error), "lamp::build::empty_demonstration");
    assert!(message.contains("no steps"), "{message}");
}
