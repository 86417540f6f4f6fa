//! Diagnostics that point at the cause, as `lampc` prints them: paths that are not files, link
//! names the URDF does not define, a byte order mark, initial scenes the solver cannot start from,
//! PDDL that does not parse, and plugin libraries the dynamic loader refuses.

mod common;
#[path = "../../build/tests/support/fixture.rs"]
mod fixture;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::lampc;

const DEMOS: usize = 40;
const SEED: u64 = 11;

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A copy of the Packing spec and its robots in `scratch`, its text changed by `edit`.
fn packing_copy(scratch: &Path, edit: impl FnOnce(&str) -> String) -> PathBuf {
    let root = fixture::workspace_root().join("domains");
    let (packing, robots) = (scratch.join("packing"), scratch.join("robots"));
    std::fs::create_dir_all(&packing).expect("a folder");
    std::fs::create_dir_all(&robots).expect("a folder");
    let robot = "magnetic_gripper.urdf";
    std::fs::copy(root.join("robots").join(robot), robots.join(robot)).expect("copies");
    let text = std::fs::read_to_string(root.join("packing/packing.lamp")).expect("the spec");
    let spec = packing.join("packing.lamp");
    std::fs::write(&spec, edit(&text)).expect("writes");
    spec
}

/// `lampc check` on a changed copy of Packing: its exit code and what it printed.
fn check(edit: impl FnOnce(&str) -> String) -> (Option<i32>, String) {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let spec = packing_copy(scratch.path(), edit);
    let output = lampc(["check".as_ref(), spec.as_os_str()]);
    (output.status.code(), stderr(&output))
}

fn replaced(from: &'static str, to: &'static str) -> impl FnOnce(&str) -> String {
    move |text: &str| {
        assert!(text.contains(from), "`{from}` is in the Packing spec");
        text.replacen(from, to, 1)
    }
}

#[test]
fn a_urdf_that_is_a_device_says_what_it_is() {
    let (code, text) = check(replaced("\"../robots/magnetic_gripper.urdf\"", "\"/dev/zero\""));
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("lamp::check::not_a_file"), "{text}");
    assert!(text.contains("`/dev/zero` is a character device, not a file"), "{text}");
    assert!(text.contains("packing.lamp:8:8"), "{text}");
    assert!(!text.contains("does not exist"), "{text}");
}

#[test]
fn a_urdf_that_is_a_folder_says_what_it_is() {
    let (code, text) = check(replaced("\"../robots/magnetic_gripper.urdf\"", "\"../robots\""));
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("`../robots` is a directory, not a file"), "{text}");
}

#[test]
fn a_planner_library_that_is_a_device_says_what_it_is() {
    let (code, text) = check(replaced("planner gbfs-ff { timeout 30 s }", "planner \"/dev/null\""));
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("`/dev/null` is a character device, not a file"), "{text}");
    assert!(text.contains("The plugin library path must name a regular file"), "{text}");
}

#[test]
fn a_link_the_urdf_does_not_define_fails_the_check_where_it_is_named() {
    let (code, text) = check(replaced("link \"gripper_link\"", "link \"nope_link\""));
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("lamp::resolve::unknown_link"), "{text}");
    assert!(text.contains("`../robots/magnetic_gripper.urdf` has no link `nope_link`"), "{text}");
    assert!(text.contains("packing.lamp:10:23"), "{text}");
    assert!(text.contains("The links of `../robots/magnetic_gripper.urdf` are `gripper_link`."));
}

#[test]
fn a_urdf_that_does_not_load_is_reported_at_its_path_with_the_reason() {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let spec = packing_copy(scratch.path(), |text| text.to_string());
    std::fs::write(scratch.path().join("robots/magnetic_gripper.urdf"), "<robot>").expect("writes");
    let output = lampc(["check".as_ref(), spec.as_os_str()]);
    let text = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{text}");
    assert!(text.contains("lamp::check::robot_file"), "{text}");
    assert!(text.contains("magnetic_gripper.urdf: invalid URDF"), "{text}");
    assert!(text.contains("packing.lamp:8:8"), "{text}");
}

