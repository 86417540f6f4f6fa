//! The learner's shape oracle: the spec's object types' collision shapes answer whether two bodies of a type fit at
//! once at given poses, which decides the `auto` clear and nowhere relations (see `docs/learning.md`).
//!
//! Robot parts are not object types, so their shape is unknown to the oracle and their sides stay on.

use std::collections::BTreeMap;

use lamp_geometry::{CollisionShape, Pose, distance, intersects};
use lamp_learn::ShapeOracle;
use lamp_world::SpecWorld;

/// Every object type's collision shape with its bounding radius about the type's origin.
pub struct SpecShapes {
    shapes: BTreeMap<String, (CollisionShape, f64)>,
    /// The types whose shape is round about an axis of their frame, with that axis.
    round: BTreeMap<String, usize>,
}

impl SpecShapes {
    /// The shapes of a loaded spec's object types; a type whose parts make no collision shape (none at all) has no
    /// known shape.
    pub fn new(world: &SpecWorld) -> SpecShapes {
        let shapes = world
            .type_parts
            .iter()
            .filter_map(|(name, parts)| {
                let shape = CollisionShape::compound(parts).ok()?;
                let radius = bounding_radius(&shape);
                Some((name.clone(), (shape, radius)))
            })
            .collect();
        let round = world
            .type_parts
            .iter()
            .filter_map(|(name, parts)| Some((name.clone(), lamp_geometry::round_axis(parts)?)))
            .collect();
        SpecShapes { shapes, round }
    }
}

/// The largest distance from the shape's origin to any of its points is at most the farthest corner of its
/// bounding box at the origin.
fn bounding_radius(shape: &CollisionShape) -> f64 {
    let aabb = shape.aabb(&Pose::identity());
    let mut radius: f64 = 0.0;
    for corner in 0..8 {
        let point = nalgebra::Vector3::from_fn(|axis, _| {
            if (corner >> axis) & 1 == 0 { aabb.mins[axis] } else { aabb.maxs[axis] }
        });
        radius = radius.max(point.norm());
    }
    radius
}

impl ShapeOracle for SpecShapes {
    /// Tries pairs in order and stops at the first that fits: centres farther apart than twice the bounding radius
    /// fit without a collision query; otherwise the shapes must not touch (no margin).
    fn two_fit(&self, type_name: &str, poses: &[Pose]) -> Option<bool> {
        let (shape, radius) = self.shapes.get(type_name)?;
        let reach = 2.0 * radius;
        for (index, first) in poses.iter().enumerate() {
            for second in &poses[index + 1..] {
                let apart = (first.translation.vector - second.translation.vector).norm() > reach;
                if apart || !intersects(shape, first, shape, second) {
                    return Some(true);
                }
            }
        }
        Some(false)
    }

    fn gap(&self, primary: &str, secondary: &str, relative: &Pose) -> Option<f64> {
        let (primary, _) = self.shapes.get(primary)?;
        let (secondary, _) = self.shapes.get(secondary)?;
        Some(distance(primary, &Pose::identity(), secondary, relative))
    }

    fn round_axis(&self, type_name: &str) -> Option<usize> {
        self.round.get(type_name).copied()
    }

    fn bounding_box(&self, type_name: &str) -> Option<([f64; 3], [f64; 3])> {
        let (shape, _) = self.shapes.get(type_name)?;
        let aabb = shape.aabb(&Pose::identity());
        Some(([0, 1, 2].map(|axis| aabb.mins[axis]), [0, 1, 2].map(|axis| aabb.maxs[axis])))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lamp_geometry::Shape;

    fn can() -> SpecShapes {
        let parts = vec![(
            Pose::translation(0.0, 0.0, 0.06),
            Shape::Cylinder { radius: 0.033, half_height: 0.06 },
        )];
        let shape = CollisionShape::compound(&parts).expect("a valid cylinder");
        let radius = bounding_radius(&shape);
        SpecShapes {
            shapes: BTreeMap::from([("can".to_string(), (shape, radius))]),
            round: BTreeMap::from([("can".to_string(), 2)]),
        }
    }

    #[test]
    fn the_bounding_radius_reaches_the_farthest_corner() {
        let radius = can().shapes["can"].1;
        // The box around the cylinder reaches (±0.033, ±0.033, 0.12) from the base.
        assert!((radius - (2.0 * 0.033f64.powi(2) + 0.12f64.powi(2)).sqrt()).abs() < 1e-9);
    }

    #[test]
    fn two_cans_fit_side_by_side_but_not_closer_than_a_diameter() {
        let shapes = can();
        let at = |x: f64| Pose::translation(x, 0.0, 0.0);
        assert_eq!(shapes.two_fit("can", &[at(0.0), at(0.05)]), Some(false));
        assert_eq!(shapes.two_fit("can", &[at(0.0), at(0.065)]), Some(false));
        assert_eq!(shapes.two_fit("can", &[at(0.0), at(0.02), at(0.07)]), Some(true));
        // Stacked cans fit once the lower one's top is below the upper one's base.
        let up = Pose::translation(0.0, 0.0, 0.13);
        assert_eq!(shapes.two_fit("can", &[at(0.0), up]), Some(true));
        assert_eq!(shapes.two_fit("gripper", &[at(0.0), at(1.0)]), None);
        assert_eq!(shapes.two_fit("can", &[at(0.0)]), Some(false));
    }

    #[test]
    fn the_gap_between_two_cans_is_between_their_surfaces() {
        let shapes = can();
        let gap = |pose: Pose| shapes.gap("can", "can", &pose).expect("known shapes");
        // Side by side, 10 cm between the axes of two cans 6.6 cm across.
        assert!((gap(Pose::translation(0.10, 0.0, 0.0)) - 0.034).abs() < 1e-6);
        // One standing on the other's top, and one sunk into it.
        assert!(gap(Pose::translation(0.0, 0.0, 0.12)) < 1e-6);
        assert_eq!(gap(Pose::translation(0.0, 0.0, 0.05)), 0.0);
        assert_eq!(shapes.gap("can", "gripper", &Pose::identity()), None);
    }
}
