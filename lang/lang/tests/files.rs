//! What the checker says about the files a spec names: a byte order mark at the start, paths
//! that are not files, and the link and joint names a robot block takes from its robot file.

mod common;

use std::path::Path;

use common::{VALID, check, codes, render};
use lamp_lang::{FileKind, Loader, MemoryLoader};

const BOM: &str = "\u{FEFF}";

/// Checks `VALID` with `from` replaced by `to` and returns the codes and the rendering.
fn replaced(from: &str, to: &str) -> (Vec<String>, String) {
    assert!(VALID.contains(from), "`{from}` is not in the valid spec");
    let outcome = check(&VALID.replacen(from, to, 1));
    assert_eq!(outcome.spec.is_some(), outcome.diagnostics.is_empty());
    (codes(&outcome), render(&outcome))
}

#[test]
fn a_byte_order_mark_starts_a_spec_as_if_absent() {
    let outcome = check(&format!("{BOM}{VALID}"));
    assert!(outcome.diagnostics.is_empty(), "{}", render(&outcome));
    assert!(outcome.spec.is_some());
}

#[test]
fn spans_after_a_byte_order_mark_point_at_the_text() {
    let source = format!("{BOM}{}", VALID.replacen("    can c1 at", "    cann c1 at", 1));
    let outcome = check(&source);
    assert_eq!(codes(&outcome), ["lamp::resolve::unknown_type"]);
    assert_eq!(&source[outcome.diagnostics[0].range()], "cann");
    // Lines and columns count from the first line as usual.
    let rendered = render(&outcome);
    let line = VALID.lines().position(|line| line.starts_with("    can c1 at")).expect("a can") + 1;
    assert!(rendered.contains(&format!("spec.lamp:{line}:5")), "{rendered}");
}

#[test]
fn a_byte_order_mark_starts_a_scene_file_too() {
    let scene = format!("{BOM}table t1 at (0, 0, 0) m\ncan c1 at (0.1, 0, 0) m\n");
    let loader = MemoryLoader::new([
        ("robots/gripper.urdf", ""),
        ("demos/a.mcap", ""),
        ("scenes/bom.lamp", scene.as_str()),
    ]);
    let start = VALID.find("  scene {").expect("an inline scene");
    let end = start + VALID[start..].find("  }\n").expect("the scene block ends") + 4;
    let source = format!(
        "{}  scene \"scenes/bom.lamp\"\n{}",
        &VALID[..start].replacen("type can {", "type spot { marker }\ntype can {", 1),
        &VALID[end..].replace(
            "    in_box(c1, box1)\n    surface_can_1(box1, c1)\n",
            "    at c1 (0, 0, 0) m within 0.01 m 5 deg\n"
        )
    );
    let outcome = lamp_lang::check_source("spec.lamp", &source, Path::new(""), &loader);
    assert!(outcome.diagnostics.is_empty(), "{}", render(&outcome));
}

#[test]
fn a_byte_order_mark_elsewhere_is_a_syntax_error() {
    let source = VALID.replacen("seed 7", &format!("{BOM}seed 7"), 1);
    assert_eq!(codes(&check(&source)), ["lamp::parse::syntax"]);
}

#[test]
fn a_folder_named_as_a_file_says_what_it_is() {
    let (found, rendered) = replaced("\"robots/gripper.urdf\"", "\"robots\"");
    assert_eq!(found, ["lamp::check::not_a_file"]);
    insta::assert_snapshot!("not_a_file", rendered);
}

#[test]
fn the_memory_loader_tells_files_folders_and_nothing_apart() {
    let loader = common::loader();
    assert_eq!(loader.file_kind(Path::new("robots/gripper.urdf")), FileKind::File);
    assert_eq!(loader.file_kind(Path::new("robots/./")), FileKind::NotAFile("a directory".into()));
    assert_eq!(loader.file_kind(Path::new("robots/grip")), FileKind::Missing);
}

