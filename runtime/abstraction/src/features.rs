//! The continuous feature vector of a relative pose: position (3) and the first two columns of the rotation matrix (6).
//!
//! This "6-D rotation representation" has no wrap anywhere: nearby rotations always have nearby features,
//! so a region around a half turn is one blob to the mixture, not two.

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

use crate::snapshot::Pose;

/// The length of a feature vector.
pub const FEATURE_DIMENSION: usize = 9;

/// Columns shorter than this cannot define a direction; a fixed fallback keeps the projection total.
const DEGENERATE_COLUMN: f64 = 1e-9;

/// The feature vector of a pose.
pub fn pose_features(pose: &Pose) -> [f64; FEATURE_DIMENSION] {
    let rotation = pose.rotation.to_rotation_matrix();
    let matrix = rotation.matrix();
    let position = pose.translation.vector;
    [
        position.x,
        position.y,
        position.z,
        matrix[(0, 0)],
        matrix[(1, 0)],
        matrix[(2, 0)],
        matrix[(0, 1)],
        matrix[(1, 1)],
        matrix[(2, 1)],
    ]
}

/// The pose of a feature vector: the rotation columns are projected back to a proper rotation by Gram–Schmidt.
pub fn features_pose(features: &[f64]) -> Pose {
    let position = Vector3::new(feature(features, 0), feature(features, 1), feature(features, 2));
    let first = Vector3::new(feature(features, 3), feature(features, 4), feature(features, 5));
    let second = Vector3::new(feature(features, 6), feature(features, 7), feature(features, 8));
    let x = first.try_normalize(DEGENERATE_COLUMN).unwrap_or_else(Vector3::x);
    let orthogonal = second - x * x.dot(&second);
    let y = orthogonal.try_normalize(DEGENERATE_COLUMN).unwrap_or_else(|| any_orthogonal(&x));
    let z = x.cross(&y);
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, y, z]));
    Pose::from_parts(position.into(), UnitQuaternion::from_rotation_matrix(&rotation))
}

fn feature(features: &[f64], index: usize) -> f64 {
    features.get(index).copied().unwrap_or(0.0)
}

/// A unit vector orthogonal to a unit vector.
fn any_orthogonal(x: &Vector3<f64>) -> Vector3<f64> {
    let helper = if x.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    x.cross(&helper).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use std::f64::consts::PI;

    #[test]
    fn features_round_trip() {
        let pose = Pose::from_parts(
            nalgebra::Translation3::new(0.1, -0.2, 0.3),
            UnitQuaternion::from_euler_angles(0.3, -1.1, 2.9),
        );
        assert_relative_eq!(features_pose(&pose_features(&pose)), pose, epsilon = 1e-12);
    }

    #[test]
    fn yaw_either_side_of_the_half_turn_has_nearby_features() {
        let below = pose_features(&Pose::rotation(Vector3::z() * (PI - 0.01)));
        let above = pose_features(&Pose::rotation(Vector3::z() * (-PI + 0.01)));
        let distance: f64 =
            below.iter().zip(&above).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
        assert!(distance < 0.03, "distance {distance}");
    }

    #[test]
    fn noisy_columns_project_to_a_proper_rotation() {
        let mut features = pose_features(&Pose::rotation(Vector3::new(0.2, 0.4, -0.1)));
        features[3] += 0.05;
        features[7] -= 0.08;
        let rotation = features_pose(&features).rotation.to_rotation_matrix();
        let matrix = rotation.matrix();
        assert_relative_eq!(matrix.determinant(), 1.0, epsilon = 1e-12);
        assert_relative_eq!(matrix.transpose() * matrix, Matrix3::identity(), epsilon = 1e-12);
        // Degenerate input still gives a rotation.
        let degenerate = features_pose(&[0.0; FEATURE_DIMENSION]);
        assert_relative_eq!(
            degenerate.rotation.to_rotation_matrix().matrix().determinant(),
            1.0,
            epsilon = 1e-12
        );
    }
}
