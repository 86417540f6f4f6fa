//! Errors from building collision shapes.

/// A shape that cannot be used for collision checking.
#[derive(Debug, Clone, PartialEq, thiserror::Error, miette::Diagnostic)]
pub enum GeometryError {
    /// A convex hull of points that span no volume (fewer than four points, or all coplanar).
    #[error("a convex hull of {points} point(s) spans no volume")]
    #[diagnostic(
        code(lamp::geometry::degenerate_hull),
        help("a mesh used as a convex hull needs at least four points that are not coplanar")
    )]
    DegenerateHull { points: usize },
    /// A triangle mesh parry refuses (no triangles, or indices out of range).
    #[error("the triangle mesh is not usable: {reason}")]
    #[diagnostic(
        code(lamp::geometry::bad_trimesh),
        help("check the mesh file's faces and vertices")
    )]
    BadTriMesh { reason: String },
    /// A body with no shapes at all.
    #[error("a body needs at least one shape")]
    #[diagnostic(code(lamp::geometry::empty_body))]
    EmptyBody,
    /// A shape whose size is not a positive finite number.
    #[error("a shape dimension must be positive and finite, found {value}")]
    #[diagnostic(code(lamp::geometry::bad_dimension))]
    BadDimension { value: f64 },
}