#[test]
fn a_spec_starting_with_a_byte_order_mark_checks() {
    let (code, text) = check(|text| format!("\u{FEFF}{text}"));
    assert_eq!(code, Some(0), "{text}");
    assert!(text.contains("ok (domain `packing`"), "{text}");
}

/// `lampc build` on a changed copy of Packing whose demonstrations are never reached.
fn build_refused(edit: impl FnOnce(&str) -> String) -> String {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let spec = packing_copy(scratch.path(), edit);
    let out = scratch.path().join("build");
    let output = lampc(["build".as_ref(), spec.as_os_str(), "--out".as_ref(), out.as_os_str()]);
    let text = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{text}");
    assert!(!text.contains("no_demonstrations"), "refused before looking for any: {text}");
    assert!(
        text.contains("in the problems' initial scenes, which the solver cannot start from; no model was written"),
        "{text}"
    );
    assert!(!out.exists(), "nothing is written");
    text
}

#[test]
fn a_build_refuses_an_object_resting_exactly_on_the_table() {
    let text = build_refused(replaced(
        "can can1 at (-0.25, -0.2, 0.001) m",
        "can can1 at (-0.25, -0.2, 0) m",
    ));
    assert!(text.contains("lampc build: 1 finding(s) in the problems' initial scenes"), "{text}");
    assert!(text.contains("lamp::build::scene_contact"), "{text}");
    assert!(text.contains("problem `pack4_01`: `table1` and `can1` touch or overlap"), "{text}");
    // Both bodies at their lines in the scene.
    assert!(text.contains("    can can1 at (-0.25, -0.2, 0) m"), "{text}");
    assert!(text.contains("`can1` is placed here"), "{text}");
    assert!(text.contains("`table1` is placed here"), "{text}");
}

/// A can 2.5 m above the table rests on nothing: `check` refuses it at its line in the scene,
/// and so do `build` and `solve` (before looking at any build), instead of a build that learns
/// and a solve that "solves" a problem whose start cannot be.
#[test]
fn an_object_in_the_air_is_refused_at_its_line_by_check_build_and_solve() {
    let floating =
        || replaced("can can1 at (-0.25, -0.2, 0.001) m", "can can1 at (-0.25, -0.2, 2.5) m");
    let expected = [
        "lamp::build::scene_unsupported",
        "problem `pack4_01`: `can1` cannot rest where the scene places it: `can1` would drop 2499.0 mm onto `table1`",
        "packing.lamp:60:5",
        "    can can1 at (-0.25, -0.2, 2.5) m",
        "`can1` is placed here",
        "help: An object must start standing on something",
    ];
    let (code, text) = check(floating());
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("packing.lamp: 1 error(s)"), "{text}");
    let text_of_build = build_refused(floating());
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let spec = packing_copy(scratch.path(), floating());
    let empty_build = scratch.path().join("no-build");
    let output = lampc([
        "solve".as_ref(),
        spec.as_os_str(),
        "--problem".as_ref(),
        "pack4_01".as_ref(),
        "--build".as_ref(),
        empty_build.as_os_str(),
    ]);
    let text_of_solve = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{text_of_solve}");
    assert!(!text_of_solve.contains("no_build"), "the scene is judged first: {text_of_solve}");
    assert!(text_of_solve.contains("lampc solve: failed; no solution files were written"));
    for text in [&text, &text_of_build, &text_of_solve] {
        for expected in expected {
            assert!(text.contains(expected), "`{expected}` in:\n{text}");
        }
    }
}

