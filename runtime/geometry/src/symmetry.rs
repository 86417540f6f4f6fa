//! The turns that map a compound shape onto itself.
//!
//! A Jenga block or a Keva plank (a box whose frame is at the centre of its bottom face) looks
//! the same turned half a turn about its vertical axis; a cube standing on its bottom face, after
//! any quarter turn. Learning uses this: a demonstration of one block resting on another shows
//! the same rest from each of the blocks' symmetric frames. Only the 24 turns that map the frame's
//! axes onto axes are tried: they are the symmetries primitive shapes have about their frames
//! (a cylinder's free turn about its axis is left to the learner, which finds it in the data).

use nalgebra::{Matrix3, Rotation3, UnitQuaternion};

use crate::math::{Pose, Real};
use crate::shape::Shape;

/// How far a part's transformed pose may be from its image's to count as the same (m, and the
/// entries of a rotation matrix).
const TOLERANCE: Real = 1e-9;

/// The turns about the frame's origin, among those that map axes onto axes, that map the
/// compound shape `parts` onto itself: the identity first, then in a fixed order. A shape with a
/// convex hull or a mesh part, or no part, has the identity alone.
pub fn axis_symmetries(parts: &[(Pose, Shape)]) -> Vec<UnitQuaternion<Real>> {
    if parts.is_empty() {
        return vec![UnitQuaternion::identity()];
    }
    axis_turns()
        .into_iter()
        .filter(|turn| {
            let turned = Pose::from_parts(nalgebra::Translation3::identity(), *turn);
            parts.iter().all(|(pose, shape)| {
                let image = turned * pose;
                parts.iter().any(|(other, other_shape)| {
                    other_shape == shape && self_symmetric(shape, &(other.inverse() * image))
                })
            })
        })
        .collect()
}

/// The turns of [`axis_symmetries`] about the frame's z axis: those that keep a shape standing as
/// it is declared (z up), identity first. A block framed at its centre may also be turned over,
/// but what rests on it would then be below it in its frame.
pub fn upright_symmetries(parts: &[(Pose, Shape)]) -> Vec<UnitQuaternion<Real>> {
    let up = nalgebra::Vector3::z();
    axis_symmetries(parts).into_iter().filter(|turn| (turn * up - up).norm() < TOLERANCE).collect()
}

/// The axis (0, 1, 2: x, y, z of the frame) about which the compound shape is round, so that every
/// turn about it maps the shape onto itself: every part a sphere centred on that axis, or a
/// cylinder centred on it and running along it. `None` for any other shape, or no part.
pub fn round_axis(parts: &[(Pose, Shape)]) -> Option<usize> {
    (0..3).find(|&axis| {
        !parts.is_empty()
            && parts.iter().all(|(pose, shape)| {
                let centre = pose.translation.vector;
                let on_axis = (0..3).all(|other| other == axis || centre[other].abs() < TOLERANCE);
                let along = || {
                    let own = pose.rotation * nalgebra::Vector3::z();
                    (own[axis].abs() - 1.0).abs() < TOLERANCE
                };
                on_axis
                    && match shape {
                        Shape::Sphere { .. } => true,
                        Shape::Cylinder { .. } => along(),
                        _ => false,
                    }
            })
    })
}

/// The 24 proper rotations whose matrices are signed permutations, the identity first.
fn axis_turns() -> Vec<UnitQuaternion<Real>> {
    let mut turns = Vec::new();
    let permutations = [[0, 1, 2], [1, 2, 0], [2, 0, 1], [0, 2, 1], [2, 1, 0], [1, 0, 2]];
    for permutation in permutations {
        for signs in 0..8u8 {
            let mut matrix: Matrix3<Real> = Matrix3::zeros();
            for (row, &column) in permutation.iter().enumerate() {
                matrix[(row, column)] = if signs & (1 << row) == 0 { 1.0 } else { -1.0 };
            }
            if (matrix.determinant() - 1.0).abs() < TOLERANCE {
                let rotation = Rotation3::from_matrix_unchecked(matrix);
                turns.push(UnitQuaternion::from_rotation_matrix(&rotation));
            }
        }
    }
    turns
}

