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
