//! Learning from ordinary ROS 2 bags: Packing demonstrations written with their standard channels,
//! stripped of `/lamp/world` and the `lamp` metadata so that only `/tf`, `/tf_static`,
//! `/robot_description`, the scene and `/lamp/held` remain, read back through the frame mapping,
//! learn the byte-identical domain; a Café bag whose grasps are only a closing gripper joint reads
//! with the same grasps; bags of scenes with and without a second can read through one mapping,
//! the can absent from the demonstrations of the bags that lack it; and the reader's diagnostics
//! for a frame no bag records, a held object the bag lacks, a jump and time going backwards.

#![allow(clippy::unwrap_used)] // a failed step is a failed test

mod support;

use lamp_build::{
    BagTally, DemoFile, FrameObject, FrameRobot, MappedRobot, Ros2Error, Ros2Mapping,
};
use lamp_demonstrators::{Simulation, file_name, generate_all};
use lamp_trajectory::{Trajectory, WORLD_TOPIC, filter_bag};
use nalgebra::Translation3;

/// Enough demonstrations to learn every relation and action of Packing quickly.
const DEMOS: u32 = 20;

/// The bag without `/lamp/world` (nor the `lamp` metadata, which `filter_bag` does not copy).
fn strip(bytes: &[u8]) -> Vec<u8> {
    filter_bag(bytes, "bag", |topic, time| (topic != WORLD_TOPIC).then_some(time)).unwrap()
}

fn mapping(trajectory: &Trajectory) -> Ros2Mapping {
    Ros2Mapping {
        objects: trajectory
            .header
            .bodies
            .iter()
            .map(|body| FrameObject {
                frame: body.name.clone(),
                name: body.name.clone(),
                type_name: body.type_name.clone(),
            })
            .collect(),
        robot: Some(FrameRobot {
            robot: "gripper".into(),
            base_frame: "gripper_link".into(),
            held_topic: Some("/lamp/held".into()),
            grasp_joint: None,
        }),
    }
}

fn domain_text(artifacts: &lamp_build::Artifacts) -> String {
    support::artifact(artifacts, "domain.pddl").to_string()
}

#[test]
fn packing_learned_from_tf_only_bags_is_the_domain_learned_from_native_files() {
    let (spec, world) = support::packing();
    let mut simulation = Simulation::from_spec(&spec).unwrap();
    simulation.count = DEMOS;
    let demonstrations = generate_all(&world, &simulation, |_| {}).unwrap();
    let robot = MappedRobot {
        model: &world.robots["gripper"],
        gripper: Some("gripper".into()),
        grasp: None,
    };
    let mut native = Vec::new();
    let mut from_bags = Vec::new();
    for demonstration in &demonstrations {
        let trajectory = &demonstration.trajectory;
        let name = file_name("packing", demonstration.index);
        let (channels, values) = lamp_world::standard_channels(&world, trajectory).unwrap();
        let bag = strip(&trajectory.to_bytes_with(&channels, &values).unwrap());
        assert!(Trajectory::from_bytes(&bag, "bag").is_err(), "the bag is no lamp file any more");
        let read =
            lamp_build::ros2_trajectory(&bag, &name, "packing", &mapping(trajectory), Some(&robot))
                .unwrap();
        assert_eq!(read.steps.len(), trajectory.steps.len());
        for (read, original) in read.steps.iter().zip(&trajectory.steps) {
            assert_eq!(read.time_nanoseconds, original.time_nanoseconds);
            assert_eq!(read.body_poses, original.body_poses);
            assert_eq!(read.robots[0].held, original.robots[0].held);
        }
        native.push(DemoFile { name: name.clone(), bytes: trajectory.to_bytes().unwrap() });
        from_bags.push(DemoFile { name, bytes: read.to_bytes().unwrap() });
    }
    let (_, native_artifacts) = lamp_build::build(&spec, "packing.lamp", &world, &native).unwrap();
    let (_, bag_artifacts) = lamp_build::build(&spec, "packing.lamp", &world, &from_bags).unwrap();
    let strip_provenance = |text: String| -> String {
        text.lines().filter(|line| !line.starts_with(';')).collect::<Vec<_>>().join("\n")
    };
    let (native_domain, bag_domain) = (domain_text(&native_artifacts), domain_text(&bag_artifacts));
    assert!(native_domain.contains("(:action"), "{native_domain}");
    assert_eq!(strip_provenance(bag_domain), strip_provenance(native_domain));
}

