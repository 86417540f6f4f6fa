//! What a resting body needs to know about what is under it: how far it can drop straight down
//! before it touches another shape, the contact points where it rests, and its centre of mass.
//!
//! A drop parry cannot compute for a pair of shape kinds is a drop of 0 (already touching), like
//! every unanswerable query in this crate: nothing is ever let fall through an unchecked contact.

use parry3d_f64::query::{
    self, ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher, ShapeCastOptions,
};

use crate::collision::CollisionShape;
use crate::math::{Point3, Pose, Real, Vec3};
use crate::parry_boundary as boundary;

/// A point where one shape touches (or nearly touches) another.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    /// The point on the first shape, in the world frame.
    pub point: Point3,
    /// The unit normal pointing from the second shape toward the first, in the world frame: for a
    /// body resting on a table, straight up.
    pub normal: Vec3,
    /// The gap between the shapes at this point (negative when they overlap).
    pub gap: Real,
}

/// How far `shape` at `pose` can move straight down (along −z) before it touches `other` at
/// `other_pose`: `None` when it can move `max` or more, `Some(0.0)` when it touches already.
pub fn drop_distance(
    shape: &CollisionShape,
    pose: &Pose,
    other: &CollisionShape,
    other_pose: &Pose,
    max: Real,
) -> Option<Real> {
    let (shape_a, local_a) = shape.parts();
    let (shape_b, local_b) = other.parts();
    let pose_a = boundary::pose(&(pose * local_a));
    let pose_b = boundary::pose(&(other_pose * local_b));
    let down = boundary::vector(&-Vec3::z());
    let still = boundary::vector(&Vec3::zeros());
    let options = ShapeCastOptions { max_time_of_impact: max, ..ShapeCastOptions::default() };
    match query::cast_shapes(&pose_a, down, shape_a, &pose_b, still, shape_b, options) {
        Ok(hit) => hit.map(|hit| hit.time_of_impact.max(0.0)),
        Err(_) => Some(0.0),
    }
}

/// Every contact point between `shape` at `pose` and `other` at `other_pose` closer than
/// `prediction` (parry's contact manifolds: up to a polygon's corners per touching face, a
/// cylinder's cap taken as its inscribed square). A pair parry cannot answer has none.
pub fn contact_points(
    shape: &CollisionShape,
    pose: &Pose,
    other: &CollisionShape,
    other_pose: &Pose,
    prediction: Real,
) -> Vec<ContactPoint> {
    let (shape_a, local_a) = shape.parts();
    let (shape_b, local_b) = other.parts();
    let placed_a = pose * local_a;
    let placed_b = other_pose * local_b;
    let pose_a = boundary::pose(&placed_a);
    let pose_12 = pose_a.inv_mul(&boundary::pose(&placed_b));
    let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
    let found = DefaultQueryDispatcher.contact_manifolds(
        &pose_12,
        shape_a,
        shape_b,
        prediction,
        &mut manifolds,
        &mut None,
    );
    if found.is_err() {
        return Vec::new();
    }
    let mut points = Vec::new();
    for manifold in &manifolds {
        // Points and normals are in the frame of the part of a compound that touches.
        let part = match manifold.subshape_pos1() {
            Some(part) => pose_a * *part,
            None => pose_a,
        };
        let outward = boundary::from_vector(part.rotation * manifold.local_n1).coords;
        for contact in &manifold.points {
            points.push(ContactPoint {
                point: boundary::from_vector(part.transform_point(contact.local_p1)),
                normal: -outward,
                gap: contact.dist,
            });
        }
    }
    points
}

impl CollisionShape {
    /// The centre of mass at uniform density, in the body's frame.
    pub fn centre_of_mass(&self) -> Point3 {
        let (shape, local) = self.parts();
        let centre = boundary::from_vector(shape.mass_properties(1.0).local_com);
        local * centre
    }
}
