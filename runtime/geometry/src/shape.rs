//! Collision shapes, in the shape's own frame.

use crate::math::{Point3, Real, Vec3};

/// A collision shape. Primitive shapes are centred at their frame origin;
/// cylinders run along their local z axis (the URDF convention).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// An axis-aligned box given by its half extents.
    Box { half_extents: Vec3 },
    /// A cylinder along local z, centred at the origin.
    Cylinder { radius: Real, half_height: Real },
    /// A sphere centred at the origin.
    Sphere { radius: Real },
    /// The convex hull of a point cloud (meshes loaded "as convex hulls").
    ConvexHull { points: Vec<Point3> },
    /// A triangle mesh (static bodies only; no volume).
    TriMesh { vertices: Vec<Point3>, triangles: Vec<[u32; 3]> },
}