/// One Packing demonstration as a bag, with its trajectory.
fn one_bag(edit: impl FnOnce(&mut Trajectory)) -> (Trajectory, Vec<u8>) {
    let (spec, world) = support::packing();
    let mut simulation = Simulation::from_spec(&spec).unwrap();
    simulation.count = 1;
    let mut trajectory = generate_all(&world, &simulation, |_| {}).unwrap().remove(0).trajectory;
    edit(&mut trajectory);
    let (channels, values) = lamp_world::standard_channels(&world, &trajectory).unwrap();
    (trajectory.clone(), strip(&trajectory.to_bytes_with(&channels, &values).unwrap()))
}

fn read(bag: &[u8], mapping: &Ros2Mapping) -> Result<Trajectory, Ros2Error> {
    let (_, world) = support::packing();
    let robot = MappedRobot {
        model: &world.robots["gripper"],
        gripper: Some("gripper".into()),
        grasp: None,
    };
    lamp_build::ros2_trajectory(bag, "bag.mcap", "packing", mapping, Some(&robot))
}

/// A mapped object whose frame one bag lacks is absent from that demonstration; when no bag of
/// the source records it, the tally of the source's bags refuses it, naming the frame.
#[test]
fn a_mapped_frame_no_bag_records_is_named() {
    let (trajectory, bag) = one_bag(|_| {});
    let mut mapping = mapping(&trajectory);
    let can = mapping.objects.iter().position(|object| object.name == "can1").unwrap();
    mapping.objects[can].frame = "can_7".into();
    let (_, world) = support::packing();
    let robot = packing_robot(&world);
    let read = lamp_build::ros2_bag(&bag, "bag.mcap", "packing", &mapping, Some(&robot)).unwrap();
    assert_eq!(read.absent, vec![can]);
    let bodies: Vec<&str> =
        read.trajectory.header.bodies.iter().map(|body| body.name.as_str()).collect();
    assert!(!bodies.contains(&"can1"), "{bodies:?}");
    let mut tally = BagTally::new(&mapping);
    tally.add(&read.absent);
    tally.add(&read.absent);
    let error = tally.check("bags/*.mcap", &mapping).unwrap_err();
    assert!(
        matches!(&error, Ros2Error::FrameInNoBag { frame, object, bags: 2, .. }
            if frame == "can_7" && object == "can1"),
        "{error}"
    );
    let code = miette::Diagnostic::code(&error).map(|code| code.to_string());
    assert_eq!(code.as_deref(), Some("lamp::ros2::frame_in_no_bag"));
    assert_eq!(
        error.to_string(),
        "frame `can_7` of object `can1` has no transform on `/tf` or `/tf_static` in any of the 2 bag(s) of `bags/*.mcap`"
    );
    let help = miette::Diagnostic::help(&error).map(|help| help.to_string()).unwrap_or_default();
    assert!(help.contains("most likely misspelt: check `can_7`"), "{help}");
    // One bag that records it is enough.
    tally.add(&[]);
    tally.check("bags/*.mcap", &mapping).unwrap();
    let absences = tally.absences(&mapping);
    assert_eq!(absences.len(), 1);
    assert_eq!((absences[0].0.name.as_str(), absences[0].1), ("can1", 2));
}

/// The robot's frame is not an object: a bag without it is refused as before.
#[test]
fn a_bag_without_the_robots_frame_is_refused() {
    let (trajectory, bag) = one_bag(|_| {});
    let mut mapping = mapping(&trajectory);
    mapping.robot.as_mut().unwrap().base_frame = "gripper_base".into();
    let error = read(&bag, &mapping).unwrap_err();
    assert!(
        matches!(&error, Ros2Error::MissingFrame { frame, .. } if frame == "gripper_base"),
        "{error}"
    );
}

