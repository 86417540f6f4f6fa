//! Loading the bundled specs from disk for the world's tests.

#![allow(dead_code, clippy::unwrap_used)]

pub use lamp_test_support::domain;

/// A pose from a translation and roll, pitch, yaw (radians).
pub fn pose(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> lamp_geometry::Pose {
    lamp_geometry::Pose::from_parts(
        nalgebra::Translation3::new(x, y, z),
        nalgebra::UnitQuaternion::from_euler_angles(roll, pitch, yaw),
    )
}
