//! Numeric conventions, written down once.
//!
//! Frames: a [`Pose`] `T_a_b` maps coordinates in frame `b` to frame `a`.
//! The pose of body B relative to body A is `A⁻¹ · B` (B expressed in A's frame).
//! Units are metres and radians everywhere.

/// The scalar type of all geometry.
pub type Real = f64;
/// A rigid transform: rotation followed by translation.
pub type Pose = nalgebra::Isometry3<Real>;
/// A vector in 3-D space.
pub type Vec3 = nalgebra::Vector3<Real>;
/// A point in 3-D space.
pub type Point3 = nalgebra::Point3<Real>;
/// A rotation as a unit quaternion.
pub type Rotation = nalgebra::UnitQuaternion<Real>;

/// The relative pose of `b` in `a`'s frame: `a⁻¹ · b`.
pub fn relative_pose(a: &Pose, b: &Pose) -> Pose {
    a.inv_mul(b)
}
