//! Poses between the plugin contract's `[x, y, z, qx, qy, qz, qw]` and nalgebra.

use lamp_geometry::Pose;
use nalgebra::{Quaternion, Translation3, UnitQuaternion};

/// How far from unit length a wire quaternion may be: a plugin's arithmetic and a JSON round trip
/// leave rounding far below this, while a quaternion that was never normalised misses it.
pub const UNIT_QUATERNION_TOLERANCE: f64 = 1e-6;

/// A wire pose as an isometry; the quaternion must be of unit length (within
/// [`UNIT_QUATERNION_TOLERANCE`]).
pub fn from_wire(pose: &[f64; 7]) -> Result<Pose, String> {
    let [x, y, z, qx, qy, qz, qw] = *pose;
    let quaternion = Quaternion::new(qw, qx, qy, qz);
    if !pose.iter().all(|value| value.is_finite())
        || (quaternion.norm() - 1.0).abs() > UNIT_QUATERNION_TOLERANCE
    {
        return Err(format!("not a pose: {pose:?}"));
    }
    Ok(Pose::from_parts(Translation3::new(x, y, z), UnitQuaternion::new_normalize(quaternion)))
}

/// An isometry as a wire pose.
pub fn to_wire(pose: &Pose) -> [f64; 7] {
    let t = pose.translation.vector;
    let q = pose.rotation.quaternion();
    [t.x, t.y, t.z, q.i, q.j, q.k, q.w]
}