/// A held topic that names a mapped frame the bag never records is refused: the held object
/// cannot be absent.
#[test]
fn a_held_object_the_bag_lacks_is_refused() {
    let (spec, world) = support::packing();
    let mut simulation = Simulation::from_spec(&spec).unwrap();
    simulation.count = 4;
    let trajectory = (generate_all(&world, &simulation, |_| {}).unwrap().into_iter())
        .map(|demonstration| demonstration.trajectory)
        .find(|trajectory| trajectory.steps.iter().any(|step| step.robots[0].held[0].is_some()))
        .unwrap();
    let (channels, mut values) = lamp_world::standard_channels(&world, &trajectory).unwrap();
    // The held topic names `can2`, a mapped frame that `/tf` never carries.
    let mut held_can2 = false;
    for value in &mut values {
        for held in value.held.iter_mut().filter(|held| *held == "can1") {
            *held = "can2".into();
            held_can2 = true;
        }
    }
    assert!(held_can2, "the demonstration grabs the can");
    let bag = strip(&trajectory.to_bytes_with(&channels, &values).unwrap());
    let mut two_cans = trajectory.clone();
    with_idle_can(&mut two_cans);
    let error = read(&bag, &mapping(&two_cans)).unwrap_err();
    assert!(matches!(&error, Ros2Error::HeldAbsent { frame, .. } if frame == "can2"), "{error}");
    let code = miette::Diagnostic::code(&error).map(|code| code.to_string());
    assert_eq!(code.as_deref(), Some("lamp::ros2::held_absent"));
}

fn packing_robot(world: &lamp_world::SpecWorld) -> MappedRobot<'_> {
    MappedRobot { model: &world.robots["gripper"], gripper: Some("gripper".into()), grasp: None }
}

/// A second can, still on the table corner, in every other demonstration.
fn with_idle_can(trajectory: &mut Trajectory) {
    let pose = nalgebra::Isometry3::translation(0.42, 0.42, 0.001);
    trajectory
        .header
        .bodies
        .push(lamp_trajectory::BodyDescription { name: "can2".into(), type_name: "can".into() });
    for step in &mut trajectory.steps {
        step.body_poses.push(pose);
    }
}

/// Scenes with different numbers of objects under one mapping: a second can is in half of the
/// bags. Each bag reads as the native file of its own scene (no body for the can it lacks), the
/// tally counts the bags that lacked it, and the model learned from the bags is the one learned
/// from the native files.
#[test]
fn an_object_some_bags_lack_is_absent_from_their_demonstrations() {
    let (spec, world) = support::packing();
    let mut simulation = Simulation::from_spec(&spec).unwrap();
    simulation.count = DEMOS;
    let demonstrations = generate_all(&world, &simulation, |_| {}).unwrap();
    let robot = packing_robot(&world);
    let mut native = Vec::new();
    let mut from_bags = Vec::new();
    let mut all_have_it = Vec::new();
    let mut two_cans = demonstrations[0].trajectory.clone();
    with_idle_can(&mut two_cans);
    let mapping = mapping(&two_cans);
    let mut tally = BagTally::new(&mapping);
    for demonstration in &demonstrations {
        let name = file_name("packing", demonstration.index);
        let mut trajectory = demonstration.trajectory.clone();
        let mut with_can = trajectory.clone();
        with_idle_can(&mut with_can);
        all_have_it.push(DemoFile { name: name.clone(), bytes: with_can.to_bytes().unwrap() });
        let lacks_it = demonstration.index % 2 == 1;
        if !lacks_it {
            trajectory = with_can;
        }
        let (channels, values) = lamp_world::standard_channels(&world, &trajectory).unwrap();
        let bag = strip(&trajectory.to_bytes_with(&channels, &values).unwrap());
        let read = lamp_build::ros2_bag(&bag, &name, "packing", &mapping, Some(&robot)).unwrap();
        let can2 = mapping.objects.iter().position(|object| object.name == "can2").unwrap();
        assert_eq!(read.absent, if lacks_it { vec![can2] } else { vec![] });
        assert_eq!(read.trajectory.header.bodies, trajectory.header.bodies);
        assert_eq!(read.trajectory.steps.len(), trajectory.steps.len());
        for (read, original) in read.trajectory.steps.iter().zip(&trajectory.steps) {
            assert_eq!(read.body_poses, original.body_poses);
            assert_eq!(read.robots[0].held, original.robots[0].held);
        }
        tally.add(&read.absent);
        native.push(DemoFile { name: name.clone(), bytes: trajectory.to_bytes().unwrap() });
        from_bags.push(DemoFile { name, bytes: read.trajectory.to_bytes().unwrap() });
    }
    tally.check("bags/*.mcap", &mapping).unwrap();
    let absences = tally.absences(&mapping);
    assert_eq!(absences.len(), 1);
    assert_eq!((absences[0].0.name.as_str(), absences[0].1), ("can2", DEMOS as usize / 2));
    let build = |files: &[DemoFile]| {
        let (_, artifacts) = lamp_build::build(&spec, "packing.lamp", &world, files).unwrap();
        let domain = domain_text(&artifacts);
        domain.lines().filter(|line| !line.starts_with(';')).collect::<Vec<_>>().join("\n")
    };
    let bag_domain = build(&from_bags);
    assert!(bag_domain.contains("(:action"), "{bag_domain}");
    assert_eq!(bag_domain, build(&native));
    // A can that only stands still teaches nothing: the domain is the one learned when every
    // scene has it.
    assert_eq!(bag_domain, build(&all_have_it));
}

