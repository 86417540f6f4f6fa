//! One snapshot per diagnostic code: the source and what `lampc check` prints for it.

mod common;

use std::path::Path;

use common::{VALID, check, codes, render};

/// Checks `VALID` with `from` replaced by `to`, asserts the codes, and snapshots the rendering.
fn case(name: &str, from: &str, to: &str, expected: &[&str]) {
    assert!(VALID.contains(from), "case {name}: `{from}` is not in the valid spec");
    let source = VALID.replacen(from, to, 1);
    let outcome = check(&source);
    assert_eq!(codes(&outcome), expected, "case {name}:\n{}", render(&outcome));
    assert!(outcome.spec.is_none(), "case {name}: a spec with errors must not produce a Spec");
    let excerpt = to.trim();
    insta::assert_snapshot!(
        name,
        format!("----- SOURCE (excerpt)\n{excerpt}\n----- DIAGNOSTICS\n{}", render(&outcome))
    );
}

#[test]
fn the_valid_spec_is_clean() {
    let outcome = check(VALID);
    assert!(outcome.diagnostics.is_empty(), "{}", render(&outcome));
    assert!(outcome.spec.is_some());
}

#[test]
fn parse_syntax() {
    case("parse_syntax", "type can {", "type can movable {", &["lamp::parse::syntax"]);
}

#[test]
fn parse_syntax_in_a_scene_file() {
    let from = "  scene {\n    table t1 at (0, 0, 0) m\n    surface box1 at (0.2, 0, 0) m rpy (0, 0, 30) deg\n    can c1 at (-0.2, 0, 0) m\n    robot gripper at (0, 0, 0.5) m rpy (180, 0, 0) deg\n  }";
    case(
        "parse_syntax_in_a_scene_file",
        from,
        "  scene \"scenes/broken.lamp\"",
        &["lamp::parse::syntax"],
    );
}

#[test]
fn resolve_duplicate_name() {
    case(
        "resolve_duplicate_name",
        "type surface {",
        "type can { movable sphere radius 1 m }\ntype surface {",
        &["lamp::resolve::duplicate_name"],
    );
}

#[test]
fn resolve_unknown_type() {
    case(
        "resolve_unknown_type",
        "    can c1 at",
        "    cann c1 at",
        &["lamp::resolve::unknown_type"],
    );
}

#[test]
fn resolve_unknown_robot() {
    case(
        "resolve_unknown_robot",
        "    robot gripper at",
        "    robot griper at",
        &["lamp::resolve::unknown_robot"],
    );
}

#[test]
fn resolve_unknown_object() {
    case(
        "resolve_unknown_object",
        "    in_box(c1, box1)",
        "    in_box(c2, box1)",
        &["lamp::resolve::unknown_object"],
    );
}

/// A goal naming the robot itself, which the scene does place, says it is a robot and which
/// parts a goal can name, rather than that it is not in the scene.
#[test]
fn resolve_robot_as_object() {
    case(
        "resolve_robot_as_object",
        "    in_box(c1, box1)",
        "    in_box(gripper, box1)",
        &["lamp::resolve::robot_as_object"],
    );
}

#[test]
fn resolve_unknown_structure() {
    case(
        "resolve_unknown_structure",
        "    in_box(c1, box1)",
        "    structure pi_tower at t1",
        &["lamp::resolve::unknown_structure"],
    );
}

/// `VALID` with a structure of two cans, and its goal in place of the relation goals.
fn with_structure(goal: &str) -> String {
    VALID
        .replacen(
            "relation in_box",
            "structure stack {\n  can c1 at (0, 0, 0.001) m\n  can c2 at (0, 0, 0.152) m\n}\n\nrelation in_box",
            1,
        )
        .replacen("    in_box(c1, box1)\n    surface_can_1(box1, c1)", goal, 1)
}

