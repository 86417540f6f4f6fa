//! Collision shapes and the queries on them: intersection, distance and margin tests.
//!
//! A [`CollisionShape`] is built once from [`Shape`]s (a compound when a body has several parts)
//! and queried at any pose. Touching counts as intersecting. A query parry cannot answer for a
//! pair of shape kinds answers "in collision": a planner must never pass through an
//! unchecked contact.

use parry3d_f64::query;
use parry3d_f64::shape::SharedShape;

use crate::error::GeometryError;
use crate::math::{Point3, Pose, Real, Vec3};
use crate::parry_boundary as boundary;
use crate::shape::Shape;

/// A shape ready for collision queries, in its own frame.
#[derive(Clone)]
pub struct CollisionShape {
    shape: SharedShape,
    /// Pose of the parry shape in the body's frame (a cylinder's quarter turn, for example).
    local: Pose,
    /// The shape's bounding box in the body's own frame, for [`CollisionShape::bounding_box`].
    frame_box: Aabb,
}

impl std::fmt::Debug for CollisionShape {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter.debug_struct("CollisionShape").field("local", &self.local).finish_non_exhaustive()
    }
}

impl CollisionShape {
    /// One shape at the body's origin.
    pub fn new(shape: &Shape) -> Result<CollisionShape, GeometryError> {
        check_dimensions(shape)?;
        let (shape, local) = boundary::shared_shape(shape)?;
        Ok(CollisionShape::placed(shape, local))
    }

    fn placed(shape: SharedShape, local: Pose) -> CollisionShape {
        let (mins, maxs) = boundary::aabb(&shape, &local);
        CollisionShape { shape, local, frame_box: Aabb { mins, maxs } }
    }

    /// Several shapes, each placed in the body's frame, as one rigid body.
    pub fn compound(parts: &[(Pose, Shape)]) -> Result<CollisionShape, GeometryError> {
        match parts {
            [] => Err(GeometryError::EmptyBody),
            [(placement, shape)] => {
                let single = CollisionShape::new(shape)?;
                Ok(CollisionShape::placed(single.shape, placement * single.local))
            }
            _ => {
                let mut placed = Vec::with_capacity(parts.len());
                for (placement, shape) in parts {
                    check_dimensions(shape)?;
                    let (shape, local) = boundary::shared_shape(shape)?;
                    placed.push((placement * local, shape));
                }
                Ok(CollisionShape::placed(boundary::compound(placed), Pose::identity()))
            }
        }
    }

    /// The parry shape and its pose in the body's frame, for the queries of this crate.
    pub(crate) fn parts(&self) -> (&dyn parry3d_f64::shape::Shape, &Pose) {
        (self.shape.as_ref(), &self.local)
    }

    /// The world-aligned bounding box of the shape at `pose`.
    pub fn aabb(&self, pose: &Pose) -> Aabb {
        let (mins, maxs) = boundary::aabb(&self.shape, &(pose * self.local));
        Aabb { mins, maxs }
    }

    /// A world-aligned box that contains the shape at `pose`, for broad phases: the box of the
    /// shape in its own frame, turned and bounded again, grown by [`BOUNDING_SLACK`] so that
    /// rounding never leaves it inside [`CollisionShape::aabb`]. It may be looser than that box
    /// (a turned box's corners) and costs a fraction of it: a few dozen operations against
    /// converting the pose and asking parry, which walks a compound's parts.
    pub fn bounding_box(&self, pose: &Pose) -> Aabb {
        let local = &self.frame_box;
        let centre = pose * nalgebra::center(&local.mins, &local.maxs);
        let half = (local.maxs - local.mins) * 0.5;
        let turn = pose.rotation.to_rotation_matrix();
        let reach = turn.matrix().abs() * half + Vec3::repeat(BOUNDING_SLACK);
        Aabb { mins: centre - reach, maxs: centre + reach }
    }
}

