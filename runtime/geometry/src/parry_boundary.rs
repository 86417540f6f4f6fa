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
