//! Numbers, sizes and folders a careless or hostile user gives `lampc`: every one is refused with
//! a message (exit 1 for a diagnostic, 2 for a flag that does not parse), never a panic, an
//! unbounded read or a silent deletion; thousands of repeated mistakes are checked quickly and
//! shown capped with a count.

mod common;
#[path = "../../build/tests/support/fixture.rs"]
mod fixture;

use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::{Duration, Instant};

use common::lampc;

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn path(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

fn packing() -> PathBuf {
    fixture::packing_spec_path()
}

/// The Packing spec with `from` replaced by `to`, written into `dir` (robot paths made absolute).
fn packing_with(dir: &Path, from: &str, to: &str) -> PathBuf {
    let robots = fixture::workspace_root().join("domains/robots/");
    let text = std::fs::read_to_string(packing()).expect("the bundled spec");
    assert!(text.contains(from), "`{from}` is in the Packing spec");
    let text = text.replace(from, to).replace("\"../robots/", &format!("\"{}/", robots.display()));
    let spec = dir.join("changed.lamp");
    std::fs::write(&spec, text).expect("a scratch folder");
    spec
}

/// Asserts a refusal with `code` and every one of `phrases` on stderr, and no panic.
fn assert_refused(output: &Output, code: i32, phrases: &[&str]) {
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(code), "{stderr}");
    for phrase in phrases {
        assert!(stderr.contains(phrase), "`{phrase}` in:\n{stderr}");
    }
    assert!(!stderr.contains("panicked") && !stderr.contains("internal error"), "{stderr}");
}

#[test]
fn time_limits_below_a_millisecond_or_beyond_a_week_are_refused_on_the_command_line() {
    let spec = packing();
    for timeout in ["1e308", "1e19", "604801", "-1", "0", "1e-300", "0.0009", "inf", "NaN"] {
        let flag = format!("--timeout={timeout}");
        let output = lampc(["solve", path(&spec), "--problem", "pack4_01", &flag]);
        assert_refused(
            &output,
            2,
            &["--timeout", "the value must be from 0.001 s to 604800 s (one week)"],
        );
    }
    let output = lampc(["solve", path(&spec), "--problem", "pack4_01", "--timeout", "soon"]);
    assert_refused(&output, 2, &["`soon` is not a number"]);
}

#[test]
fn plan_counts_are_refused_as_in_the_spec() {
    let spec = packing();
    for plans in ["0", "1001", "2.5", "-3"] {
        let flag = format!("--plans={plans}");
        let output = lampc(["solve", path(&spec), "--problem", "pack4_01", &flag]);
        assert_refused(&output, 2, &["--plans", "a whole number from 1 to 1000"]);
    }
}

#[test]
fn a_demonstration_count_of_zero_is_refused_and_deletes_nothing() {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let out = scratch.path().join("demos");
    std::fs::create_dir_all(&out).expect("a scratch folder");
    std::fs::write(out.join("packing_0000.mcap"), b"an earlier demonstration").expect("writable");
    for count in ["0", "10001", "1.5", "-2"] {
        let flag = format!("--count={count}");
        let output = lampc(["demos", path(&packing()), &flag, "--out", path(&out)]);
        assert_refused(&output, 2, &["--count", "a whole number from 1 to 10000"]);
    }
    let kept = std::fs::read(out.join("packing_0000.mcap")).expect("still there");
    assert_eq!(kept, b"an earlier demonstration");
}

#[test]
fn plugin_numbers_out_of_range_fail_the_check_with_the_range_not_the_solve_with_a_panic() {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let cases = [
        ("planner gbfs-ff { timeout 30 s }", "planner gbfs-ff { timeout -30 s }", "-30 s"),
        ("planner gbfs-ff { timeout 30 s }", "planner gbfs-ff { timeout 1e308 s }", "(one week)"),
        (
            "motion rrt-connect { resolution 0.01 rad }",
            "motion rrt-connect { resolution 0 rad }",
            "from 0.001 rad to 0.1 rad",
        ),
        (
            "motion rrt-connect { resolution 0.01 rad }",
            "motion rrt-connect { resolution 0.01 rad  timeout -1 s }",
            "-1 s",
        ),
        (
            "refiner gmm { samples 4  draws 2000 }",
            "refiner gmm { samples 0  draws 2000 }",
            "a whole number from 1 to 10000",
        ),
        (
            "refiner gmm { samples 4  draws 2000 }",
            "refiner gmm { samples 4  displacement -1 m }",
            "greater than 0 m",
        ),
        (
            "planner gbfs-ff { timeout 30 s }",
            "planner gbfs-ff { plans 0 }",
            "a whole number from 1 to 1000",
        ),
    ];
    for (from, to, phrase) in cases {
        let spec = packing_with(scratch.path(), from, to);
        let check = lampc(["check", path(&spec)]);
        assert_refused(&check, 1, &["lamp::check::out_of_range", phrase, "1 error(s)"]);
        // The solve checks the spec first, and stops there: no build is read, nothing panics.
        let solve = lampc(["solve", path(&spec), "--problem", "pack4_01"]);
        assert_refused(&solve, 1, &["lamp::check::out_of_range"]);
    }
    let spec = packing_with(scratch.path(), "refiner gmm { samples 4", "refiner gmm { sample 4");
    let check = lampc(["check", path(&spec)]);
    assert_refused(&check, 1, &["lamp::check::unknown_word", "Did you mean `samples`?"]);
}

