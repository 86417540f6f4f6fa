//! Outlines of shapes: points whose projection's convex hull is the shape's silhouette in an
//! axis-aligned view, and the 2-D convex hull itself.

use lamp_geometry::{Point3, Pose, Shape};

/// Points around each circle of a cylinder or sphere: a 32-gon deviates from the circle by
/// 0.5 % of its radius, well under a pixel at the sizes drawn.
pub(crate) const CIRCLE_POINTS: usize = 32;

/// World points of `shape` placed at `pose`, enough to outline it in any axis-aligned view.
///
/// Boxes give their corners, cylinders their two end circles, spheres three great circles (one
/// in each coordinate plane, so the one in the view plane is the exact silhouette), hulls and
/// meshes their vertices.
pub(crate) fn world_points(pose: &Pose, shape: &Shape) -> Vec<Point3> {
    let local: Vec<Point3> = match shape {
        Shape::Box { half_extents: h } => {
            let mut corners = Vec::with_capacity(8);
            for sx in [-1.0, 1.0] {
                for sy in [-1.0, 1.0] {
                    for sz in [-1.0, 1.0] {
                        corners.push(Point3::new(sx * h.x, sy * h.y, sz * h.z));
                    }
                }
            }
            corners
        }
        Shape::Cylinder { radius, half_height } => {
            let mut points = Vec::with_capacity(2 * CIRCLE_POINTS);
            for z in [-*half_height, *half_height] {
                for (c, s) in circle() {
                    points.push(Point3::new(radius * c, radius * s, z));
                }
            }
            points
        }
        Shape::Sphere { radius } => {
            let mut points = Vec::with_capacity(3 * CIRCLE_POINTS);
            for (c, s) in circle() {
                points.push(Point3::new(radius * c, radius * s, 0.0));
                points.push(Point3::new(radius * c, 0.0, radius * s));
                points.push(Point3::new(0.0, radius * c, radius * s));
            }
            points
        }
        Shape::ConvexHull { points } => points.clone(),
        Shape::TriMesh { vertices, .. } => vertices.clone(),
    };
    local.iter().map(|point| pose * point).collect()
}

/// Unit-circle points (cos, sin), starting at angle zero.
fn circle() -> impl Iterator<Item = (f64, f64)> {
    (0..CIRCLE_POINTS).map(|i| {
        let angle = std::f64::consts::TAU * i as f64 / CIRCLE_POINTS as f64;
        (angle.cos(), angle.sin())
    })
}

/// The convex hull of 2-D points, counter-clockwise from the lowest-leftmost point, without
/// collinear points (Andrew's monotone chain). Fewer than three distinct points come back as
/// they are, deduplicated.
pub(crate) fn convex_hull(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut sorted: Vec<(f64, f64)> =
        points.iter().copied().filter(|(x, y)| x.is_finite() && y.is_finite()).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    sorted.dedup();
    if sorted.len() < 3 {
        return sorted;
    }
    let mut hull = half_hull(sorted.iter());
    hull.extend(half_hull(sorted.iter().rev()));
    hull
}

/// One chain of the monotone-chain hull, without its last point (the first of the other chain).
fn half_hull<'a>(points: impl Iterator<Item = &'a (f64, f64)>) -> Vec<(f64, f64)> {
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut chain: Vec<(f64, f64)> = Vec::new();
    for &point in points {
        while chain.len() >= 2
            && cross(chain[chain.len() - 2], chain[chain.len() - 1], point) <= 0.0
        {
            chain.pop();
        }
        chain.push(point);
    }
    chain.pop();
    chain
}

#[cfg(test)]
mod tests {
    use super::*;
    use lamp_geometry::Vec3;

    #[test]
    fn hull_of_a_square_with_inner_and_edge_points() {
        let points = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.5, 0.5), (0.5, 0.0)];
        let hull = convex_hull(&points);
        assert_eq!(hull, vec![(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
    }

    #[test]
    fn degenerate_hulls_keep_their_distinct_points() {
        assert_eq!(convex_hull(&[(1.0, 1.0), (1.0, 1.0)]), vec![(1.0, 1.0)]);
        assert_eq!(convex_hull(&[(0.0, 0.0), (2.0, 0.0)]).len(), 2);
    }

    #[test]
    fn a_box_has_its_corners_in_the_world() {
        let pose = Pose::translation(1.0, 2.0, 3.0);
        let shape = Shape::Box { half_extents: Vec3::new(0.1, 0.2, 0.3) };
        let points = world_points(&pose, &shape);
        assert_eq!(points.len(), 8);
        let max_z = points.iter().map(|p| p.z).fold(f64::MIN, f64::max);
        assert!((max_z - 3.3).abs() < 1e-12);
    }

    #[test]
    fn a_lying_cylinder_is_long_along_world_x() {
        // A cylinder rotated a quarter turn about y lies along world x.
        let pose = Pose::new(Vec3::zeros(), Vec3::new(0.0, std::f64::consts::FRAC_PI_2, 0.0));
        let shape = Shape::Cylinder { radius: 0.1, half_height: 0.5 };
        let points = world_points(&pose, &shape);
        let max_x = points.iter().map(|p| p.x).fold(f64::MIN, f64::max);
        let max_z = points.iter().map(|p| p.z).fold(f64::MIN, f64::max);
        assert!((max_x - 0.5).abs() < 1e-9);
        assert!((max_z - 0.1).abs() < 1e-9);
    }
}
