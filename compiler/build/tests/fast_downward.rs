//! Oracle: Fast Downward's translator accepts the domain learned from real Packing demonstrations
//! and the written problems unchanged.
//!
//! Skips with a message when `python3 -m fast_downward.translate` (pip `fast-downward-translate`)
//! is missing, and fails instead when `LAMP_REQUIRE_ORACLES=1`.

mod support;

use std::path::Path;

use support::{PACKING_BUILD, artifact};

/// Runs the translator; returns the SAS text.
fn translate(directory: &Path, name: &str, domain: &str, problem: &str) -> String {
    let domain_path = directory.join(format!("{name}-domain.pddl"));
    let problem_path = directory.join(format!("{name}-problem.pddl"));
    let sas_path = directory.join(format!("{name}.sas"));
    std::fs::write(&domain_path, domain).expect("write domain");
    std::fs::write(&problem_path, problem).expect("write problem");
    let output = std::process::Command::new("python3")
        .args(["-m", "fast_downward.translate"])
        .arg(&domain_path)
        .arg(&problem_path)
        .arg("--sas-file")
        .arg(&sas_path)
        .output()
        .expect("python3 runs");
    assert!(
        output.status.success(),
        "{name}: translator failed\n{}\n{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    let sas = std::fs::read_to_string(&sas_path).expect("a SAS file");
    assert!(sas.starts_with("begin_version"), "{name}: not a SAS file");
    sas
}

#[test]
fn fast_downward_translator_accepts_the_domain_and_problems() {
    if !lamp_test_support::python_oracle("fast_downward.translate", "fast-downward-translate") {
        return;
    }
    let directory = tempfile::tempdir().expect("a scratch directory");
    let (_, artifacts) = &*PACKING_BUILD;
    let domain = artifact(artifacts, "domain.pddl");
    // The bundled four-can problem is accepted and not proved unsolvable: with `clear off` on
    // the box–can pair, every learned action grounds for each of the four cans (with clear
    // relations on the box the translator would find the goal mutex: one can per box).
    let sas =
        translate(directory.path(), "pack4", domain, artifact(artifacts, "problems/pack4_01.pddl"));
    let operators = sas.matches("begin_operator").count();
    assert!(
        operators >= 4 * 5,
        "every action grounds for the four cans, got {operators} operators"
    );
}