#[test]
fn a_frame_that_jumps_is_refused_with_its_time() {
    let (trajectory, bag) = one_bag(|trajectory| {
        let body = trajectory.header.body_index("can1").unwrap();
        let middle = trajectory.steps.len() / 2;
        let step = &mut trajectory.steps[middle];
        step.body_poses[body] = Translation3::new(0.0, 0.0, 1.0) * step.body_poses[body];
    });
    let error = read(&bag, &mapping(&trajectory)).unwrap_err();
    let time = trajectory.steps[trajectory.steps.len() / 2].time_nanoseconds;
    assert!(
        matches!(&error, Ros2Error::Jump { frame, time_nanoseconds, .. } if frame == "can1" && *time_nanoseconds == time),
        "{error}"
    );
    assert!(error.to_string().contains("jumps 1.000 m"), "{error}");
}

#[test]
fn time_going_backwards_is_refused() {
    let (trajectory, bag) = one_bag(|_| {});
    // The tenth /tf message is logged at time zero, after the ninth at 160 ms (50 Hz).
    let mut tf_seen = 0;
    let bag = filter_bag(&bag, "bag", |topic, time| {
        tf_seen += usize::from(topic == "/tf");
        Some(if topic == "/tf" && tf_seen == 10 { 0 } else { time })
    })
    .unwrap();
    let error = read(&bag, &mapping(&trajectory)).unwrap_err();
    assert!(matches!(&error, Ros2Error::Timing { .. }), "{error}");
    assert!(
        error.to_string().contains("a `/tf` message at 0 ns follows one at 160000000 ns"),
        "{error}"
    );
}

/// One Café demonstration (a Fetch: a planar base and arm joints) and its bag.
fn cafe_bag() -> (lamp_world::SpecWorld, Trajectory, Vec<u8>) {
    let (spec, world) = lamp_test_support::domain("cafe");
    let mut simulation = Simulation::from_spec(&spec).unwrap();
    simulation.count = 1;
    simulation.cut_fraction = 0.0;
    let trajectory = generate_all(&world, &simulation, |_| {}).unwrap().remove(0).trajectory;
    let (channels, values) = lamp_world::standard_channels(&world, &trajectory).unwrap();
    let bag = strip(&trajectory.to_bytes_with(&channels, &values).unwrap());
    (world, trajectory, bag)
}

fn cafe_mapping(trajectory: &Trajectory) -> Ros2Mapping {
    let mut mapping = mapping(trajectory);
    mapping.robot = Some(FrameRobot {
        robot: "fetch".into(),
        base_frame: "base_link".into(),
        held_topic: Some("/lamp/held".into()),
        grasp_joint: None,
    });
    mapping
}

