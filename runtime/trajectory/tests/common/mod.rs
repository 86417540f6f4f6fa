//! Sample trajectories for the tests: a scene with bodies and a robot, random but seeded.

#![allow(dead_code)]

use lamp_trajectory::{
    BodyDescription, RobotDescription, RobotState, Step, Trajectory, TrajectoryHeader,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub fn oracles_required() -> bool {
    std::env::var("LAMP_REQUIRE_ORACLES").is_ok_and(|value| value == "1")
}

pub fn header(body_count: usize) -> TrajectoryHeader {
    let mut bodies: Vec<BodyDescription> = (0..body_count)
        .map(|index| BodyDescription { name: format!("can_{index}"), type_name: "can".into() })
        .collect();
    bodies.push(BodyDescription { name: "table".into(), type_name: "surface".into() });
    TrajectoryHeader {
        domain: "packing".into(),
        seed: 42,
        provenance: [
            ("cut_at".to_string(), "17".to_string()),
            ("demo_index".to_string(), "3".to_string()),
            ("demonstrator".to_string(), "scripted pick and place".to_string()),
        ]
        .into(),
        bodies,
        robots: vec![
            RobotDescription {
                name: "fetch".into(),
                coordinates: ["base_x", "base_y", "base_yaw", "torso", "j1", "j2", "j3"]
                    .map(String::from)
                    .to_vec(),
                grippers: vec!["gripper".into()],
            },
            RobotDescription { name: "camera_mast".into(), coordinates: vec![], grippers: vec![] },
        ],
    }
}

pub fn random_pose(rng: &mut ChaCha8Rng) -> Isometry3<f64> {
    let translation = Translation3::new(
        rng.random_range(-2.0..2.0),
        rng.random_range(-2.0..2.0),
        rng.random_range(0.0..1.5),
    );
    let axis = Vector3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    );
    let rotation = UnitQuaternion::from_scaled_axis(axis * 3.0);
    Isometry3::from_parts(translation, rotation)
}

/// A trajectory with random poses and configurations; the gripper holds `can_0` in the middle
/// third of the steps.
pub fn trajectory(body_count: usize, step_count: usize, seed: u64) -> Trajectory {
    let header = header(body_count);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let steps = (0..step_count)
        .map(|index| {
            let holding = index >= step_count / 3 && index < 2 * step_count / 3;
            Step {
                time_nanoseconds: index as u64 * 33_333_333,
                body_poses: header.bodies.iter().map(|_| random_pose(&mut rng)).collect(),
                robots: vec![
                    RobotState {
                        positions: (0..7).map(|_| rng.random_range(-3.0..3.0)).collect(),
                        held: vec![holding.then_some(0)],
                    },
                    RobotState { positions: vec![], held: vec![] },
                ],
            }
        })
        .collect();
    Trajectory { header, steps }
}

/// Poses compared bit for bit, not by value (so -0.0 and 0.0 differ, and NaNs would be caught).
pub fn assert_bit_identical(left: &Trajectory, right: &Trajectory) {
    assert_eq!(left.header, right.header);
    assert_eq!(left.steps.len(), right.steps.len());
    for (a, b) in left.steps.iter().zip(&right.steps) {
        assert_eq!(a.time_nanoseconds, b.time_nanoseconds);
        for (pa, pb) in a.body_poses.iter().zip(&b.body_poses) {
            let bits = |pose: &Isometry3<f64>| -> Vec<u64> {
                pose.translation
                    .vector
                    .iter()
                    .chain(pose.rotation.as_ref().coords.iter())
                    .map(|value| value.to_bits())
                    .collect()
            };
            assert_eq!(bits(pa), bits(pb));
        }
        for (ra, rb) in a.robots.iter().zip(&b.robots) {
            let bits = |values: &[f64]| values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&ra.positions), bits(&rb.positions));
            assert_eq!(ra.held, rb.held);
        }
    }
}
