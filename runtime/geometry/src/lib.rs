//! Poses, collision shapes and collision queries: the geometric conventions every crate shares.
//!
//! Every pose in the project is a [`Pose`] (`nalgebra::Isometry3<f64>`). Collision queries run
//! on parry, behind the private `parry_boundary` module: no parry or glam type appears in this
//! crate's public API, and no other crate names parry.

pub mod collision;
pub mod error;
pub mod math;
mod parry_boundary;
pub mod shape;
pub mod support;
pub mod symmetry;
pub mod world;

pub use collision::{
    Aabb, CollisionShape, closest_points, distance, intersects, penetration_depth, within_margin,
};
pub use error::GeometryError;
pub use math::{Point3, Pose, Real, Rotation, Vec3};
pub use shape::Shape;
pub use support::{ContactPoint, contact_points, drop_distance};
pub use symmetry::{axis_symmetries, round_axis, upright_symmetries};
pub use world::{BodyId, CollisionWorld};
