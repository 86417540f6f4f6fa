//! Helpers shared by the language tests: checking in memory and rendering like `lampc`.

// Each test binary uses a different subset of these helpers.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use lamp_lang::{CheckOutcome, MemoryLoader};

/// Files every test spec may refer to; the robot files come with their names.
pub fn loader() -> MemoryLoader {
    MemoryLoader::new([
        ("robots/gripper.urdf", "<robot name=\"g\"/>"),
        ("robots/arm.urdf", "<robot name=\"a\"/>"),
        ("meshes/bowl.stl", "solid bowl"),
        ("demos/a.mcap", ""),
        ("scenes/pack.lamp", "table t1 at (0, 0, 0) m\ncan c9 at (0.1, 0, 0) m\n"),
        ("scenes/broken.lamp", "table t1 at (0, 0) m\n"),
    ])
    .with_robot(
        "robots/gripper.urdf",
        robot_names(
            &["gripper_link", "left_finger", "right_finger"],
            &["left_finger_joint", "right_finger_joint"],
            &["base_x", "base_y", "base_z", "base_rx", "base_ry", "base_rz"],
        ),
    )
    .with_robot(
        "robots/arm.urdf",
        robot_names(
            &["base_link", "shoulder_link", "forearm_link", "gripper_link"],
            &["shoulder_joint", "elbow_joint", "wrist_fixed_joint"],
            &[],
        ),
    )
}

/// A robot file's names: links, joints, and the coordinates of the mount and the moving joints
/// (every joint but those named `…_fixed_joint` moves in one coordinate of its own name).
fn robot_names(links: &[&str], joints: &[&str], mount: &[&str]) -> lamp_spec::RobotNames {
    let owned = |names: &[&str]| names.iter().map(ToString::to_string).collect::<Vec<_>>();
    let moving = joints.iter().filter(|joint| !joint.ends_with("_fixed_joint"));
    lamp_spec::RobotNames {
        links: owned(links),
        joints: owned(joints),
        coordinates: mount.iter().chain(moving).map(ToString::to_string).collect(),
    }
}

/// Checks `text` as `spec.lamp` in the loader's root folder.
pub fn check(text: &str) -> CheckOutcome {
    lamp_lang::check_source("spec.lamp", text, Path::new(""), &loader())
}

/// Renders every diagnostic without colour at a fixed width, as `lampc check` does on a pipe.
pub fn render(outcome: &CheckOutcome) -> String {
    let handler =
        miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
            .with_width(100);
    let mut out = String::new();
    for diagnostic in &outcome.diagnostics {
        handler
            .render_report(&mut out, &diagnostic.with_source(&outcome.sources))
            .expect("rendering into a String cannot fail");
        out.push('\n');
    }
    out
}

/// The codes of an outcome's diagnostics, in order.
pub fn codes(outcome: &CheckOutcome) -> Vec<String> {
    outcome.diagnostics.iter().map(|d| d.code()).collect()
}

/// The workspace's `domains` folder.
pub fn domains_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains")
}

/// A minimal valid spec to which a test appends or in which it replaces text.
pub const VALID: &str = r#"domain test
seed 7

robot gripper {
  urdf "robots/gripper.urdf"
  kind free_flying
  part gripper = link "gripper_link"
  grab distance 0.19 m .. 0.22 m
}

type table { static world  box size (0.9, 0.9, 0.05) m at (0, 0, -0.025) m }
type surface { static  box size (0.15, 0.15, 0.01) m }
type can { movable  cylinder radius 0.0325 m height 0.15 m at (0, 0, 0.075) m }

demonstrations {
  simulate packing { count 20  cut 0.5  objects 1  seed 3 }
}

learn {
  threshold 0.5
  pair gripper can { position bins (9, 9, 9) range (0.3, 0.3, 0.3) m }
}

relation in_box(can, surface) = region of can in surface containing (0, 0, 0.001) m

problem p1 {
  scene {
    table t1 at (0, 0, 0) m
    surface box1 at (0.2, 0, 0) m rpy (0, 0, 30) deg
    can c1 at (-0.2, 0, 0) m
    robot gripper at (0, 0, 0.5) m rpy (180, 0, 0) deg
  }
  goal {
    in_box(c1, box1)
    surface_can_1(box1, c1)
  }
}
"#;

/// The `simulate` line of [`VALID`], where a test writes an option.
pub const SIMULATE: &str = "simulate packing { count 20  cut 0.5  objects 1  seed 3 }";

/// [`VALID`] with `extra` written inside the `simulate` block, after the other options.
pub fn with_simulate_option(extra: &str) -> String {
    assert!(VALID.contains(SIMULATE), "the valid spec simulates packing");
    let simulate = SIMULATE.replace(" }", &format!("  {extra} }}"));
    VALID.replacen(SIMULATE, &simulate, 1)
}

/// The codes and the text each diagnostic points at.
pub fn found(source: &str, outcome: &CheckOutcome) -> Vec<(String, String)> {
    outcome.diagnostics.iter().map(|d| (d.code(), source[d.range()].to_string())).collect()
}

/// The one simulated source of `source`, checked (which must accept it).
pub fn simulated_source(source: &str) -> lamp_spec::DemoSource {
    let outcome = check(source);
    let rendered = render(&outcome);
    let spec = outcome.spec.unwrap_or_else(|| panic!("accepted:\n{rendered}"));
    match <[_; 1]>::try_from(spec.demonstrations) {
        Ok([source @ lamp_spec::DemoSource::Simulated { .. }]) => source,
        Ok(other) => panic!("one simulated source, not {other:?}"),
        Err(other) => panic!("one simulated source, not {other:?}"),
    }
}

/// [`VALID`] with `extra` in its `simulate` block, checked: asserts one diagnostic per
/// `(code, text)` and no spec; returns the rendering.
pub fn refused_simulate_option(extra: &str, expected: &[(&str, &str)]) -> String {
    let source = with_simulate_option(extra);
    let outcome = check(&source);
    let expected: Vec<(String, String)> =
        expected.iter().map(|(code, text)| (code.to_string(), text.to_string())).collect();
    assert_eq!(found(&source, &outcome), expected, "{extra}:\n{}", render(&outcome));
    assert!(outcome.spec.is_none(), "{extra}: a spec with errors has no Spec");
    render(&outcome)
}
