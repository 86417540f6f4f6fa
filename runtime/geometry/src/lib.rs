//! Poses and collision shapes: the numeric conventions every crate shares.
//!
//! Every pose in the project is a [`Pose`] (`nalgebra::Isometry3<f64>`).
//! Collision queries (parry) will live here too, behind one boundary module, so that no parry
//! or glam type appears in any public API.

pub mod math;
pub mod shape;

pub use math::{Point3, Pose, Real, Rotation, Vec3};
pub use shape::Shape;