#[test]
fn a_mobile_arm_is_read_from_its_base_frame_and_joint_states() {
    let (world, trajectory, bag) = cafe_bag();
    let robot =
        MappedRobot { model: &world.robots["fetch"], gripper: Some("gripper".into()), grasp: None };
    let read = lamp_build::ros2_trajectory(
        &bag,
        "cafe.mcap",
        "cafe",
        &cafe_mapping(&trajectory),
        Some(&robot),
    )
    .unwrap();
    assert_eq!(read.header.robots, trajectory.header.robots);
    assert_eq!(read.steps.len(), trajectory.steps.len());
    for (read, original) in read.steps.iter().zip(&trajectory.steps) {
        assert_eq!(read.body_poses, original.body_poses);
        let (read, original) = (&read.robots[0], &original.robots[0]);
        assert_eq!(read.held, original.held);
        // The base's x, y and yaw go through a pose (yaw within rounding, as an angle in ±π);
        // joints come from /joint_states as written.
        for (index, (a, b)) in read.positions.iter().zip(&original.positions).enumerate() {
            let difference = if index == 2 {
                (a - b + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI
            } else {
                a - b
            };
            assert!(difference.abs() < 1e-12, "coordinate {index}: {a} read, {b} written");
        }
    }
    // Without /joint_states the arm's joints are unknown.
    let no_joints =
        filter_bag(&bag, "bag", |topic, time| (topic != "/joint_states").then_some(time)).unwrap();
    let error = lamp_build::ros2_trajectory(
        &no_joints,
        "cafe.mcap",
        "cafe",
        &cafe_mapping(&trajectory),
        Some(&robot),
    )
    .unwrap_err();
    assert!(matches!(&error, Ros2Error::MissingJoint { robot, .. } if robot == "fetch"), "{error}");
}

/// The Café bag with the grasps only in the finger joints: no `/lamp/held`, the fingers at
/// `closed` on `/joint_states` while the demonstration holds the can and at `open` otherwise.
fn cafe_bag_with_fingers(
    world: &lamp_world::SpecWorld,
    trajectory: &Trajectory,
    open: f64,
    closed: f64,
) -> Vec<u8> {
    let (mut channels, mut values) = lamp_world::standard_channels(world, trajectory).unwrap();
    channels.held_topics.clear();
    let fingers: Vec<usize> = (channels.joints.iter().enumerate())
        .filter(|(_, joint)| joint.ends_with("gripper_finger_joint"))
        .map(|(index, _)| index)
        .collect();
    assert_eq!(fingers.len(), 2, "{:?}", channels.joints);
    for (value, step) in values.iter_mut().zip(&trajectory.steps) {
        value.held.clear();
        let holding = step.robots[0].held[0].is_some();
        for finger in &fingers {
            value.joint_positions[*finger] = if holding { closed } else { open };
        }
    }
    strip(&trajectory.to_bytes_with(&channels, &values).unwrap())
}

fn grasp_joint_mapping(trajectory: &Trajectory, closed_below: f64) -> Ros2Mapping {
    let mut mapping = cafe_mapping(trajectory);
    let robot = mapping.robot.as_mut().unwrap();
    robot.held_topic = None;
    robot.grasp_joint =
        Some(lamp_build::ros2::GraspJoint { joint: "l_gripper_finger_joint".into(), closed_below });
    mapping
}

#[test]
fn grasps_are_read_from_a_closing_gripper_joint_near_a_movable_object() {
    let (world, trajectory, _) = cafe_bag();
    let holding = |steps: &[lamp_trajectory::Step]| -> Vec<Option<usize>> {
        steps.iter().map(|step| step.robots[0].held[0]).collect()
    };
    assert!(holding(&trajectory.steps).iter().any(Option::is_some), "the demo grasps the can");
    let bag = cafe_bag_with_fingers(&world, &trajectory, 0.05, 0.02);
    let mapping = grasp_joint_mapping(&trajectory, 0.03);
    let robot = lamp_build::ros2::mapped_robot(&world, &mapping).unwrap().unwrap();
    let grasp = robot.grasp.as_ref().unwrap();
    // Cans are movable; the surfaces they stand on are not.
    let can = |name: &str| name.starts_with("can");
    let expected: Vec<bool> =
        trajectory.header.bodies.iter().map(|body| can(&body.type_name)).collect();
    assert_eq!(grasp.holdable, expected);
    let read = lamp_build::ros2_trajectory(&bag, "cafe.mcap", "cafe", &mapping, Some(&robot));
    let read = read.unwrap();
    assert_eq!(holding(&read.steps), holding(&trajectory.steps));

    // A can the bag lacks, mapped first, is absent: the grasped body is the same can.
    let mut with_absent = grasp_joint_mapping(&trajectory, 0.03);
    let absent_can =
        FrameObject { frame: "can_absent".into(), name: "can0".into(), type_name: "can".into() };
    with_absent.objects.insert(0, absent_can);
    let robot = lamp_build::ros2::mapped_robot(&world, &with_absent).unwrap().unwrap();
    let read = lamp_build::ros2_bag(&bag, "cafe.mcap", "cafe", &with_absent, Some(&robot));
    let read = read.unwrap();
    assert_eq!(read.absent, vec![0]);
    assert_eq!(read.trajectory.header.bodies, trajectory.header.bodies);
    assert_eq!(holding(&read.trajectory.steps), holding(&trajectory.steps));

    // The same bag read with a closing value below the closed fingers never grasps.
    let mapping = grasp_joint_mapping(&trajectory, 0.01);
    let robot = lamp_build::ros2::mapped_robot(&world, &mapping).unwrap().unwrap();
    let read = lamp_build::ros2_trajectory(&bag, "cafe.mcap", "cafe", &mapping, Some(&robot));
    assert!(holding(&read.unwrap().steps).iter().all(Option::is_none));

    // Fingers closed from the start, with the can out of reach: nothing is grasped then, and a
    // gripper that stays closed does not pick up what it later comes near.
    let always_closed = cafe_bag_with_fingers(&world, &trajectory, 0.02, 0.02);
    let mapping = grasp_joint_mapping(&trajectory, 0.03);
    let robot = lamp_build::ros2::mapped_robot(&world, &mapping).unwrap().unwrap();
    let read =
        lamp_build::ros2_trajectory(&always_closed, "cafe.mcap", "cafe", &mapping, Some(&robot));
    assert!(holding(&read.unwrap().steps).iter().all(Option::is_none));
}

/// A bag of two robots, as lamp writes it: Keva's free-flying hand and YuMi arm, their frames
/// and joints prefixed `hand/` and `yumi/`, each read through a mapping of its own root frame.
#[test]
fn each_of_two_robots_is_read_through_its_prefixed_frames_and_joints() {
    use lamp_trajectory::{BodyDescription, RobotDescription, RobotState, Step, TrajectoryHeader};
    use nalgebra::{Isometry3, UnitQuaternion};
    let (_, world) = lamp_test_support::domain("keva");
    let (hand, yumi) = (&world.robots["hand"], &world.robots["yumi"]);
    let describe = |name: &str, model: &lamp_robot::Robot| RobotDescription {
        name: name.into(),
        coordinates: model.coordinate_names().to_vec(),
        grippers: vec!["gripper".into()],
    };
    let header = TrajectoryHeader {
        domain: "keva".into(),
        seed: 0,
        provenance: Default::default(),
        bodies: vec![
            BodyDescription { name: "table1".into(), type_name: "table".into() },
            BodyDescription { name: "plank1".into(), type_name: "plank".into() },
        ],
        robots: vec![describe("hand", hand), describe("yumi", yumi)],
    };
    let steps = (0..30)
        .map(|index| {
            let t = index as f64 * 0.01;
            let mut hand_q = hand.neutral_configuration();
            hand_q[0] = 0.1 + t;
            hand_q[2] = 0.3;
            let mut yumi_q = yumi.neutral_configuration();
            for (joint, value) in yumi_q.iter_mut().enumerate() {
                *value += 0.1 * (t + joint as f64).sin();
            }
            // Within the joints' limits, as a real arm records them.
            yumi.clamp(&mut yumi_q);
            let plank = Isometry3::from_parts(
                Translation3::new(0.2, 0.1 * t, 0.0),
                UnitQuaternion::from_euler_angles(0.0, 0.0, t),
            );
            Step {
                time_nanoseconds: index * 10_000_000,
                body_poses: vec![Isometry3::identity(), plank],
                robots: vec![
                    RobotState { positions: hand_q, held: vec![None] },
                    RobotState { positions: yumi_q, held: vec![None] },
                ],
            }
        })
        .collect();
    let trajectory = Trajectory { header, steps };
    let (channels, values) = lamp_world::standard_channels(&world, &trajectory).unwrap();
    let bag = strip(&trajectory.to_bytes_with(&channels, &values).unwrap());
    for (index, (name, model)) in [("hand", hand), ("yumi", yumi)].into_iter().enumerate() {
        let mut mapping = mapping(&trajectory);
        mapping.robot = Some(FrameRobot {
            robot: name.into(),
            base_frame: format!("{name}/{}", model.link_name(0)),
            held_topic: Some(format!("/{name}/lamp/held")),
            grasp_joint: None,
        });
        let robot = lamp_build::ros2::mapped_robot(&world, &mapping).unwrap().unwrap();
        let read =
            lamp_build::ros2_trajectory(&bag, "keva.mcap", "keva", &mapping, Some(&robot)).unwrap();
        assert_eq!(read.steps.len(), trajectory.steps.len());
        for (read, original) in read.steps.iter().zip(&trajectory.steps) {
            assert_eq!(read.body_poses, original.body_poses);
            let (read, original) = (&read.robots[0], &original.robots[index]);
            assert_eq!(read.held, original.held);
            for (a, b) in read.positions.iter().zip(&original.positions) {
                assert!((a - b).abs() < 1e-9, "{name}: {a} read, {b} written");
            }
        }
    }
    // The bare URDF names are not on /joint_states: a mapping whose frame has no prefix finds
    // no YuMi joint.
    let mut mapping = mapping(&trajectory);
    mapping.robot = Some(FrameRobot {
        robot: "yumi".into(),
        base_frame: "plank1".into(),
        held_topic: None,
        grasp_joint: None,
    });
    mapping.objects.truncate(1);
    let robot = lamp_build::ros2::mapped_robot(&world, &mapping).unwrap().unwrap();
    let error =
        lamp_build::ros2_trajectory(&bag, "keva.mcap", "keva", &mapping, Some(&robot)).unwrap_err();
    assert!(matches!(&error, Ros2Error::MissingJoint { robot, .. } if robot == "yumi"), "{error}");
}

/// A held topic the bag lacks (a typo in the mapping, or a recorder that left it out) is refused
/// naming the bag's topics, instead of being read as a gripper that never holds anything.
#[test]
fn a_held_topic_the_bag_lacks_is_refused_with_the_topics_it_has() {
    let (world, trajectory, bag) = cafe_bag();
    let robot =
        MappedRobot { model: &world.robots["fetch"], gripper: Some("gripper".into()), grasp: None };
    let mut mapping = cafe_mapping(&trajectory);
    mapping.robot.as_mut().unwrap().held_topic = Some("/lamp/hold".into());
    let error =
        lamp_build::ros2_trajectory(&bag, "cafe.mcap", "cafe", &mapping, Some(&robot)).unwrap_err();
    let message = error.to_string();
    assert!(matches!(&error, Ros2Error::NoHeldTopic { topic, .. } if topic == "/lamp/hold"));
    assert!(message.starts_with("cafe.mcap has no topic `/lamp/hold`"), "{message}");
    assert!(message.contains("/lamp/held") && message.contains("/joint_states"), "{message}");
}

/// A joint value no robot could have is refused with the joint, the value and the limits; one a
/// little past the URDF's limit, as real encoders read, and a continuous joint's unwrapped angle
/// are kept.
#[test]
fn a_joint_value_far_outside_its_limits_is_refused() {
    let (world, trajectory, _) = cafe_bag();
    let robot =
        MappedRobot { model: &world.robots["fetch"], gripper: Some("gripper".into()), grasp: None };
    let with_joint = |joint: &str, value: f64| {
        let (channels, mut values) = lamp_world::standard_channels(&world, &trajectory).unwrap();
        let index = channels.joints.iter().position(|name| name == joint).unwrap();
        values[3].joint_positions[index] = value;
        let bag = strip(&trajectory.to_bytes_with(&channels, &values).unwrap());
        lamp_build::ros2_trajectory(
            &bag,
            "cafe.mcap",
            "cafe",
            &cafe_mapping(&trajectory),
            Some(&robot),
        )
    };
    // shoulder_lift_joint is revolute, limited to [-1.221, 1.518] rad.
    let error = with_joint("shoulder_lift_joint", 1e300).unwrap_err();
    assert!(
        matches!(&error, Ros2Error::JointOutOfRange { joint, .. } if joint == "shoulder_lift_joint"),
        "{error}"
    );
    assert!(
        error
            .to_string()
            .contains("is at 1e300 on `/joint_states`, outside its limits [-1.221, 1.518]"),
        "{error}"
    );
    assert!(with_joint("shoulder_lift_joint", 1.518 + 0.01).is_ok());
    // upperarm_roll_joint is continuous: a driver reports it unwrapped.
    assert!(with_joint("upperarm_roll_joint", 7.0).is_ok());
    assert!(with_joint("upperarm_roll_joint", 1e300).is_err());
}

/// A bag of three steps whose `/tf` frames are `frames` (frame, parent), every pose the identity;
/// `can1` is the body the mapping reads.
fn tf_bag(frames: &[(String, String)]) -> Vec<u8> {
    use lamp_trajectory::{
        BodyDescription, StandardChannels, StandardStep, Step, TfFrame, TrajectoryHeader,
    };
    let trajectory = Trajectory {
        header: TrajectoryHeader {
            domain: "packing".into(),
            seed: 0,
            provenance: Default::default(),
            bodies: vec![BodyDescription { name: "can1".into(), type_name: "can".into() }],
            robots: vec![],
        },
        steps: (0..3)
            .map(|index| Step {
                time_nanoseconds: index * 10_000_000,
                body_poses: vec![nalgebra::Isometry3::identity()],
                robots: vec![],
            })
            .collect(),
    };
    let channels = StandardChannels {
        frames: frames
            .iter()
            .map(|(frame, parent)| TfFrame {
                parent: parent.clone(),
                frame: frame.clone(),
                derived: false,
            })
            .collect(),
        ..StandardChannels::rooted_at("world")
    };
    let values: Vec<StandardStep> = trajectory
        .steps
        .iter()
        .map(|_| StandardStep {
            frame_poses: vec![nalgebra::Isometry3::identity(); frames.len()],
            joint_positions: vec![],
            label: None,
            approach: None,
            held: vec![],
            trajectories: Vec::new(),
            gripper_commands: Vec::new(),
        })
        .collect();
    strip(&trajectory.to_bytes_with(&channels, &values).unwrap())
}

/// `can1` read from `bag` with no robot.
fn read_can(bag: &[u8]) -> Result<Trajectory, Ros2Error> {
    let mapping = Ros2Mapping {
        objects: vec![FrameObject {
            frame: "can1".into(),
            name: "can1".into(),
            type_name: "can".into(),
        }],
        robot: None,
    };
    lamp_build::ros2_trajectory(bag, "bag.mcap", "packing", &mapping, None)
}

fn frame(frame: &str, parent: &str) -> (String, String) {
    (frame.to_string(), parent.to_string())
}

/// A chain of `depth` frames `f1` … from `can1` up to `world`.
fn chain(depth: usize) -> Vec<(String, String)> {
    let name = |index: usize| if index == 0 { "can1".to_string() } else { format!("f{index}") };
    let mut frames: Vec<_> = (0..depth).map(|index| (name(index), name(index + 1))).collect();
    frames.push((name(depth), "world".to_string()));
    frames
}

/// A cycle of parents on `/tf` was reported as a frame that never appears; it is named, frame by
/// frame.
#[test]
fn a_tf_cycle_is_named_with_its_frames() {
    let bag = tf_bag(&[frame("can1", "a"), frame("a", "b"), frame("b", "a")]);
    let error = read_can(&bag).unwrap_err();
    assert!(
        matches!(&error, Ros2Error::TfCycle { frame, cycle, time_nanoseconds: 0, .. }
            if frame == "can1" && cycle == "`a` → `b` → `a`"),
        "{error}"
    );
    let code = miette::Diagnostic::code(&error).map(|code| code.to_string());
    assert_eq!(code.as_deref(), Some("lamp::ros2::tf_cycle"));
    let message = error.to_string();
    assert!(
        message.contains("frame `can1` has no root on `/tf`: its parents form the cycle"),
        "{message}"
    );
    assert!(!message.contains("never appears"), "{message}");
    let help = miette::Diagnostic::help(&error).map(|help| help.to_string()).unwrap_or_default();
    assert!(help.contains("the chain of parents ends at a root"), "{help}");
    // A frame that is its own parent is the shortest cycle.
    let error = read_can(&tf_bag(&[frame("can1", "can1")])).unwrap_err();
    assert!(
        matches!(&error, Ros2Error::TfCycle { cycle, .. } if cycle == "`can1` → `can1`"),
        "{error}"
    );
}

/// A chain of parents longer than the depth limit was reported as a frame that never appears; it
/// names the limit, and a chain just within it reads.
#[test]
fn a_tf_chain_deeper_than_the_limit_names_the_limit() {
    let depth = lamp_build::MAX_TREE_DEPTH;
    let error = read_can(&tf_bag(&chain(depth))).unwrap_err();
    assert!(
        matches!(&error, Ros2Error::TfTooDeep { frame, max_depth, .. }
            if frame == "can1" && *max_depth == depth),
        "{error}"
    );
    let code = miette::Diagnostic::code(&error).map(|code| code.to_string());
    assert_eq!(code.as_deref(), Some("lamp::ros2::tf_depth"));
    let message = error.to_string();
    assert!(message.contains("is more than 1000 transforms below the root"), "{message}");
    let read = read_can(&tf_bag(&chain(depth - 1))).unwrap();
    assert!(!read.steps.is_empty());
}
