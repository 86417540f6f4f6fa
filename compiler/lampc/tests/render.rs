//! `lampc render` as a user runs it: a spec's problem scene, a trajectory file with its spec,
//! the default output path, and the diagnostics for what cannot be drawn.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use lamp_robot::{Mount, Robot};
use lamp_trajectory::{
    BodyDescription, RobotDescription, RobotState, Step, Trajectory, TrajectoryHeader,
};
use nalgebra::Isometry3;

fn domains() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains")
}

fn lampc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lampc"))
        .arg("render")
        .args(args)
        .env("NO_COLOR", "1")
        .output()
        .expect("lampc runs")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn path(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

/// A copy of the packing spec and its robots in a scratch folder (so the SVG lands beside it).
fn packing_copy(folder: &Path) -> PathBuf {
    std::fs::create_dir_all(folder.join("packing")).expect("a scratch folder");
    std::fs::create_dir_all(folder.join("robots")).expect("a scratch folder");
    std::fs::copy(domains().join("packing/packing.lamp"), folder.join("packing/packing.lamp"))
        .expect("the bundled spec copies");
    std::fs::copy(
        domains().join("robots/magnetic_gripper.urdf"),
        folder.join("robots/magnetic_gripper.urdf"),
    )
    .expect("the bundled robot copies");
    folder.join("packing/packing.lamp")
}

/// A three-step packing trajectory: the gripper carries can1 along x.
fn write_trajectory(file: &Path) {
    let robot =
        Robot::from_urdf_file(&domains().join("robots/magnetic_gripper.urdf"), Mount::Floating)
            .expect("the bundled robot loads");
    let header = TrajectoryHeader {
        domain: "packing".into(),
        seed: 1,
        provenance: Default::default(),
        bodies: vec![
            BodyDescription { name: "table1".into(), type_name: "table".into() },
            BodyDescription { name: "can1".into(), type_name: "can".into() },
        ],
        robots: vec![RobotDescription {
            name: "gripper".into(),
            coordinates: robot.coordinate_names().to_vec(),
            grippers: vec!["gripper".into()],
        }],
    };
    let steps = (0..3u32)
        .map(|i| {
            let x = 0.1 * f64::from(i);
            let mut q = robot.neutral_configuration();
            robot.mount().write_coordinates(&Isometry3::translation(x, 0.0, 0.4), &mut q);
            Step {
                time_nanoseconds: u64::from(i) * 1_000_000_000,
                body_poses: vec![Isometry3::identity(), Isometry3::translation(x, 0.0, 0.2)],
                robots: vec![RobotState { positions: q, held: vec![Some(1)] }],
            }
        })
        .collect();
    Trajectory { header, steps }.write_file(file).expect("the trajectory is written");
}

#[test]
fn a_spec_is_drawn_beside_itself_by_default() {
    let folder = tempfile::tempdir().unwrap();
    let spec = packing_copy(folder.path());
    let output = lampc(&[path(&spec), "--problem", "pack4_03"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let svg = std::fs::read_to_string(spec.with_extension("svg")).unwrap();
    assert!(svg.contains("packing \u{b7} pack4_03 (initial scene)"));
    assert!(svg.contains(">can4<") && svg.contains(">box1<"));
    assert!(String::from_utf8_lossy(&output.stdout).contains("drew problem `pack4_03`"));
}

#[test]
fn a_trajectory_is_drawn_with_its_spec() {
    let folder = tempfile::tempdir().unwrap();
    let spec = packing_copy(folder.path());
    let file = folder.path().join("run.mcap");
    write_trajectory(&file);
    let out = folder.path().join("picture.svg");
    let output = lampc(&[path(&file), "--spec", path(&spec), "--step", "1", "--out", path(&out)]);
    assert!(output.status.success(), "{}", stderr(&output));
    let svg = std::fs::read_to_string(&out).unwrap();
    assert!(svg.contains("packing \u{b7} step 1 of 0\u{2013}2 (t = 1.00 s)"), "{svg}");
    assert_eq!(svg.matches("<polyline").count(), 2, "the gripper path in both views");
    assert!(!folder.path().join("run.svg").exists());
}

#[test]
fn what_cannot_be_drawn_is_a_diagnostic_with_exit_code_one() {
    let folder = tempfile::tempdir().unwrap();
    let spec = packing_copy(folder.path());
    let file = folder.path().join("run.mcap");
    write_trajectory(&file);
    let out = folder.path().join("x.svg");
    let missing = folder.path().join("missing.mcap");
    let folder_named = folder.path().join("folder.mcap");
    std::fs::create_dir(&folder_named).unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec![path(&file)], "lamp::render::spec_required"),
        (
            vec![path(&file), "--spec", path(&spec), "--step", "7"],
            "lamp::render::step_out_of_range",
        ),
        (vec![path(&spec), "--problem", "pack9_99"], "lamp::render::unknown_problem"),
        (vec![path(&spec), "--step", "1"], "lamp::render::option"),
        (vec!["notes.txt"], "lamp::render::file_kind"),
        (vec![path(&missing), "--spec", path(&spec)], "lamp::render::read"),
        (vec![path(&folder_named), "--spec", path(&spec)], "it is a directory, not a file"),
    ];
    for (mut args, code) in cases {
        args.extend(["--out", path(&out)]);
        let output = lampc(&args);
        let message = stderr(&output);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {message}");
        assert!(message.contains(code), "{args:?}: {message}");
        assert!(!message.contains("panicked"), "{message}");
    }
    assert!(!out.exists(), "nothing is written when nothing is drawn");
}