fn check_dimensions(shape: &Shape) -> Result<(), GeometryError> {
    let dimensions: Vec<Real> = match shape {
        Shape::Box { half_extents } => half_extents.iter().copied().collect(),
        Shape::Cylinder { radius, half_height } => vec![*radius, *half_height],
        Shape::Sphere { radius } => vec![*radius],
        Shape::ConvexHull { points } => {
            if let Some(&value) = points.iter().flat_map(|p| p.iter()).find(|v| !v.is_finite()) {
                return Err(GeometryError::BadDimension { value });
            }
            return if spans_volume(points) {
                Ok(())
            } else {
                Err(GeometryError::DegenerateHull { points: points.len() })
            };
        }
        Shape::TriMesh { .. } => return Ok(()),
    };
    match dimensions.into_iter().find(|v| !(v.is_finite() && *v > 0.0)) {
        Some(value) => Err(GeometryError::BadDimension { value }),
        None => Ok(()),
    }
}

/// Whether the points span a volume: a point, the farthest from it, the farthest from their line
/// and the farthest from their plane must be apart by more than a micrometre each.
fn spans_volume(points: &[Point3]) -> bool {
    const TOLERANCE: Real = 1e-6;
    let Some(first) = points.first() else { return false };
    let farthest = |score: &dyn Fn(&Point3) -> Real| {
        points.iter().map(|p| (score(p), p)).max_by(|a, b| a.0.total_cmp(&b.0))
    };
    let Some((spread, second)) = farthest(&|p| (p - first).norm()) else { return false };
    if spread <= TOLERANCE {
        return false;
    }
    let axis = (second - first) / spread;
    let off_line = |p: &Point3| {
        let v = p - first;
        (v - axis * v.dot(&axis)).norm()
    };
    let Some((height, third)) = farthest(&off_line) else { return false };
    if height <= TOLERANCE {
        return false;
    }
    let normal = axis.cross(&(third - first)).normalize();
    farthest(&|p| (p - first).dot(&normal).abs()).is_some_and(|(depth, _)| depth > TOLERANCE)
}

/// How far [`CollisionShape::bounding_box`] is grown beyond the turned box: far above the
/// rounding of a pose's product, far below any clearance a query asks about.
pub const BOUNDING_SLACK: Real = 1e-9;

/// An axis-aligned bounding box in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub mins: Point3,
    pub maxs: Point3,
}

impl Aabb {
    /// Whether the boxes overlap once each is grown by `margin` / 2 (so `margin` is a gap).
    #[inline]
    pub fn overlaps(&self, other: &Aabb, margin: Real) -> bool {
        (0..3).all(|axis| {
            self.mins[axis] <= other.maxs[axis] + margin
                && other.mins[axis] <= self.maxs[axis] + margin
        })
    }

    /// The smallest box containing both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb { mins: self.mins.inf(&other.mins), maxs: self.maxs.sup(&other.maxs) }
    }
}

/// Whether the boxes `a` and `b` (each a box in its own frame, the frames at `pose_a` and
/// `pose_b`) are more than `gap` apart: some axis of the separating axis theorem for two
/// oriented boxes (the 3 face normals of each and the 9 cross products of their edges) parts
/// them once each is grown by `gap` / 2 (a box grown so contains the box widened by a ball of
/// that radius). Exact for boxes up to rounding, which [`BOUNDING_SLACK`] on every half extent
/// and a small term on the turn's entries (for nearly parallel edges, whose cross product
/// vanishes) keep on the side of "not apart".
fn boxes_apart(a: &Aabb, pose_a: &Pose, b: &Aabb, pose_b: &Pose, gap: Real) -> bool {
    let grow = Vec3::repeat(0.5 * gap.max(0.0) + BOUNDING_SLACK);
    let half_a = (a.maxs - a.mins) * 0.5 + grow;
    let half_b = (b.maxs - b.mins) * 0.5 + grow;
    let turn_a = pose_a.rotation.to_rotation_matrix();
    let turn_b = pose_b.rotation.to_rotation_matrix();
    // b's axes and centre in a's frame.
    let turn = turn_a.matrix().transpose() * turn_b.matrix();
    let centre_a = pose_a * nalgebra::center(&a.mins, &a.maxs);
    let centre_b = pose_b * nalgebra::center(&b.mins, &b.maxs);
    let t = turn_a.matrix().transpose() * (centre_b - centre_a);
    let size = turn.abs().add_scalar(1e-12);
    for i in 0..3 {
        if t[i].abs() > half_a[i] + size.row(i).transpose().dot(&half_b) {
            return true;
        }
    }
    for j in 0..3 {
        if t.dot(&turn.column(j)).abs() > half_a.dot(&size.column(j)) + half_b[j] {
            return true;
        }
    }
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let reach_a = half_a[i1] * size[(i2, j)] + half_a[i2] * size[(i1, j)];
            let reach_b = half_b[j1] * size[(i, j2)] + half_b[j2] * size[(i, j1)];
            if (t[i2] * turn[(i1, j)] - t[i1] * turn[(i2, j)]).abs() > reach_a + reach_b {
                return true;
            }
        }
    }
    false
}

