//! How far apart two keyframe poses of the secondary are: the farthest that any point of its shape moves from one
//! to the other.
//!
//! Position alone cannot tell rests apart that differ in how the secondary is turned. A Keva plank standing
//! against another's end, its face one way or the other, has its origin 7 mm from where it is in the other rest;
//! compared by position, single linkage joins the two at 8 mm, and with poses folded up to the planks' half turns
//! the joined group is no longer stable, so a rest that eight demonstrations show is lost. Compared by how far the
//! plank's corners move, the two rests are a plank length apart.
//!
//! The points measured are the corners of the secondary's bounding box in its own frame. A shape round about an
//! axis (a can) looks the same at every turn about it, so only the two ends of that axis count: a can set down at
//! any yaw is at one place. A shape that looks the same after a turn (a cube after a quarter turn) is at the same
//! place turned so, so two poses are as far apart as the nearest of the second's turned frames is from the first.
//! A secondary of unknown shape (a marker) is measured at its origin: its position alone. For two poses with the
//! same rotation every point moves as the origin does, so the distance is the distance of the positions.

use nalgebra::{Point3, UnitQuaternion, Vector3};

use crate::demo::Pose;

/// The points of the secondary that two of its poses are compared at, and the turns of its frame that map its
/// shape onto itself (the identity first).
#[derive(Debug, Clone, PartialEq)]
pub struct Probes {
    points: Vec<Point3<f64>>,
    turns: Vec<UnitQuaternion<f64>>,
}

/// The probes of one pose: per turn of the secondary (the identity first), where its points are.
#[derive(Debug, Clone, PartialEq)]
pub struct Placed(Vec<Vec<[f64; 3]>>);

impl Probes {
    /// Only the secondary's origin: the distance of positions.
    pub fn origin() -> Probes {
        Probes { points: vec![Point3::origin()], turns: vec![UnitQuaternion::identity()] }
    }

    /// The corners of the box `(low, high)` around the secondary's shape in its frame; with `round`, the axis the
    /// shape is round about, the two ends of that axis within the box. `turns`, the turns of its frame that map
    /// the shape onto itself (the identity may be left out), make poses that differ by one of them one place.
    pub fn of_box(
        low: [f64; 3],
        high: [f64; 3],
        round: Option<usize>,
        turns: &[UnitQuaternion<f64>],
    ) -> Probes {
        let points = match round {
            Some(axis) => [low[axis], high[axis]]
                .into_iter()
                .map(|along| {
                    let mut point = Point3::origin();
                    point[axis] = along;
                    point
                })
                .collect(),
            None => (0..8)
                .map(|corner| {
                    Point3::from(Vector3::from_fn(|axis, _| {
                        if (corner >> axis) & 1 == 0 { low[axis] } else { high[axis] }
                    }))
                })
                .collect(),
        };
        let identity = UnitQuaternion::identity();
        let others = turns.iter().filter(|turn| turn.angle_to(&identity) > 1e-9).copied();
        Probes { points, turns: std::iter::once(identity).chain(others).collect() }
    }

    /// Where the probes are with the secondary at `pose`, the translation's `fixed` axes taken as zero:
    /// [`fixed_axes`](super::fixed_axes) says which participants a pose is of along them, not where.
    pub fn placed(&self, pose: &Pose, fixed: [bool; 3]) -> Placed {
        let mut pose = *pose;
        for (axis, fixed) in fixed.into_iter().enumerate() {
            if fixed {
                pose.translation.vector[axis] = 0.0;
            }
        }
        Placed(
            self.turns
                .iter()
                .map(|turn| {
                    let turned = pose * Pose::from_parts(nalgebra::Translation3::identity(), *turn);
                    self.points.iter().map(|point| (turned * point).coords.into()).collect()
                })
                .collect(),
        )
    }
}