#[test]
fn a_part_names_a_link_of_the_robot_file() {
    let (found, rendered) = replaced(
        "link \"gripper_link\"",
        "link \"griper_link\"\n  part finger = link \"nope_link\"",
    );
    assert_eq!(found, ["lamp::resolve::unknown_link", "lamp::resolve::unknown_link"]);
    insta::assert_snapshot!("unknown_link", rendered);
}

#[test]
fn ignored_collisions_name_links_of_the_robot_file() {
    let (found, _) = replaced(
        "  grab distance",
        "  ignore collision \"left_finger\" \"right_fingers\"\n  grab distance",
    );
    assert_eq!(found, ["lamp::resolve::unknown_link"]);
}

#[test]
fn groups_and_configurations_name_joints_and_coordinates_of_the_robot_file() {
    let setting = "  group fingers = [\"left_finger_joint\", \"right_finger_jiont\", \"base_x\", \"elbow\"]\n  \
                   config open { left_finger_joint: 0.04 m, base_z: 0.5 m, right_finger: 0.04 m }\n  grab distance";
    let (found, rendered) = replaced("  grab distance", setting);
    assert_eq!(
        found,
        [
            "lamp::resolve::unknown_joint",
            "lamp::resolve::unknown_joint",
            "lamp::resolve::unknown_joint"
        ]
    );
    insta::assert_snapshot!("unknown_joint", rendered);
}

#[test]
fn a_configuration_cannot_set_a_fixed_joint() {
    let spec = VALID
        .replacen("robots/gripper.urdf", "robots/arm.urdf", 1)
        .replacen("kind free_flying", "kind fixed_arm", 1)
        .replacen(
            "  grab distance",
            "  config home { shoulder_joint: 10 deg, wrist_fixed_joint: 0 deg }\n  grab distance",
            1,
        )
        .replacen(
            "    robot gripper at (0, 0, 0.5) m rpy (180, 0, 0) deg\n",
            "    robot gripper config home\n",
            1,
        );
    let outcome = check(&spec);
    assert_eq!(codes(&outcome), ["lamp::check::conflict"], "{}", render(&outcome));
    assert!(
        render(&outcome)
            .contains("joint `wrist_fixed_joint` of `robots/arm.urdf` has no single value to set")
    );
}

/// A loader whose robot file does not load.
struct BrokenRobot;

impl Loader for BrokenRobot {
    fn read_to_string(&self, path: &Path) -> Result<String, String> {
        common::loader().read_to_string(path)
    }
    fn file_kind(&self, path: &Path) -> FileKind {
        common::loader().file_kind(path)
    }
    fn glob(&self, pattern: &Path) -> Vec<std::path::PathBuf> {
        common::loader().glob(pattern)
    }
    fn robot_names(
        &self,
        _path: &Path,
        _kind: lamp_spec::RobotKind,
    ) -> Result<Option<lamp_spec::RobotNames>, String> {
        Err("robots/gripper.urdf: invalid URDF: missing field `name`".to_string())
    }
}

#[test]
fn a_robot_file_that_does_not_load_is_reported_at_its_path() {
    let outcome = lamp_lang::check_source("spec.lamp", VALID, Path::new(""), &BrokenRobot);
    assert_eq!(codes(&outcome), ["lamp::check::robot_file"]);
    assert_eq!(&VALID[outcome.diagnostics[0].range()], "\"robots/gripper.urdf\"");
    insta::assert_snapshot!("robot_file", render(&outcome));
}

#[test]
fn a_loader_without_robot_names_leaves_the_names_unchecked() {
    let loader = MemoryLoader::new([("robots/gripper.urdf", ""), ("demos/a.mcap", "")]);
    let source = VALID.replacen("link \"gripper_link\"", "link \"nope_link\"", 1);
    let outcome = lamp_lang::check_source("spec.lamp", &source, Path::new(""), &loader);
    assert!(outcome.diagnostics.is_empty(), "{}", render(&outcome));
}
