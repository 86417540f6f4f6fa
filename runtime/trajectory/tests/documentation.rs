//! `docs/formats.md` states the schema a user must write; it must be the one we write.

use std::path::Path;

#[test]
fn the_documented_schema_is_the_written_schema() {
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/formats.md");
    let text = std::fs::read_to_string(docs).unwrap();
    let section = text.split("### The step message").nth(1).expect("a step message section");
    let start = section.find("```text\n").expect("a schema block") + "```text\n".len();
    let length = section[start..].find("```").unwrap();
    assert_eq!(&section[start..start + length], lamp_trajectory::WORLD_STEP_SCHEMA);
}

#[test]
fn every_standard_channel_is_documented_with_its_type() {
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/formats.md");
    let text = std::fs::read_to_string(docs).unwrap();
    let section = text.split("### Standard channels for viewers").nth(1).expect("the section");
    use lamp_trajectory::*;
    for (topic, schema) in [
        (ROBOT_DESCRIPTION_TOPIC, STRING_SCHEMA_NAME),
        (TF_STATIC_TOPIC, TF_SCHEMA_NAME),
        (SCENE_TOPIC, SCENE_SCHEMA_NAME),
        (TF_TOPIC, TF_SCHEMA_NAME),
        (JOINT_STATES_TOPIC, JOINT_STATE_SCHEMA_NAME),
        (HELD_TOPIC, STRING_SCHEMA_NAME),
        (STEP_LABEL_TOPIC, STRING_SCHEMA_NAME),
    ] {
        let row = format!("| `{topic}` | `{schema}` (");
        assert!(section.contains(&row), "docs/formats.md has no row {row}");
    }
}