#[test]
fn goal_structure_object() {
    // `c2` is not in the scene, and the anchor `c1` is an object of the structure.
    let source = with_structure("    structure stack at c1");
    let outcome = check(&source);
    assert_eq!(
        codes(&outcome),
        ["lamp::goal::structure_object", "lamp::goal::structure_object"],
        "{}",
        render(&outcome)
    );
    assert!(outcome.spec.is_none());
    insta::assert_snapshot!(
        "goal_structure_object",
        format!(
            "----- SOURCE (excerpt)\nstructure stack at c1\n----- DIAGNOSTICS\n{}",
            render(&outcome)
        )
    );
}

#[test]
fn goal_structure_object_of_another_type() {
    let source = with_structure("    structure stack at box1").replacen(
        "    can c1 at (-0.2, 0, 0) m\n",
        "    can c1 at (-0.2, 0, 0) m\n    surface c2 at (-0.4, 0, 0) m\n",
        1,
    );
    let outcome = check(&source);
    assert_eq!(codes(&outcome), ["lamp::goal::structure_object"], "{}", render(&outcome));
    assert!(
        render(&outcome).contains("a can, and the scene's `c2` is a surface"),
        "{}",
        render(&outcome)
    );
}

#[test]
fn goal_structure_object_with_an_at_goal_too() {
    let source = with_structure(
        "    structure stack at box1\n    at c1 (0.3, 0, 0.001) m within 0.01 m 10 deg",
    )
    .replacen("type can {", "type spot { marker }\ntype can {", 1)
    .replacen(
        "    can c1 at (-0.2, 0, 0) m\n",
        "    can c1 at (-0.2, 0, 0) m\n    can c2 at (-0.3, 0, 0) m\n",
        1,
    );
    let outcome = check(&source);
    assert_eq!(codes(&outcome), ["lamp::goal::structure_object"], "{}", render(&outcome));
    assert!(
        render(&outcome).contains("and an `at` goal gives `c1` another target"),
        "{}",
        render(&outcome)
    );
}

#[test]
fn a_structure_goal_binds_its_objects_by_name() {
    let source = with_structure("    structure stack at box1 offset (0, 0, 0.01) m").replacen(
        "    can c1 at (-0.2, 0, 0) m\n",
        "    can c1 at (-0.2, 0, 0) m\n    can c2 at (-0.3, 0, 0) m\n",
        1,
    );
    let outcome = check(&source);
    assert!(outcome.diagnostics.is_empty(), "{}", render(&outcome));
    let spec = outcome.spec.expect("a clean spec");
    let goal = spec.problems[0].goal.structure.clone().expect("the structure goal");
    assert_eq!((goal.structure.as_str(), goal.anchor.as_str()), ("stack", "box1"));
    let places = &outcome.places;
    assert!(places.structure_goal("p1").is_some());
    assert!(places.structure_object("stack", "c2").is_some());
    assert!(places.structure_object("stack", "c3").is_none());
}

#[test]
fn resolve_unknown_configuration() {
    case(
        "resolve_unknown_configuration",
        "rpy (180, 0, 0) deg\n",
        "rpy (180, 0, 0) deg config tuck\n",
        &["lamp::resolve::unknown_configuration"],
    );
}

#[test]
fn check_unknown_word() {
    case(
        "check_unknown_word",
        "kind free_flying",
        "kind free_flyer",
        &["lamp::check::unknown_word"],
    );
}

#[test]
fn check_missing_declaration() {
    case("check_missing_declaration", "seed 7\n", "", &["lamp::check::missing_declaration"]);
}

#[test]
fn check_duplicate_setting() {
    case(
        "check_duplicate_setting",
        "  threshold 0.5\n",
        "  threshold 0.5\n  threshold 0.6\n",
        &["lamp::check::duplicate_setting"],
    );
}

#[test]
fn check_out_of_range() {
    case(
        "check_out_of_range",
        "  threshold 0.5\n",
        "  threshold 1.5\n",
        &["lamp::check::out_of_range"],
    );
}

#[test]
fn check_unit_required() {
    case(
        "check_unit_required",
        "radius 0.0325 m",
        "radius 0.0325",
        &["lamp::check::unit_required"],
    );
}

#[test]
fn check_wrong_unit() {
    case("check_wrong_unit", "radius 0.0325 m", "radius 0.0325 deg", &["lamp::check::wrong_unit"]);
}