#[test]
fn a_build_refuses_an_object_out_of_any_plausible_range() {
    let text = build_refused(replaced(
        "can can1 at (-0.25, -0.2, 0.001) m",
        "can can1 at (1e308, -0.2, 0.001) m",
    ));
    assert!(text.contains("lamp::build::scene_range"), "{text}");
    assert!(
        text.contains(
            "problem `pack4_01`: object `can1` is placed at (1e308, -0.2, 0.001) m, farther than 1000 m from the origin"
        ),
        "{text}"
    );
}

#[test]
fn a_build_refuses_a_robot_starting_inside_an_object() {
    let text = build_refused(replaced(
        "robot gripper at (0, 0, 0.45) m rpy (180, 0, 0) deg",
        "robot gripper at (-0.25, -0.2, 0.12) m rpy (180, 0, 0) deg",
    ));
    assert!(text.contains("lamp::build::robot_start_collision"), "{text}");
    assert!(text.contains("`gripper` is placed here"), "{text}");
    assert!(
        text.contains("problem `pack4_01`: robot `gripper` starts in collision: link `gripper_link` touches `can1`"),
        "{text}"
    );
}

/// A model built from the fixture demonstrations: (scratch folder, build folder).
fn built_model() -> (tempfile::TempDir, PathBuf) {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let demos = scratch.path().join("demos");
    fixture::write_packing_fixture(&demos, DEMOS, SEED);
    let build = scratch.path().join("build");
    let spec = fixture::packing_spec_path();
    let output = lampc([
        "build".as_ref(),
        spec.as_os_str(),
        "--demos".as_ref(),
        demos.as_os_str(),
        "--out".as_ref(),
        build.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    (scratch, build)
}

fn solve(build: &Path, out: &Path, more: &[&str]) -> Output {
    let spec = fixture::packing_spec_path();
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "solve".as_ref(),
        spec.as_os_str(),
        "--problem".as_ref(),
        "pack4_01".as_ref(),
        "--build".as_ref(),
        build.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ];
    args.extend(more.iter().map(std::ffi::OsStr::new));
    lampc(args)
}

#[test]
fn solve_names_the_pddl_file_line_and_column_and_the_plugin_loader_reason() {
    let (scratch, build) = built_model();
    let out = scratch.path().join("solution");

    // A parenthesis too many after the first precondition atom of the domain.
    let domain = build.join("model/domain.pddl");
    let text = std::fs::read_to_string(&domain).expect("the domain");
    let (index, line) = text
        .lines()
        .enumerate()
        .skip_while(|(_, line)| !line.contains(":precondition"))
        .find(|(_, line)| line.trim_start().starts_with("(clear_"))
        .expect("an action with a clear precondition");
    let column = line.len() + 1;
    let broken = text.replacen(line, &format!("{line})"), 1);
    std::fs::write(&domain, broken).expect("edits");
    let output = solve(&build, &out, &["--unchecked-build"]);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert!(message.contains("lamp::solve::pddl"), "{message}");
    assert!(message.contains("lamp::pddl::syntax"), "{message}");
    let place = format!("{}:{}:{column}", domain.display(), index + 1);
    assert!(
        message.contains(&format!(
            "the domain does not parse: 1 PDDL error(s) in {}",
            domain.display()
        ))
    );
    assert!(message.contains(&place), "expected {place} in:\n{message}");
    assert!(!out.exists(), "nothing is written");
    std::fs::write(&domain, text).expect("restores");

    // A planner library that is a text file: the dynamic loader's reason is shown.
    let library = scratch.path().join("libplanner.so");
    std::fs::write(&library, "not a shared library, only text\n".repeat(8)).expect("writes");
    let output = solve(&build, &out, &["--planner", library.to_str().expect("a UTF-8 path")]);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert!(message.contains("dlopen failed: "), "{message}");
    if cfg!(all(target_os = "linux", target_env = "gnu")) {
        assert!(message.contains("libplanner.so: invalid ELF header"), "{message}");
    }
    assert!(!out.exists(), "nothing is written");
}
