//! The `files "…" as ros2 { … }` demonstration source: a frame mapping for bags of standard ROS 2
//! messages, lowered into the spec, and its diagnostics with spans on the mapping.

mod common;

use common::{VALID, check, codes, render};
use lamp_spec::{DemoSource, FrameObject, FrameRobot, GraspJoint, Ros2Mapping};

fn with_source(source: &str) -> String {
    let simulate = "  simulate packing { count 20  cut 0.5  objects 1  seed 3 }";
    assert!(VALID.contains(simulate));
    VALID.replacen(simulate, source, 1)
}

#[test]
fn a_ros2_source_lowers_to_its_mapping() {
    let source = with_source(
        "  files \"demos/*.mcap\" as ros2 {\n    object can can1 frame \"can_1\"\n    object surface box1\n    robot gripper frame \"gripper_link\" held topic \"/lamp/held\"\n  }",
    );
    let outcome = check(&source);
    let spec = outcome.spec.unwrap_or_else(|| panic!("{}", render(&check(&source))));
    let object = |frame: &str, name: &str, type_name: &str| FrameObject {
        frame: frame.into(),
        name: name.into(),
        type_name: type_name.into(),
    };
    let expected = Ros2Mapping {
        objects: vec![object("can_1", "can1", "can"), object("box1", "box1", "surface")],
        robot: Some(FrameRobot {
            robot: "gripper".into(),
            base_frame: "gripper_link".into(),
            held_topic: Some("/lamp/held".into()),
            grasp_joint: None,
        }),
    };
    assert_eq!(
        spec.demonstrations,
        [DemoSource::Files { pattern: "demos/*.mcap".into(), ros2: Some(expected) }]
    );
    // Each mapped object's line, from its type to its frame, is kept for the build's findings
    // (a frame no bag records).
    let span = outcome.places.mapped_object("demos/*.mcap", "can1").expect("the can's line");
    assert_eq!(&source[span.start..span.end], "can can1 frame \"can_1\"");
    let span = outcome.places.mapped_object("demos/*.mcap", "box1").expect("the box's line");
    assert_eq!(&source[span.start..span.end], "surface box1");
    assert!(outcome.places.mapped_object("other/*.mcap", "can1").is_none());
    // A plain `files` source has no mapping.
    let outcome = check(&with_source("  files \"demos/*.mcap\""));
    let spec = outcome.spec.expect("a plain files source checks");
    assert_eq!(
        spec.demonstrations,
        [DemoSource::Files { pattern: "demos/*.mcap".into(), ros2: None }]
    );
}

#[test]
fn mistakes_in_a_mapping_are_reported_on_the_mapping() {
    let source = with_source(
        "  files \"demos/*.mcap\" as ros2 {\n    object cann can1\n    object can can2 frame \"x\"\n    object can can3 frame \"x\"\n    robot grippr frame \"base\"\n    robot gripper frame \"base\" held topic \"held\"\n  }",
    );
    let outcome = check(&source);
    assert_eq!(
        codes(&outcome),
        [
            "lamp::resolve::unknown_type",
            "lamp::resolve::duplicate_name",
            "lamp::resolve::unknown_robot",
            "lamp::check::duplicate_setting",
        ],
        "{}",
        render(&outcome)
    );
    let text = render(&outcome);
    assert!(text.contains("tf frame `x` is declared twice"), "{text}");
    assert!(text.contains("Did you mean `can`?"), "{text}");
    let empty = check(&with_source("  files \"demos/*.mcap\" as ros2 { }"));
    assert_eq!(codes(&empty), ["lamp::check::missing_declaration"]);
    let topic = check(&with_source(
        "  files \"demos/*.mcap\" as ros2 { object can can1  robot gripper frame \"g\" held topic \"held\" }",
    ));
    assert_eq!(codes(&topic), ["lamp::check::out_of_range"]);
}

#[test]
fn grasps_may_come_from_a_gripper_joint() {
    let source = with_source(
        "  files \"demos/*.mcap\" as ros2 {\n    object can can1\n    robot gripper frame \"gripper_link\" grasp joint \"left_finger_joint\" below 10 mm\n  }",
    );
    let outcome = check(&source);
    let spec = outcome.spec.unwrap_or_else(|| panic!("{}", render(&check(&source))));
    let DemoSource::Files { ros2: Some(mapping), .. } = &spec.demonstrations[0] else {
        panic!("a ros2 source: {:?}", spec.demonstrations);
    };
    let robot = mapping.robot.as_ref().unwrap();
    assert_eq!(robot.held_topic, None);
    assert_eq!(
        robot.grasp_joint,
        Some(GraspJoint { joint: "left_finger_joint".into(), closed_below: 0.01 })
    );
    // An angle for a revolute finger, in radians.
    let degrees = check(&with_source(
        "  files \"demos/*.mcap\" as ros2 { object can can1  robot gripper frame \"g\" grasp joint \"left_finger_joint\" below 90 deg }",
    ));
    let spec = degrees.spec.expect("an angle checks");
    let DemoSource::Files { ros2: Some(mapping), .. } = &spec.demonstrations[0] else { panic!() };
    let closed_below = mapping.robot.as_ref().unwrap().grasp_joint.as_ref().unwrap().closed_below;
    assert!((closed_below - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
}

#[test]
fn a_grasp_joint_must_be_a_joint_of_the_robot_and_the_robot_needs_a_grab_distance() {
    let misspelt = check(&with_source(
        "  files \"demos/*.mcap\" as ros2 { object can can1  robot gripper frame \"g\" grasp joint \"left_fingr_joint\" below 1 cm }",
    ));
    assert_eq!(codes(&misspelt), ["lamp::resolve::unknown_joint"], "{}", render(&misspelt));
    let text = render(&misspelt);
    assert!(text.contains("Did you mean `left_finger_joint`?"), "{text}");
    assert!(text.contains("grasp joint \"left_fingr_joint\""), "the span shows the joint: {text}");
    let no_grab = VALID.replacen("  grab distance 0.19 m .. 0.22 m\n", "", 1);
    assert_ne!(no_grab, VALID);
    let no_grab = no_grab.replacen(
        "  simulate packing { count 20  cut 0.5  objects 1  seed 3 }",
        "  files \"demos/*.mcap\" as ros2 { object can can1  robot gripper frame \"g\" grasp joint \"left_finger_joint\" below 1 cm }",
        1,
    );
    let outcome = check(&no_grab);
    assert!(codes(&outcome).contains(&"lamp::check::conflict".to_string()), "{}", render(&outcome));
    let text = render(&outcome);
    assert!(text.contains("has no grab distance to find the grasped object by"), "{text}");
    // A held topic and a grasp joint are alternatives.
    let both = check(&with_source(
        "  files \"demos/*.mcap\" as ros2 { object can can1  robot gripper frame \"g\" held topic \"/h\" grasp joint \"left_finger_joint\" below 1 cm }",
    ));
    assert_eq!(codes(&both), ["lamp::parse::syntax"], "{}", render(&both));
}
