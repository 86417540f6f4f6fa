//! `lampc demos` as a user runs it: three Packing demonstrations into a scratch folder that
//! read back as demonstration files with the standard channels viewers read, the folder written
//! whole and by one process at a time, and the diagnostic for a spec with no simulator.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use lamp_trajectory::TrajectoryReader;

fn domains() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains")
}

fn lampc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lampc"))
        .arg("demos")
        .args(args)
        .env("NO_COLOR", "1")
        .output()
        .expect("lampc runs")
}

fn path(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

#[test]
fn three_packing_demonstrations_are_written_and_read_back() {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let out = scratch.path().join("demos");
    // The folder is replaced whole: a file of an earlier, larger run does not stay behind.
    std::fs::create_dir_all(&out).expect("a scratch folder");
    std::fs::write(out.join("packing_0007.mcap"), b"stale").expect("writable");
    let spec = domains().join("packing/packing.lamp");
    let output = lampc(&[path(&spec), "--count", "3", "--seed", "4", "--out", path(&out)]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{}\n{stdout}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("3 packing demonstrations"), "{stdout}");

    let mut names: Vec<String> = std::fs::read_dir(&out)
        .expect("the folder exists")
        .map(|entry| entry.expect("an entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["packing_0000.mcap", "packing_0001.mcap", "packing_0002.mcap"]);
    for (index, name) in names.iter().enumerate() {
        let reader = TrajectoryReader::open(out.join(name)).expect("a demonstration file");
        let header = reader.header().clone();
        assert_eq!(header.domain, "packing");
        assert_eq!(header.seed, 4);
        assert_eq!(header.provenance["demo_index"], index.to_string());
        let trajectory = reader.read_all().expect("every step reads");
        assert!(trajectory.steps.len() > 10, "{name}: {} steps", trajectory.steps.len());
        let bytes = std::fs::read(out.join(name)).expect("readable");
        common::assert_viewer_channels(&bytes, name);
    }

    // The same command again gives the same bytes.
    let first = std::fs::read(out.join("packing_0001.mcap")).expect("readable");
    let again = lampc(&[path(&spec), "--count", "3", "--seed", "4", "--out", path(&out)]);
    assert!(again.status.success());
    assert_eq!(std::fs::read(out.join("packing_0001.mcap")).expect("readable"), first);
}

/// A folder is written by one `lampc demos` at a time, and only one that holds nothing but its
/// demonstrations is replaced: a user's own file is never deleted with it.
#[test]
fn a_folder_being_written_or_holding_other_files_is_refused_and_left_as_it_is() {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let spec = domains().join("packing/packing.lamp");
    let out = scratch.path().join("demos");
    std::fs::create_dir_all(&out).expect("a scratch folder");
    std::fs::write(out.join("packing_0000.mcap"), b"earlier").expect("writable");

    // Another process writing: its lock beside the folder is held.
    let lock = std::fs::File::create(scratch.path().join(".demos.lock")).expect("a lock file");
    lock.lock().expect("locked");
    let output = lampc(&[path(&spec), "--count", "2", "--out", path(&out)]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("lamp::output::locked"), "{stderr}");
    assert!(stderr.contains("is being written by another lampc"), "{stderr}");
    drop(lock);
    assert_eq!(std::fs::read(out.join("packing_0000.mcap")).expect("kept"), b"earlier");

    std::fs::write(out.join("notes.txt"), b"mine").expect("writable");
    let output = lampc(&[path(&spec), "--count", "2", "--out", path(&out)]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("lamp::output::occupied"), "{stderr}");
    assert!(stderr.contains("it holds notes.txt, which `lampc demos` did not write"), "{stderr}");
    assert_eq!(std::fs::read(out.join("notes.txt")).expect("kept"), b"mine");
    assert_eq!(std::fs::read(out.join("packing_0000.mcap")).expect("kept"), b"earlier");
    let mut names: Vec<String> = std::fs::read_dir(scratch.path())
        .expect("readable")
        .flatten()
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, [".demos.lock", "demos"], "no staging folder is left");
}

#[test]
fn a_spec_without_a_simulator_is_a_diagnostic() {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let text = std::fs::read_to_string(domains().join("packing/packing.lamp")).expect("readable");
    let text = text.replace(
        "simulate packing { count 200  cut 0.5  objects 1  seed 11  rate 50 Hz }",
        "files \"recorded.mcap\"",
    );
    assert!(text.contains("files \"recorded.mcap\""));
    let folder = scratch.path().join("packing");
    std::fs::create_dir_all(&folder).expect("a scratch folder");
    std::fs::create_dir_all(scratch.path().join("robots")).expect("a scratch folder");
    std::fs::copy(
        domains().join("robots/magnetic_gripper.urdf"),
        scratch.path().join("robots/magnetic_gripper.urdf"),
    )
    .expect("the robot copies");
    std::fs::write(folder.join("packing.lamp"), text).expect("writable");
    std::fs::write(folder.join("recorded.mcap"), b"").expect("writable");
    let output = lampc(&[path(&folder.join("packing.lamp"))]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("lamp::demos::no_simulator"), "{stderr}");
    assert!(stderr.contains("simulate packing"), "{stderr}");
    assert!(!folder.join("build").exists(), "nothing written");
}
