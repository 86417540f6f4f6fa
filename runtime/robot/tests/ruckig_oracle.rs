//! The timing of straight moves cross-checked against Ruckig: a rest-to-rest move along a straight
//! line of joint space, cut into any number of pieces, takes Ruckig's time-optimal duration with
//! unlimited jerk (the acceleration-limited trapezoid of the slowest joint). Skips when Python's
//! `ruckig` is missing unless `LAMP_REQUIRE_ORACLES=1`.

// The oracle helper reports what it compared or why it skipped, as the test harness shows.
#![allow(clippy::print_stdout)]

mod common;

use std::path::Path;
use std::process::Command;

use lamp_robot::{Limits, time_path};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Ruckig solves its profiles in double precision to about 1e-8 s.
const DURATION_TOLERANCE: f64 = 1e-6;
const MOVES: usize = 60;

struct Move {
    displacement: Vec<f64>,
    velocity: Vec<f64>,
    acceleration: Vec<f64>,
    pieces: usize,
}

/// Random moves of one to three joints. With several, the first joint needs the longest at both
/// its velocity and its acceleration limit, so the straight line is time-optimal and Ruckig's
/// time-synchronised duration (the slowest joint's) is the answer too; otherwise Ruckig's joints
/// may leave the line and arrive sooner than any motion along it.
fn moves() -> Vec<Move> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    (0..MOVES)
        .map(|index| {
            let joints = 1 + index % 3;
            let length = 0.005 + 3.0 * rng.random::<f64>();
            let sign = if rng.random::<bool>() { 1.0 } else { -1.0 };
            let velocity = 0.1 + 2.0 * rng.random::<f64>();
            let acceleration = 0.2 + 4.0 * rng.random::<f64>();
            let mut displacement = vec![sign * length];
            for _ in 1..joints {
                displacement.push(length * (rng.random::<f64>() - 0.5));
            }
            Move {
                displacement,
                velocity: vec![velocity; joints],
                acceleration: vec![acceleration; joints],
                pieces: 1 + rng.random_range(0..60),
            }
        })
        .collect()
}

fn ruckig_available() -> bool {
    Command::new("python3")
        .args(["-c", "import ruckig"])
        .output()
        .is_ok_and(|output| output.status.success())
}

#[test]
fn straight_moves_take_ruckigs_time_optimal_duration() {
    if !ruckig_available() {
        assert!(
            !common::oracles_required(),
            "ruckig is required (LAMP_REQUIRE_ORACLES=1) but not importable"
        );
        println!("skipped: ruckig is not installed (pip install ruckig)");
        return;
    }
    let moves = moves();
    let list = |values: &[f64]| {
        let entries: Vec<String> = values.iter().map(|value| format!("{value:.17e}")).collect();
        format!("[{}]", entries.join(", "))
    };
    let json: Vec<String> = moves
        .iter()
        .map(|m| {
            format!(
                "{{\"displacement\": {}, \"velocity\": {}, \"acceleration\": {}}}",
                list(&m.displacement),
                list(&m.velocity),
                list(&m.acceleration)
            )
        })
        .collect();
    let directory = tempfile::tempdir().expect("temporary directory");
    let json_path = directory.path().join("moves.json");
    std::fs::write(&json_path, format!("[{}]", json.join(",\n"))).expect("write moves");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/oracle/ruckig_durations.py");
    let output = Command::new("python3").arg(&script).arg(&json_path).output().expect("python3");
    assert!(
        output.status.success(),
        "ruckig oracle failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let expected: Vec<f64> = String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|line| line.parse().expect("a duration"))
        .collect();
    assert_eq!(expected.len(), moves.len());
    for (index, (m, expected)) in moves.iter().zip(&expected).enumerate() {
        let piece: Vec<f64> = m.displacement.iter().map(|d| d / m.pieces as f64).collect();
        let pieces = vec![piece; m.pieces];
        let limits = Limits { velocity: &m.velocity, acceleration: &m.acceleration };
        let total: f64 = time_path(&pieces, &limits).expect("times").iter().sum();
        assert!(
            (total - expected).abs() <= DURATION_TOLERANCE,
            "move {index} ({:?} in {} pieces): {total} s, Ruckig {expected} s",
            m.displacement,
            m.pieces
        );
    }
    println!("compared {} moves with ruckig", moves.len());
}