/// Whether `relative` (a pose in the shape's frame) maps the primitive onto itself.
fn self_symmetric(shape: &Shape, relative: &Pose) -> bool {
    if relative.translation.vector.norm() > TOLERANCE {
        return false;
    }
    let matrix = relative.rotation.to_rotation_matrix().into_inner();
    match shape {
        Shape::Sphere { .. } => true,
        Shape::Cylinder { .. } => (matrix[(2, 2)].abs() - 1.0).abs() < TOLERANCE,
        Shape::Box { half_extents } => {
            let signed_permutation = matrix
                .iter()
                .all(|entry| entry.abs() < TOLERANCE || (entry.abs() - 1.0).abs() < TOLERANCE);
            let extents = matrix.abs() * half_extents;
            signed_permutation && (extents - half_extents).amax() < TOLERANCE
        }
        Shape::ConvexHull { .. } | Shape::TriMesh { .. } => {
            (matrix - Matrix3::identity()).amax() < TOLERANCE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use nalgebra::Vector3;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn at(x: Real, y: Real, z: Real) -> Pose {
        Pose::translation(x, y, z)
    }

    fn box_of(x: Real, y: Real, z: Real) -> Shape {
        Shape::Box { half_extents: Vec3::new(x, y, z) }
    }

    fn about(axis: Vector3<Real>, angle: Real) -> UnitQuaternion<Real> {
        UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle)
    }

    fn same(a: &UnitQuaternion<Real>, b: &UnitQuaternion<Real>) -> bool {
        a.angle_to(b) < 1e-9
    }

    #[test]
    fn a_plank_on_its_bottom_face_looks_the_same_half_turned_about_its_vertical_axis() {
        // A Keva plank: 117 × 23 × 7 mm, frame at the centre of its bottom face.
        let plank = [(at(0.0, 0.0, 0.0035), box_of(0.0585, 0.0115, 0.0035))];
        let turns = axis_symmetries(&plank);
        assert_eq!(turns.len(), 2, "{turns:?}");
        assert!(same(&turns[0], &UnitQuaternion::identity()));
        assert!(same(&turns[1], &about(Vector3::z(), PI)));
        // Framed at its centre it also turns over, about each axis; standing, only the half turn.
        let centred = [(Pose::identity(), box_of(0.0585, 0.0115, 0.0035))];
        assert_eq!(axis_symmetries(&centred).len(), 4);
        let standing = upright_symmetries(&centred);
        assert_eq!(standing.len(), 2);
        assert!(same(&standing[1], &about(Vector3::z(), PI)));
    }

    #[test]
    fn a_cube_on_its_bottom_face_has_the_four_quarter_turns_a_cube_at_its_centre_all_24() {
        let on_bottom = [(at(0.0, 0.0, 0.02), box_of(0.02, 0.02, 0.02))];
        let turns = axis_symmetries(&on_bottom);
        assert_eq!(turns.len(), 4);
        assert!(turns.iter().any(|turn| same(turn, &about(Vector3::z(), FRAC_PI_2))));
        let centred = [(Pose::identity(), box_of(0.02, 0.02, 0.02))];
        assert_eq!(axis_symmetries(&centred).len(), 24);
    }

    #[test]
    fn a_cylinder_keeps_the_turns_about_its_axis_and_an_off_centre_part_breaks_symmetry() {
        let can = [(at(0.0, 0.0, 0.06), Shape::Cylinder { radius: 0.03, half_height: 0.06 })];
        assert_eq!(axis_symmetries(&can).len(), 4);
        // A handle on one side: only the identity.
        let mug = [
            (at(0.0, 0.0, 0.05), Shape::Cylinder { radius: 0.04, half_height: 0.05 }),
            (at(0.05, 0.0, 0.05), box_of(0.01, 0.005, 0.03)),
        ];
        assert_eq!(axis_symmetries(&mug).len(), 1);
        // Two handles opposite each other: the half turn again.
        let pot = [
            (at(0.0, 0.0, 0.05), Shape::Cylinder { radius: 0.04, half_height: 0.05 }),
            (at(0.05, 0.0, 0.05), box_of(0.01, 0.005, 0.03)),
            (at(-0.05, 0.0, 0.05), box_of(0.01, 0.005, 0.03)),
        ];
        assert_eq!(axis_symmetries(&pot).len(), 2);
    }

    #[test]
    fn a_can_is_round_about_its_axis_and_a_box_or_an_off_axis_part_is_not() {
        let can = [(at(0.0, 0.0, 0.06), Shape::Cylinder { radius: 0.03, half_height: 0.06 })];
        assert_eq!(round_axis(&can), Some(2));
        let lying = [(
            Pose::from_parts(
                nalgebra::Translation3::new(0.06, 0.0, 0.0),
                about(Vector3::y(), FRAC_PI_2),
            ),
            Shape::Cylinder { radius: 0.03, half_height: 0.06 },
        )];
        assert_eq!(round_axis(&lying), Some(0));
        let knob = [
            (at(0.0, 0.0, 0.05), Shape::Cylinder { radius: 0.04, half_height: 0.05 }),
            (at(0.0, 0.0, 0.12), Shape::Sphere { radius: 0.01 }),
        ];
        assert_eq!(round_axis(&knob), Some(2));
        let mug = [
            (at(0.0, 0.0, 0.05), Shape::Cylinder { radius: 0.04, half_height: 0.05 }),
            (at(0.05, 0.0, 0.05), box_of(0.01, 0.005, 0.03)),
        ];
        assert_eq!(round_axis(&mug), None);
        assert_eq!(round_axis(&[(at(0.0, 0.0, 0.02), box_of(0.02, 0.02, 0.02))]), None);
        assert_eq!(round_axis(&[]), None);
    }

    #[test]
    fn a_mesh_or_no_shape_has_the_identity_alone() {
        let hull = Shape::ConvexHull {
            points: vec![
                crate::Point3::new(0.0, 0.0, 0.0),
                crate::Point3::new(1.0, 0.0, 0.0),
                crate::Point3::new(0.0, 1.0, 0.0),
                crate::Point3::new(0.0, 0.0, 1.0),
            ],
        };
        assert_eq!(axis_symmetries(&[(Pose::identity(), hull)]).len(), 1);
        assert_eq!(axis_symmetries(&[]).len(), 1);
    }
}
