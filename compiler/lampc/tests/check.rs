//! `lampc check` as a user runs it: exit codes and what it prints.

use std::path::Path;
use std::process::Command;

fn lampc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lampc"))
}

fn domains() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains")
}

#[test]
fn bundled_specs_check_cleanly_with_exit_code_zero() {
    for domain in ["packing", "cafe", "keva", "jenga", "dinner"] {
        let spec = domains().join(domain).join(format!("{domain}.lamp"));
        let output =
            lampc().arg("check").arg(&spec).env("NO_COLOR", "1").output().expect("lampc runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{domain}: {stderr}");
        assert!(stderr.contains(&format!("ok (domain `{domain}`")), "{domain}: {stderr}");
    }
}

#[test]
fn a_broken_spec_exits_with_one_and_names_file_line_and_code() {
    let folder = tempfile::tempdir().expect("a scratch folder");
    let spec = folder.path().join("broken.lamp");
    std::fs::write(
        &spec,
        "domain broken\nseed 1\ntype can { movable cylinder radius 3 height 1 m }\n",
    )
    .expect("writable scratch folder");
    let output = lampc().arg("check").arg(&spec).env("NO_COLOR", "1").output().expect("lampc runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("lamp::check::unit_required"), "{stderr}");
    assert!(stderr.contains("broken.lamp:3:"), "{stderr}");
    assert!(stderr.contains("1 error(s)"), "{stderr}");
}

#[test]
fn a_missing_spec_file_is_a_diagnostic_not_a_panic() {
    let output = lampc().args(["check", "no/such/spec.lamp"]).output().expect("lampc runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("lamp::check::unreadable_file"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn solve_without_a_build_says_how_to_make_one() {
    let spec = domains().join("packing/packing.lamp");
    let empty = tempfile::tempdir().expect("a scratch directory");
    let output = lampc()
        .arg("solve")
        .arg(&spec)
        .args(["--problem", "pack4_01", "--build"])
        .arg(empty.path())
        .output()
        .expect("lampc runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("domain.pddl") && stderr.contains("lampc build"), "{stderr}");
    assert!(std::fs::read_dir(empty.path()).expect("readable").next().is_none(), "nothing written");
}
