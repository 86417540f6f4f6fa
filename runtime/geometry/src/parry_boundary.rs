//! The one place where parry and its glam types meet nalgebra.
//!
//! Everything else in the project speaks `nalgebra`; this module converts poses and points at
//! the boundary and builds parry shapes. Nothing here is public outside the crate.

use parry3d_f64::math::{Pose as ParryPose, Rotation as ParryRotation, Vector as ParryVector};
use parry3d_f64::shape::SharedShape;

use crate::error::GeometryError;
use crate::math::{Point3, Pose, Vec3};
use crate::shape::Shape;

pub(crate) fn vector(v: &Vec3) -> ParryVector {
    ParryVector::new(v.x, v.y, v.z)
}

pub(crate) fn point(p: &Point3) -> ParryVector {
    ParryVector::new(p.x, p.y, p.z)
}

pub(crate) fn from_vector(v: ParryVector) -> Point3 {
    Point3::new(v.x, v.y, v.z)
}

pub(crate) fn pose(pose: &Pose) -> ParryPose {
    let q = pose.rotation.quaternion();
    ParryPose::from_parts(
        vector(&pose.translation.vector),
        ParryRotation::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

/// A parry shape in our conventions. Parry's cylinders run along y, ours along z (URDF), so a
/// cylinder carries a quarter turn about x as its local pose.
pub(crate) fn shared_shape(shape: &Shape) -> Result<(SharedShape, Pose), GeometryError> {
    let identity = Pose::identity();
    Ok(match shape {
        Shape::Box { half_extents } => {
            (SharedShape::cuboid(half_extents.x, half_extents.y, half_extents.z), identity)
        }
        Shape::Sphere { radius } => (SharedShape::ball(*radius), identity),
        Shape::Cylinder { radius, half_height } => {
            let y_to_z = Pose::rotation(Vec3::x() * std::f64::consts::FRAC_PI_2);
            (SharedShape::cylinder(*half_height, *radius), y_to_z)
        }
        Shape::ConvexHull { points } => {
            let points: Vec<ParryVector> = points.iter().map(point).collect();
            let hull = SharedShape::convex_hull(&points)
                .ok_or(GeometryError::DegenerateHull { points: points.len() })?;
            (hull, identity)
        }
        Shape::TriMesh { vertices, triangles } => {
            let vertices: Vec<ParryVector> = vertices.iter().map(point).collect();
            let mesh = SharedShape::trimesh(vertices, triangles.clone())
                .map_err(|error| GeometryError::BadTriMesh { reason: error.to_string() })?;
            (mesh, identity)
        }
    })
}

/// A compound of placed parts (each part's own local pose folded in).
pub(crate) fn compound(parts: Vec<(Pose, SharedShape)>) -> SharedShape {
    SharedShape::compound(
        parts.into_iter().map(|(placement, shape)| (pose(&placement), shape)).collect(),
    )
}

/// The world-aligned bounding box of a parry shape at `placed` (the shape's local pose folded in),
/// as (mins, maxs). A cylinder's box is computed in closed form: parry derives it from six
/// support-point queries, which made bounding boxes of the Fetch's cylinder links the largest
/// single cost of collision checking.
pub(crate) fn aabb(shape: &SharedShape, placed: &Pose) -> (Point3, Point3) {
    if let Some(cylinder) = shape.as_cylinder() {
        // Parry's cylinder axis is its local y; per world axis i the half-width is
        // |a_i|·h + r·√(1 − a_i²) for the unit axis a.
        let axis = placed.rotation * Vec3::y();
        let half = axis.map(|a| {
            a.abs() * cylinder.half_height + cylinder.radius * (1.0 - a * a).max(0.0).sqrt()
        });
        let centre = Point3::from(placed.translation.vector);
        return (centre - half, centre + half);
    }
    let aabb = shape.compute_aabb(&pose(placed));
    (from_vector(aabb.mins), from_vector(aabb.maxs))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form cylinder box equals parry's support-map box at many orientations.
    #[test]
    fn cylinder_box_matches_parry() {
        let shape = SharedShape::cylinder(0.1, 0.045);
        let mut angle: f64 = 0.0;
        for step in 0..200 {
            angle += 0.37;
            let axis = Vec3::new(angle.sin(), (1.7 * angle).cos(), 0.3 + (step as f64 * 0.01));
            let rotation = nalgebra::UnitQuaternion::from_scaled_axis(axis.normalize() * angle);
            let placed = Pose::from_parts(
                nalgebra::Translation3::new(0.5 * angle.cos(), -0.2, step as f64 * 0.01),
                rotation,
            );
            let (mins, maxs) = aabb(&shape, &placed);
            let expected = shape.compute_aabb(&pose(&placed));
            let difference = (mins - from_vector(expected.mins)).norm()
                + (maxs - from_vector(expected.maxs)).norm();
            assert!(difference < 1e-9, "step {step}: {mins:?} {maxs:?} vs {expected:?}");
        }
    }
}