#[cfg(unix)]
#[test]
fn devices_folders_and_huge_files_are_not_read_as_specs() {
    let started = Instant::now();
    let output = lampc(["check", "/dev/zero"]);
    assert_refused(
        &output,
        1,
        &["lamp::check::unreadable_file", "it is a character device, not a file"],
    );
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let output = lampc(["check", path(scratch.path())]);
    assert_refused(&output, 1, &["it is a directory, not a file"]);
    // A sparse file: 17 MiB long, nothing written.
    let huge = scratch.path().join("huge.lamp");
    std::fs::File::create(&huge).and_then(|file| file.set_len(17 << 20)).expect("a sparse file");
    let output = lampc(["check", path(&huge)]);
    assert_refused(
        &output,
        1,
        &["it is 17.0 MiB (17825792 bytes), more than the 16.0 MiB a spec file may be"],
    );
    assert!(started.elapsed() < Duration::from_secs(10), "refused without reading");
}

/// A spec declaring the type `can` `count` times.
fn duplicates(dir: &Path, count: usize) -> PathBuf {
    let mut text = String::from("domain many\nseed 1\n");
    for _ in 0..count {
        text.push_str("type can { movable sphere radius 1 m }\n");
    }
    let spec = dir.join("many.lamp");
    std::fs::write(&spec, text).expect("a scratch folder");
    spec
}

#[test]
fn thousands_of_one_mistake_are_checked_quickly_and_shown_twenty_times_with_a_count() {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let spec = duplicates(scratch.path(), 4_000);
    let started = Instant::now();
    let output = lampc(["check", path(&spec)]);
    let elapsed = started.elapsed();
    assert_refused(
        &output,
        1,
        &["… and 3979 more `lamp::resolve::duplicate_name` errors", "many.lamp: 3999 error(s)"],
    );
    let stderr = text(&output.stderr);
    assert_eq!(stderr.matches("lamp::resolve::duplicate_name\n").count(), 20, "{stderr}");
    // Generous: the quadratic renderer took 3 s on a debug build, and 40 s for 16,000.
    assert!(elapsed < Duration::from_secs(10), "{elapsed:?}");
}

#[cfg(unix)]
#[test]
fn odd_entries_of_the_demonstration_folder_are_named_never_silently_used_or_dropped() {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let demos = scratch.path().join("demos");
    fixture::write_packing_fixture(&demos, 40, 11);
    // A folder and a link to nothing that match `*.mcap` are skipped with a warning; a link to a
    // demonstration is followed.
    std::fs::create_dir(demos.join("folder.mcap")).expect("a folder");
    std::os::unix::fs::symlink(demos.join("gone.bin"), demos.join("gone.mcap")).expect("a link");
    std::os::unix::fs::symlink(demos.join("demo_000.mcap"), demos.join("link.mcap"))
        .expect("a link");
    let out = scratch.path().join("out");
    let build = |out: &Path| {
        lampc(["build", path(&packing()), "--demos", path(&demos), "--out", path(out)])
    };
    let output = build(&out);
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    assert!(output.status.success(), "{stdout}\n{stderr}");
    assert!(stderr.contains("folder.mcap is a directory, not a file; skipped"), "{stderr}");
    assert!(stderr.contains("gone.mcap is a symbolic link to nothing; skipped"), "{stderr}");
    assert!(stdout.contains("demonstrations  41 files"), "{stdout}");

    // A demonstration with no step, or of another domain, stops the build naming the file.
    let bytes = std::fs::read(demos.join("demo_001.mcap")).expect("a fixture file");
    let mut trajectory =
        lamp_trajectory::Trajectory::from_bytes(&bytes, "demo_001.mcap").expect("it reads");
    let steps = std::mem::take(&mut trajectory.steps);
    std::fs::write(demos.join("empty.mcap"), trajectory.to_bytes().expect("encodes"))
        .expect("writable");
    let output = build(&scratch.path().join("empty"));
    assert_refused(&output, 1, &["lamp::build::empty_demonstration", "empty.mcap"]);
    std::fs::remove_file(demos.join("empty.mcap")).expect("removable");

    trajectory.steps = steps;
    trajectory.header.domain = "cafe".into();
    std::fs::write(demos.join("cafe.mcap"), trajectory.to_bytes().expect("encodes"))
        .expect("writable");
    let output = build(&scratch.path().join("other"));
    assert_refused(&output, 1, &["lamp::build::other_domain", "cafe.mcap", "`cafe`", "`packing`"]);
}
