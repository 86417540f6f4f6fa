//! A failed solve explains itself in the scene's terms, as a user meets it: where the plans
//! ended, what was refused there, and help that follows from it. Each case is a copy of a bundled
//! spec with problems added (a structure out of the YuMi's reach, planks too close together to
//! grasp, six cans for a box that holds four, a goal that contradicts itself). The explanations
//! are pinned as snapshots, with the counts, which any change to the search moves, written as N.

use std::path::{Path, PathBuf};
use std::process::Command;

fn lampc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lampc"))
}

fn domains() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains")
}

/// A bundled domain copied into a scratch folder with its text changed by `edit`, its
/// demonstrations generated and its model built there.
struct Prepared {
    _scratch: tempfile::TempDir,
    spec: PathBuf,
}

fn prepared(domain: &str, edit: impl FnOnce(String) -> String) -> Prepared {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let robots = domains().join("robots");
    let text = std::fs::read_to_string(domains().join(domain).join(format!("{domain}.lamp")))
        .expect("the bundled spec")
        .replace("\"../robots/", &format!("\"{}/", robots.display()));
    let spec = scratch.path().join(format!("{domain}.lamp"));
    std::fs::write(&spec, edit(text)).expect("writes the spec");
    let demos = scratch.path().join("demos");
    for arguments in [["demos", "--out"], ["build", "--demos"]] {
        let mut command = lampc();
        command.arg(arguments[0]).arg(&spec).arg(arguments[1]).arg(&demos);
        let output = command.output().expect("lampc runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{command:?}:\n{stderr}");
    }
    Prepared { _scratch: scratch, spec }
}

/// `text` with `from` replaced once, which it must hold.
fn replaced(text: String, from: &str, to: &str) -> String {
    assert!(text.contains(from), "the spec holds `{from}`");
    text.replacen(from, to, 1)
}

/// The problem `name` of `text` copied as `copy`, its text changed by `edit`, added at the end.
fn with_copy(text: String, name: &str, copy: &str, edit: impl FnOnce(String) -> String) -> String {
    let start = text.find(&format!("problem {name} {{")).expect("the problem is in the spec");
    let end = start + text[start..].find("\n}\n").expect("the problem ends") + 3;
    let problem = edit(text[start..end].replacen(name, copy, 1));
    format!("{text}\n{problem}")
}

/// What `lampc solve` printed about its failure (the diagnostic, unwrapped), with every count
/// of attempts, plans, candidates and shares written as N.
fn explanation(spec: &Path, problem: &str, more: &[&str]) -> String {
    let output = lampc()
        .arg("solve")
        .arg(spec)
        .args(["--problem", problem])
        .args(more)
        .env("NO_COLOR", "1")
        .env("COLUMNS", "10000")
        .output()
        .expect("lampc runs");
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    let start = stderr.find("lamp::solve::").expect("a solve diagnostic");
    let end = stderr.find("lampc solve: failed").expect("the last line");
    counts_as_n(stderr[start..end].trim_end())
}

fn counts_as_n(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find(|c: char| c.is_ascii_digit()) {
        let digits = rest[at..].find(|c: char| !c.is_ascii_digit()).map_or(rest.len(), |n| at + n);
        let (before, number, after) = (&rest[..at], &rest[at..digits], &rest[digits..]);
        out.push_str(before);
        let counted = before.ends_with('×')
            || [" %", " plan(s) tried", " candidates"].iter().any(|unit| after.starts_with(unit));
        out.push_str(if counted { "N" } else { number });
        rest = after;
    }
    out.push_str(rest);
    out
}

#[test]
fn counts_are_written_as_n_and_nothing_else_is() {
    assert_eq!(
        counts_as_n(
            "(20 plan(s) tried, 400 candidates, deepest step 3 of 14; ×27100 (481 mm) 66 %"
        ),
        "(N plan(s) tried, N candidates, deepest step 3 of 14; ×N (481 mm) N %"
    );
}

/// Keva with two problems of three planks: the pi tower's marker 0.75 m out, beyond what the
/// YuMi reaches, and the planks laid 3 mm apart, too close for its fingers. Few draws per step
/// and one plan per round keep the failing searches to seconds.
#[test]
fn keva_failures_name_the_unreachable_target_and_the_planks_in_the_way() {
    let keva = prepared("keva", |text| {
        let text = replaced(
            text,
            "planner topk { plans 50 }",
            "planner topk { plans 50 }\n  refiner gmm { draws 100 }",
        );
        let text = with_copy(text, "pi_tower_3", "far_pi_3", |problem| {
            replaced(
                problem,
                "droparea area1 at (-0.05, 0.1, 0) m",
                "droparea area1 at (0.75, 0.1, 0) m",
            )
        });
        with_copy(text, "pi_tower_3", "crowded_pi_3", |problem| {
            let problem = replaced(problem, "(-0.35, -0.065, 0.001)", "(-0.35, -0.026, 0.001)");
            replaced(problem, "(-0.35, 0.065, 0.001)", "(-0.35, 0.026, 0.001)")
        })
    });
    let far = explanation(&keva.spec, "far_pi_3", &["--plans", "1"]);
    assert!(far.contains("cannot reach where the step puts"), "{far}");
    insta::assert_snapshot!("keva_target_out_of_reach", far);
    let crowded = explanation(&keva.spec, "crowded_pi_3", &["--plans", "1"]);
    assert!(crowded.contains("`p2` and `p3` are in the way"), "{crowded}");
    insta::assert_snapshot!("keva_planks_in_the_way", crowded);
}

/// Packing with six cans for its box that holds four, and a goal asking for a can in the box
/// and in none of its regions at once.
#[test]
fn packing_failures_name_the_cans_in_the_box_and_the_contradicting_goal() {
    let packing = prepared("packing", |text| {
        let text = replaced(text, "draws 2000", "draws 100");
        let text = with_copy(text, "pack4_01", "pack6_01", |problem| {
            let problem = replaced(
                problem,
                "    robot gripper",
                "    can can5 at (0.3, -0.2, 0.001) m\n    can can6 at (-0.35, 0.3, 0.001) m\n    robot gripper",
            );
            replaced(
                problem,
                "    in_box(can4, box1)\n",
                "    in_box(can4, box1)\n    in_box(can5, box1)\n    in_box(can6, box1)\n",
            )
        });
        with_copy(text, "pack4_01", "contradiction", |problem| {
            replaced(
                problem,
                "    in_box(can2, box1)\n    in_box(can3, box1)\n    in_box(can4, box1)\n",
                "    surface_can_0(box1, can1)\n",
            )
        })
    });
    let full = explanation(&packing.spec, "pack6_01", &["--plans", "1"]);
    assert!(full.contains("are in the way"), "{full}");
    insta::assert_snapshot!("packing_box_full", full);
    let contradiction = explanation(&packing.spec, "contradiction", &["--no-relax"]);
    assert!(contradiction.contains("cannot all hold together"), "{contradiction}");
    insta::assert_snapshot!("packing_goal_contradicts_itself", contradiction);
}