/// Whether the shapes touch or overlap.
///
/// Shapes whose boxes in their own frames are apart are apart: that test (a few dozen
/// operations) answers most queries of a robot's links before parry's GJK runs.
pub fn intersects(a: &CollisionShape, pose_a: &Pose, b: &CollisionShape, pose_b: &Pose) -> bool {
    if boxes_apart(&a.frame_box, pose_a, &b.frame_box, pose_b, 0.0) {
        return false;
    }
    let pose_a = boundary::pose(&(pose_a * a.local));
    let pose_b = boundary::pose(&(pose_b * b.local));
    query::intersection_test(&pose_a, a.shape.as_ref(), &pose_b, b.shape.as_ref())
        .map_or(true, |found| found.intersecting)
}

/// The distance between the shapes (0 when they touch or overlap).
pub fn distance(a: &CollisionShape, pose_a: &Pose, b: &CollisionShape, pose_b: &Pose) -> Real {
    let pose_a = boundary::pose(&(pose_a * a.local));
    let pose_b = boundary::pose(&(pose_b * b.local));
    query::distance(&pose_a, a.shape.as_ref(), &pose_b, b.shape.as_ref())
        .map_or(0.0, |found| found.distance.max(0.0))
}

/// How far the shapes overlap: the depth of the deepest overlapping pair of their convex parts
/// (a compound's parts, a mesh's triangles), the length of the shortest translation that would
/// separate that pair; 0 when they are apart or only touch, and when parry cannot say.
///
/// A lower bound of what any rigid motion must move a point of `a` to clear `b`: when it exceeds
/// how far a motion moves any point of `a`, the moved shape still overlaps `b` (a plane that
/// separated a part of the moved `a` from a part of `b` would separate the unmoved part after a
/// translation no longer than that motion).
pub fn penetration_depth(
    a: &CollisionShape,
    pose_a: &Pose,
    b: &CollisionShape,
    pose_b: &Pose,
) -> Real {
    let pose_a = boundary::pose(&(pose_a * a.local));
    let pose_b = boundary::pose(&(pose_b * b.local));
    match query::contact(&pose_a, a.shape.as_ref(), &pose_b, b.shape.as_ref(), 0.0) {
        Ok(Some(contact)) => (-contact.dist).max(0.0),
        _ => 0.0,
    }
}

/// The nearest points of two shapes at most `max_distance` apart, in the world frame (the first
/// on `a`): `None` when they touch or overlap, are farther apart, or parry cannot say.
pub fn closest_points(
    a: &CollisionShape,
    pose_a: &Pose,
    b: &CollisionShape,
    pose_b: &Pose,
    max_distance: Real,
) -> Option<(Point3, Point3)> {
    let pose_a = boundary::pose(&(pose_a * a.local));
    let pose_b = boundary::pose(&(pose_b * b.local));
    match query::closest_points(&pose_a, a.shape.as_ref(), &pose_b, b.shape.as_ref(), max_distance)
    {
        Ok(query::ClosestPoints::WithinMargin(on_a, on_b)) => {
            Some((boundary::from_vector(on_a), boundary::from_vector(on_b)))
        }
        _ => None,
    }
}

/// Whether the shapes are closer than `margin` (touching counts; `margin` 0 is [`intersects`]).
pub fn within_margin(
    a: &CollisionShape,
    pose_a: &Pose,
    b: &CollisionShape,
    pose_b: &Pose,
    margin: Real,
) -> bool {
    if margin <= 0.0 {
        intersects(a, pose_a, b, pose_b)
    } else {
        !boxes_apart(&a.frame_box, pose_a, &b.frame_box, pose_b, margin)
            && distance(a, pose_a, b, pose_b) <= margin
    }
}