/// How far apart two placed poses are ([`Probes::placed`]): the largest distance between corresponding probes,
/// for the nearest of the second's turned frames.
pub fn distance(a: &Placed, b: &Placed) -> f64 {
    let first = &a.0[0];
    b.0.iter()
        .map(|turned| {
            first
                .iter()
                .zip(turned)
                .map(|(p, q)| {
                    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
                })
                .fold(0.0, f64::max)
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    fn at(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> Pose {
        Pose::from_parts(
            Translation3::new(x, y, z),
            UnitQuaternion::from_euler_angles(roll, pitch, yaw),
        )
    }

    const FREE: [bool; 3] = [false; 3];

    #[test]
    fn the_same_turn_gives_the_distance_of_positions() {
        let plank = Probes::of_box([-0.0585, -0.0115, 0.0], [0.0585, 0.0115, 0.007], None, &[]);
        let (a, b) =
            (at(0.06, 0.0, -0.035, 0.3, -1.2, 0.5), at(0.067, 0.001, -0.035, 0.3, -1.2, 0.5));
        let expected = (0.007f64.powi(2) + 0.001f64.powi(2)).sqrt();
        let d = distance(&plank.placed(&a, FREE), &plank.placed(&b, FREE));
        assert!((d - expected).abs() < 1e-12, "{d}");
        let origin = Probes::origin();
        let d = distance(&origin.placed(&a, FREE), &origin.placed(&b, FREE));
        assert!((d - expected).abs() < 1e-12, "{d}");
    }

    #[test]
    fn a_plank_turned_over_is_as_far_as_its_corners_move() {
        // Standing on its end, face one way, then face the other: the origin moves 7 mm, the far end of the
        // plank's 117 mm length swings across.
        let plank = Probes::of_box([-0.0585, -0.0115, 0.0], [0.0585, 0.0115, 0.007], None, &[]);
        let half_pi = std::f64::consts::FRAC_PI_2;
        let (a, b) =
            (at(0.06, 0.0, -0.035, 0.0, half_pi, 0.0), at(0.067, 0.0, -0.035, 0.0, -half_pi, 0.0));
        let d = distance(&plank.placed(&a, FREE), &plank.placed(&b, FREE));
        assert!(d > 0.1, "{d}");
        // The origin alone sees 7 mm.
        let origin = Probes::origin();
        let d = distance(&origin.placed(&a, FREE), &origin.placed(&b, FREE));
        assert!((d - 0.007).abs() < 1e-12, "{d}");
    }

    #[test]
    fn a_round_shape_turned_about_its_axis_has_not_moved() {
        let can = Probes::of_box([-0.033, -0.033, 0.0], [0.033, 0.033, 0.12], Some(2), &[]);
        let (a, b) = (at(0.1, 0.2, 0.0, 0.0, 0.0, 0.3), at(0.1, 0.2, 0.0, 0.0, 0.0, 2.9));
        assert!(distance(&can.placed(&a, FREE), &can.placed(&b, FREE)) < 1e-12);
        // Tipped by 0.1 rad, its top moves 12 cm × 0.1.
        let tipped = at(0.1, 0.2, 0.0, 0.1, 0.0, 0.3);
        let d = distance(&can.placed(&a, FREE), &can.placed(&tipped, FREE));
        assert!((d - 2.0 * 0.12 * (0.05f64).sin()).abs() < 1e-12, "{d}");
    }

    #[test]
    fn a_fixed_axis_does_not_separate_poses() {
        let origin = Probes::origin();
        let (a, b) = (at(0.9, 0.0, 0.73, 0.0, 0.0, 0.0), at(0.9, 0.0, 0.90, 0.0, 0.0, 0.0));
        let fixed = [false, false, true];
        assert_eq!(distance(&origin.placed(&a, fixed), &origin.placed(&b, fixed)), 0.0);
    }

    #[test]
    fn a_cube_turned_by_a_quarter_is_where_it_was() {
        let quarter = UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2);
        let turns = [quarter, quarter * quarter, quarter * quarter * quarter];
        let cube = Probes::of_box([-0.02, -0.02, 0.0], [0.02, 0.02, 0.04], None, &turns);
        let (a, b) = (at(0.0, 0.0, 0.041, 0.0, 0.0, 0.02), at(0.0, 0.0, 0.041, 0.0, 0.0, 1.59));
        let d = distance(&cube.placed(&a, FREE), &cube.placed(&b, FREE));
        // 1.59 rad is a quarter turn and 0.0192 rad more than 0.02: the corners, 28 mm out, move by that much.
        let beyond = 1.59 - 0.02 - std::f64::consts::FRAC_PI_2;
        let expected = 2.0 * (2.0 * 0.02f64.powi(2)).sqrt() * (beyond / 2.0).abs().sin();
        assert!((d - expected).abs() < 1e-12, "{d} against {expected}");
        // Without its turns, the cube's corners swing a quarter of the way round.
        let plain = Probes::of_box([-0.02, -0.02, 0.0], [0.02, 0.02, 0.04], None, &[]);
        assert!(distance(&plain.placed(&a, FREE), &plain.placed(&b, FREE)) > 0.035);
        // The same either way round.
        let back = distance(&cube.placed(&b, FREE), &cube.placed(&a, FREE));
        assert!((back - d).abs() < 1e-12, "{back} against {d}");
    }
}
