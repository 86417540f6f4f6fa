//! Forward kinematics of the shipped robots cross-checked against pybullet for random
//! configurations. Skips when pybullet is missing unless `LAMP_REQUIRE_ORACLES=1`.

// The oracle helper reports what it compared or why it skipped, as the test harness shows.
#![allow(clippy::print_stdout)]

mod common;

use std::path::Path;
use std::process::Command;

use lamp_geometry::{Rotation, Vec3};
use lamp_robot::{Pose, Robot};
use nalgebra::Quaternion;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// pybullet computes in double precision too; allow for its float32 storage of some constants.
const POSITION_TOLERANCE: f64 = 1e-5;
const ANGLE_TOLERANCE: f64 = 1e-5;
const CONFIGURATIONS: usize = 25;

fn pybullet_available() -> bool {
    Command::new("python3")
        .args(["-c", "import pybullet"])
        .output()
        .is_ok_and(|output| output.status.success())
}

fn check_against_pybullet(file: &str) {
    if !pybullet_available() {
        assert!(
            !common::oracles_required(),
            "pybullet is required (LAMP_REQUIRE_ORACLES=1) but not importable"
        );
        println!("skipped: pybullet is not installed (pip install pybullet)");
        return;
    }
    let robot: Robot = common::fixed(file);
    let group = robot.group("all").expect("all group").clone();
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let neutral = robot.neutral_configuration();
    let mut configurations = Vec::new();
    let mut q = neutral.clone();
    for _ in 0..CONFIGURATIONS {
        robot.sample_uniform(&group, &neutral, &mut rng, &mut q);
        configurations.push(q.clone());
    }
    let json_configurations: Vec<String> = configurations
        .iter()
        .map(|q| {
            let entries: Vec<String> = robot
                .coordinate_names()
                .iter()
                .zip(q)
                .map(|(name, value)| format!("\"{name}\": {value:.17e}"))
                .collect();
            format!("{{{}}}", entries.join(", "))
        })
        .collect();
    let directory = tempfile::tempdir().expect("temporary directory");
    let json_path = directory.path().join("configurations.json");
    std::fs::write(&json_path, format!("[{}]", json_configurations.join(",\n")))
        .expect("write configurations");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/oracle/fk_pybullet.py");
    let output = Command::new("python3")
        .arg(&script)
        .arg(common::robots_dir().join(file))
        .arg(&json_path)
        .output()
        .expect("run python3");
    assert!(
        output.status.success(),
        "pybullet oracle failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let stdout = String::from_utf8_lossy(&output.stdout);

    let mut poses = vec![Pose::identity(); robot.link_count()];
    let mut compared = 0;
    let mut current = usize::MAX;
    for line in stdout.lines().filter_map(|line| line.find("POSE ").map(|start| &line[start..])) {
        let fields: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(fields.len(), 10, "malformed oracle line {line}");
        let index: usize = fields[1].parse().expect("configuration index");
        if index != current {
            robot.forward_kinematics(&configurations[index], &mut poses);
            current = index;
        }
        let link = robot
            .link_id(fields[2])
            .unwrap_or_else(|| panic!("oracle reports unknown link {}", fields[2]));
        let numbers: Vec<f64> =
            fields[3..].iter().map(|field| field.parse().expect("number")).collect();
        let position = Vec3::new(numbers[0], numbers[1], numbers[2]);
        let rotation = Rotation::new_normalize(Quaternion::new(
            numbers[6], numbers[3], numbers[4], numbers[5],
        ));
        let ours = &poses[link];
        let position_error = (ours.translation.vector - position).norm();
        let angle_error = ours.rotation.angle_to(&rotation);
        assert!(
            position_error < POSITION_TOLERANCE && angle_error < ANGLE_TOLERANCE,
            "{file} link {} configuration {index}: position error {position_error}, angle error {angle_error}",
            fields[2]
        );
        compared += 1;
    }
    assert_eq!(compared, CONFIGURATIONS * robot.link_count(), "oracle did not report every link");
    println!("{file}: {compared} link poses agree with pybullet");
}

#[test]
fn fetch_matches_pybullet() {
    check_against_pybullet("fetch.urdf");
}

#[test]
fn yumi_matches_pybullet() {
    check_against_pybullet("yumi.urdf");
}