#[test]
fn check_unexpected_unit() {
    case(
        "check_unexpected_unit",
        "  threshold 0.5\n",
        "  threshold 0.5 m\n",
        &["lamp::check::unexpected_unit"],
    );
}

#[test]
fn check_not_integer() {
    case("check_not_integer", "count 20 ", "count 20.5 ", &["lamp::check::not_integer"]);
}

#[test]
fn check_missing_file() {
    case(
        "check_missing_file",
        "\"robots/gripper.urdf\"",
        "\"robots/griper.urdf\"",
        &["lamp::check::missing_file"],
    );
}

#[test]
fn check_conflict() {
    case(
        "check_conflict",
        "  kind free_flying\n",
        "  kind free_flying\n  mount (0, 0, 0) m\n",
        &["lamp::check::conflict"],
    );
}

#[test]
fn goal_unknown_relation() {
    case(
        "goal_unknown_relation",
        "    in_box(c1, box1)",
        "    inside(c1, box1)",
        &["lamp::goal::unknown_relation"],
    );
}

#[test]
fn goal_arity() {
    case("goal_arity", "    in_box(c1, box1)", "    in_box(c1)", &["lamp::goal::arity"]);
}

#[test]
fn goal_argument_type() {
    case(
        "goal_argument_type",
        "    in_box(c1, box1)",
        "    in_box(box1, c1)",
        &["lamp::goal::argument_type", "lamp::goal::argument_type"],
    );
}

#[test]
fn goal_not_movable() {
    case(
        "goal_not_movable",
        "    in_box(c1, box1)",
        "    at box1 (0, 0, 0) m within 0.01 m 5 deg",
        &["lamp::goal::not_movable"],
    );
}

/// An `at` goal on a marker names it a marker, not a static object.
#[test]
fn goal_not_movable_marker() {
    let source = VALID
        .replacen("type can {", "type spot { marker }\ntype can {", 1)
        .replacen(
            "    can c1 at (-0.2, 0, 0) m\n",
            "    can c1 at (-0.2, 0, 0) m\n    spot coaster1 at (0.3, 0, 0) m\n",
            1,
        )
        .replacen("    in_box(c1, box1)", "    at coaster1 (0, 0, 0) m within 0.01 m 5 deg", 1);
    let outcome = check(&source);
    assert_eq!(codes(&outcome), ["lamp::goal::not_movable"], "{}", render(&outcome));
    let rendered = render(&outcome);
    assert!(!rendered.contains("static"), "{rendered}");
    insta::assert_snapshot!("goal_not_movable_marker", rendered);
}

/// An `at` goal on a robot's part (an object a goal may name, but no object of the scene) is
/// refused by the checker, not left for the build to find.
#[test]
fn goal_not_movable_robot_part() {
    let source = VALID.replacen("type can {", "type spot { marker }\ntype can {", 1).replacen(
        "    in_box(c1, box1)",
        "    at gripper_gripper (0, 0, 0.3) m within 0.01 m 5 deg",
        1,
    );
    let outcome = check(&source);
    assert_eq!(codes(&outcome), ["lamp::goal::not_movable"], "{}", render(&outcome));
    insta::assert_snapshot!("goal_not_movable_robot_part", render(&outcome));
}

/// A problem's name names its files, so it must fit in a file name with room to spare.
#[test]
fn check_name_too_long() {
    let long = format!("p{}", "1".repeat(239));
    case(
        "check_name_too_long",
        "problem p1 {",
        &format!("problem {long} {{"),
        &["lamp::check::name_too_long"],
    );
    let longest = format!("p{}", "1".repeat(199));
    let outcome = check(&VALID.replacen("problem p1 {", &format!("problem {longest} {{"), 1));
    assert!(outcome.diagnostics.is_empty(), "{}", render(&outcome));
}

#[test]
fn marker_with_a_shape() {
    case(
        "marker_with_a_shape",
        "type surface {",
        "type spot { marker  box size (0.1, 0.1, 0.1) m }\ntype surface {",
        &["lamp::check::conflict"],
    );
}

