//! The fuzz corpora and crash reproducers, replayed on stable: every file under
//! `fuzz/corpus/<target>/` and `fuzz/regressions/<target>/` goes through the target's entry
//! function (the same one `cargo fuzz` runs), which panics when a reader breaks its contract.

use std::fs;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use lamp_fuzz_entries::{Entry, TARGETS};

/// The folders, under `fuzz/`, that hold one subfolder of inputs per target.
const INPUT_FOLDERS: [&str; 2] = ["corpus", "regressions"];

/// `fuzz/` of the workspace (this test's own manifest folder is `tests/`).
fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz")
}

/// The files of a folder, sorted by name; none when the folder does not exist.
fn files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = fs::read_dir(dir) else { return Vec::new() };
    let mut files: Vec<PathBuf> =
        entries.map(|entry| entry.expect("a readable folder entry").path()).collect();
    files.sort();
    for file in &files {
        assert!(file.is_file(), "{} is not a file; inputs are flat files", file.display());
    }
    files
}

/// Runs every input of a target; returns how many ran, and fails naming every input that panics.
fn replay(target: &str) -> [usize; 2] {
    let entry: Entry = TARGETS
        .iter()
        .find(|(name, _)| *name == target)
        .map(|(_, entry)| *entry)
        .expect("a target of lamp-fuzz-entries");
    let mut failures = Vec::new();
    let counts = INPUT_FOLDERS.map(|folder| {
        let inputs = files(&fuzz_dir().join(folder).join(target));
        for input in &inputs {
            let data = fs::read(input).expect("a readable input");
            if catch_unwind(AssertUnwindSafe(|| entry(&data))).is_err() {
                failures.push(input.display().to_string());
            }
        }
        inputs.len()
    });
    assert!(failures.is_empty(), "inputs that panic (message above):\n{}", failures.join("\n"));
    counts
}

/// Replays a target whose corpus must not be empty: an empty one would replay nothing.
fn replay_with_corpus(target: &str) {
    let [corpus, _] = replay(target);
    assert!(corpus > 0, "fuzz/corpus/{target}/ is empty or missing");
}

#[test]
fn check_corpus_and_regressions_replay() {
    replay_with_corpus("check");
}

#[test]
fn pddl_corpus_and_regressions_replay() {
    replay_with_corpus("pddl");
}

#[test]
fn trajectory_corpus_and_regressions_replay() {
    replay_with_corpus("trajectory");
}

#[test]
fn samplers_corpus_and_regressions_replay() {
    replay_with_corpus("samplers");
}

#[test]
fn every_input_folder_belongs_to_a_target_and_every_target_is_replayed() {
    let known: Vec<&str> = TARGETS.iter().map(|(name, _)| *name).collect();
    assert_eq!(known, ["check", "pddl", "trajectory", "samplers"], "one test above per target");
    let mut strays = Vec::new();
    for folder in INPUT_FOLDERS {
        let Ok(entries) = fs::read_dir(fuzz_dir().join(folder)) else { continue };
        for entry in entries {
            let name = entry.expect("a readable folder entry").file_name();
            if !known.iter().any(|target| name.to_str() == Some(target)) {
                strays.push(format!("fuzz/{folder}/{}", name.to_string_lossy()));
            }
        }
    }
    assert!(strays.is_empty(), "input folders no test replays: {strays:?}");
}
