//! The `files "…" as ros2 { … }` demonstration source: a frame mapping for bags of standard ROS 2
//! messages, lowered into the spec, and its diagnostics with spans on the mapping.

mod common;

use common::{VALID, check, codes, render};
use lamp_spec::{DemoSource, FrameObject, FrameRobot, Ros2Mapping};

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
        }),
    };
    assert_eq!(
        spec.demonstrations,
        [DemoSource::Files { pattern: "demos/*.mcap".into(), ros2: Some(expected) }]
    );
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