#[test]
fn at_goal_without_a_marker_type() {
    case(
        "at_goal_without_a_marker_type",
        "    in_box(c1, box1)",
        "    at c1 (0.2, 0, 0.001) m within 0.01 m 5 deg",
        &["lamp::check::conflict"],
    );
}

/// The valid spec with a marker type `spot`, the goal `at c1 …` instead of `in_box(c1, box1)`,
/// and `extra_scene` lines after `c1` in the scene.
fn with_at_goal(extra_scene: &str) -> String {
    VALID
        .replacen("type can {", "type spot { marker }\ntype can {", 1)
        .replacen(
            "    can c1 at (-0.2, 0, 0) m",
            &format!("    can c1 at (-0.2, 0, 0) m{extra_scene}"),
            1,
        )
        .replacen("    in_box(c1, box1)", "    at c1 (0.2, 0, 0.001) m within 0.01 m 5 deg", 1)
}

#[test]
fn an_at_goal_takes_the_only_marker_type_and_names_its_marker() {
    let outcome = check(&with_at_goal(""));
    let rendered = render(&outcome);
    let spec = outcome.spec.unwrap_or_else(|| panic!("{rendered}"));
    let spot = spec.object_type("spot").expect("the marker type");
    assert_eq!(spot.mobility, lamp_spec::Mobility::Marker);
    assert!(spot.shapes.is_empty());
    let target = &spec.problems[0].goal.at[0];
    assert_eq!((target.marker_type.as_str(), target.marker_name()), ("spot", "goal_c1".into()));
}

#[test]
fn an_at_goal_whose_start_marker_name_is_taken_is_refused() {
    let outcome = check(&with_at_goal("\n    can start_c1 at (-0.3, 0.2, 0) m"));
    assert_eq!(codes(&outcome), ["lamp::check::conflict"], "{}", render(&outcome));
    assert!(render(&outcome).contains("a marker named `start_c1`"), "{}", render(&outcome));
}

#[test]
fn a_start_marker_name_of_an_object_without_an_at_goal_is_checked_too() {
    // Every movable object of a problem with `at` goals gets a start marker, goal or not.
    let outcome = check(&with_at_goal(
        "\n    can c2 at (-0.3, 0.2, 0) m\n    spot start_c2 at (0.3, 0.3, 0) m",
    ));
    assert_eq!(codes(&outcome), ["lamp::check::conflict"], "{}", render(&outcome));
    assert!(render(&outcome).contains("`start_c2` where `c2` starts"), "{}", render(&outcome));
}

/// A loader whose one file exists but cannot be read.
struct LockedLoader;

impl lamp_lang::Loader for LockedLoader {
    fn read_to_string(&self, path: &Path) -> Result<String, String> {
        match path.to_str() {
            Some("scenes/locked.lamp") => Err("permission denied".to_string()),
            _ => common::loader().read_to_string(path),
        }
    }
    fn file_kind(&self, path: &Path) -> lamp_lang::FileKind {
        match path == Path::new("scenes/locked.lamp") {
            true => lamp_lang::FileKind::File,
            false => common::loader().file_kind(path),
        }
    }
    fn glob(&self, pattern: &Path) -> Vec<std::path::PathBuf> {
        common::loader().glob(pattern)
    }
    fn robot_names(
        &self,
        path: &Path,
        kind: lamp_spec::RobotKind,
    ) -> Result<Option<lamp_spec::RobotNames>, String> {
        common::loader().robot_names(path, kind)
    }
}

#[test]
fn check_unreadable_file() {
    let start = VALID.find("  scene {").expect("the valid spec has a scene");
    let end = start + VALID[start..].find("  }\n").expect("the scene block ends") + 4;
    let source = format!("{}  scene \"scenes/locked.lamp\"\n{}", &VALID[..start], &VALID[end..]);
    let outcome = lamp_lang::check_source("spec.lamp", &source, Path::new(""), &LockedLoader);
    let found = codes(&outcome);
    assert_eq!(found[0], "lamp::check::unreadable_file", "{}", render(&outcome));
    insta::assert_snapshot!("check_unreadable_file", render(&outcome));
}
