//! Helpers shared by the integration tests: the shipped robots and oracle handling.
#![allow(dead_code)]

use std::path::PathBuf;

use lamp_robot::{Mount, Pose, Robot};

/// The folder holding the shipped robot models.
pub fn robots_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../domains/robots")
}

pub fn load(file: &str, mount: Mount) -> Robot {
    Robot::from_urdf_file(&robots_dir().join(file), mount).expect("shipped robot loads")
}

pub fn fetch_fixed() -> Robot {
    load("fetch.urdf", Mount::Fixed(Pose::identity()))
}

pub fn yumi_fixed() -> Robot {
    load("yumi.urdf", Mount::Fixed(Pose::identity()))
}

/// Whether a missing oracle must fail the test (CI) instead of skipping it.
pub fn oracles_required() -> bool {
    std::env::var("LAMP_REQUIRE_ORACLES").is_ok_and(|value| value == "1")
}

/// A shipped robot bolted at the world origin.
pub fn fixed(file: &str) -> Robot {
    load(file, Mount::Fixed(Pose::identity()))
}
