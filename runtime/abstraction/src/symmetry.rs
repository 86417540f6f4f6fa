//! Relative poses compared up to the shapes' symmetries.
//!
//! A Jenga block framed at the centre of its bottom face looks the same half turned about its
//! vertical axis. One block resting across another is then one rest that frames show as up to
//! four relative poses: the upper block in the lower's frame or in its half-turned frame, each with
//! the upper's own frame either way. A demonstration shows one of them; a test structure needs
//! whichever its frames make. Comparing relative poses up to the symmetries makes them one.
//!
//! The turns of each frame that map its shape onto itself (lamp-geometry's `axis_symmetries`)
//! make the orbit `{ a⁻¹ · T · b }` of a relative pose `T`, for `a` a turn of the primary and `b`
//! one of the secondary. Its representative is the member whose position lies furthest along
//! [`POSITION_KEY`]; members within [`POSITION_BAND`] of that (a rest on the symmetry's axis, such
//! as a post centred on a plank, whose position every turn keeps) are told apart by how far their
//! x axis, then their y axis, points along [`ROTATION_KEY`]. The key directions are perpendicular
//! to no axis and no diagonal of a frame, so that the representative of a demonstrated rest does
//! not change under the few millimetres and degrees of placement noise. Every member is the same
//! physical placement, so a pose sampled as a representative is a placement like any other.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::snapshot::Pose;

/// Orbit members whose positions lie within this distance (m) along [`POSITION_KEY`] of the
/// furthest are told apart by their rotation.
pub const POSITION_BAND: f64 = 0.002;

/// The direction along which the representative's position lies furthest (normalised).
pub const POSITION_KEY: [f64; 3] = [0.8, 0.5, 0.3];

/// The direction along which the representative's x axis, then y axis, points furthest
/// (normalised).
pub const ROTATION_KEY: [f64; 3] = [0.5, 0.8, 0.3];

/// Below this difference two rotation keys are equal.
const ROTATION_TIE: f64 = 1e-9;

/// The turns that map a type pair's shapes onto themselves: of the primary's frame and of the
/// secondary's, each list starting with the identity.
#[derive(Debug, Clone, PartialEq)]
pub struct PairSymmetry {
    /// The primary's turns.
    pub primary: Vec<UnitQuaternion<f64>>,
    /// The secondary's turns.
    pub secondary: Vec<UnitQuaternion<f64>>,
}

impl PairSymmetry {
    /// The pair's symmetry, or `None` when neither shape has a turn besides the identity (every
    /// relative pose is then its own representative).
    pub fn new(
        primary: Vec<UnitQuaternion<f64>>,
        secondary: Vec<UnitQuaternion<f64>>,
    ) -> Option<PairSymmetry> {
        let with_identity = |mut turns: Vec<UnitQuaternion<f64>>| {
            if !turns.first().is_some_and(|first| first.angle() < ROTATION_TIE) {
                turns.insert(0, UnitQuaternion::identity());
            }
            turns
        };
        let symmetry =
            PairSymmetry { primary: with_identity(primary), secondary: with_identity(secondary) };
        (symmetry.primary.len() > 1 || symmetry.secondary.len() > 1).then_some(symmetry)
    }

    /// Every member `a⁻¹ · relative · b` of `relative`'s orbit, with each of the primary's turns
    /// `a` and each of the secondary's `b` (when `secondary_turns`), the identity pair first.
    pub fn members<'a>(
        &'a self,
        relative: &'a Pose,
        secondary_turns: bool,
    ) -> impl Iterator<Item = Pose> + 'a {
        let secondary = if secondary_turns { &self.secondary[..] } else { &self.secondary[..1] };
        self.primary.iter().flat_map(move |a| {
            let left = turn(a).inverse() * relative;
            secondary.iter().map(move |b| left * turn(b))
        })
    }

    /// `relative` with the primary's frame turned by its `index`-th turn (the identity first): the
    /// same kind of placement at the place the turn maps it to, for drawing one place of an orbit.
    pub fn primary_member(&self, relative: &Pose, index: usize) -> Pose {
        self.primary.get(index).map_or(*relative, |a| turn(a).inverse() * relative)
    }

    /// The representative of `relative`'s orbit.
    pub fn canonical(&self, relative: &Pose) -> Pose {
        let position_key = Vector3::from(POSITION_KEY).normalize();
        let rotation_key = Vector3::from(ROTATION_KEY).normalize();
        // `relative` seen from the primary's frame turned by `a`; a turn of the secondary then
        // leaves its position where it is and only turns it.
        let left = |a: &UnitQuaternion<f64>| turn(a).inverse() * relative;
        let along = |left: &Pose| left.translation.vector.dot(&position_key);
        let axis_key = |rotation: &UnitQuaternion<f64>, axis: Vector3<f64>| {
            (rotation * axis).dot(&rotation_key)
        };
        // Passes over the orbit rather than a list of it, so that learning, which takes every
        // recorded step to its representative, allocates nothing here: the furthest position
        // (one per turn of the primary), the best x axis within its band, then the best y axis
        // among those; the members in the order primary turn, then secondary turn.
        let furthest =
            self.primary.iter().map(|a| along(&left(a))).fold(f64::NEG_INFINITY, f64::max);
        let near = || {
            self.primary.iter().enumerate().filter_map(move |(i, a)| {
                let left = left(a);
                (along(&left) >= furthest - POSITION_BAND).then_some((i, left))
            })
        };
        let mut best_x = f64::NEG_INFINITY;
        for (_, left) in near() {
            for b in &self.secondary {
                best_x = best_x.max(axis_key(&(left.rotation * b), Vector3::x()));
            }
        }
        let mut best: Option<(usize, usize, f64)> = None;
        for (i, left) in near() {
            for (j, b) in self.secondary.iter().enumerate() {
                let rotation = left.rotation * b;
                if axis_key(&rotation, Vector3::x()) < best_x - ROTATION_TIE {
                    continue;
                }
                let y = axis_key(&rotation, Vector3::y());
                if best.is_none_or(|(_, _, best_y)| y > best_y + ROTATION_TIE) {
                    best = Some((i, j, y));
                }
            }
        }
        best.map_or(*relative, |(i, j, _)| left(&self.primary[i]) * turn(&self.secondary[j]))
    }

    /// Checks a deserialised symmetry: finite unit turns, the identity first in each list.
    pub fn validate(&self) -> Result<(), String> {
        for (side, turns) in [("primary", &self.primary), ("secondary", &self.secondary)] {
            if !turns.first().is_some_and(|first| first.angle() < 1e-9) {
                return Err(format!("the {side}'s turns do not start with the identity"));
            }
            let unit = |turn: &UnitQuaternion<f64>| {
                turn.coords.iter().all(|c| c.is_finite()) && (turn.norm() - 1.0).abs() < 1e-9
            };
            if !turns.iter().all(unit) {
                return Err(format!("a turn of the {side} is not a unit quaternion"));
            }
        }
        Ok(())
    }
}

fn turn(rotation: &UnitQuaternion<f64>) -> Isometry3<f64> {
    Isometry3::from_parts(Translation3::identity(), *rotation)
}

/// `{ "primary": [[w, x, y, z], …], "secondary": [[w, x, y, z], …] }`.
#[derive(Serialize, Deserialize)]
struct Wire {
    primary: Vec<[f64; 4]>,
    secondary: Vec<[f64; 4]>,
}

fn to_wire(turns: &[UnitQuaternion<f64>]) -> Vec<[f64; 4]> {
    turns.iter().map(|turn| [turn.w, turn.i, turn.j, turn.k]).collect()
}

fn from_wire(turns: &[[f64; 4]]) -> Vec<UnitQuaternion<f64>> {
    turns
        .iter()
        .map(|[w, i, j, k]| {
            UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(*w, *i, *j, *k))
        })
        .collect()
}

impl Serialize for PairSymmetry {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        Wire { primary: to_wire(&self.primary), secondary: to_wire(&self.secondary) }
            .serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for PairSymmetry {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let wire = Wire::deserialize(deserializer)?;
        let symmetry = PairSymmetry {
            primary: from_wire(&wire.primary),
            secondary: from_wire(&wire.secondary),
        };
        symmetry.validate().map_err(serde::de::Error::custom)?;
        Ok(symmetry)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn half_turn() -> UnitQuaternion<f64> {
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), PI)
    }

    fn blocks() -> PairSymmetry {
        PairSymmetry::new(
            vec![UnitQuaternion::identity(), half_turn()],
            vec![UnitQuaternion::identity(), half_turn()],
        )
        .expect("symmetric")
    }

    fn pose(x: f64, y: f64, z: f64, yaw: f64) -> Pose {
        Pose::from_parts(
            Translation3::new(x, y, z),
            UnitQuaternion::from_euler_angles(0.0, 0.0, yaw),
        )
    }

    fn same(a: &Pose, b: &Pose) -> bool {
        (a.translation.vector - b.translation.vector).norm() < 1e-9
            && a.rotation.angle_to(&b.rotation) < 1e-9
    }

    /// The definition, member by member: every `a⁻¹ · T · b` listed, the furthest along the
    /// position key, then the best x axis within the band, then the first best y axis.
    fn listed_representative(symmetry: &PairSymmetry, relative: &Pose) -> Pose {
        let position_key = Vector3::from(POSITION_KEY).normalize();
        let rotation_key = Vector3::from(ROTATION_KEY).normalize();
        let members: Vec<Pose> = symmetry
            .primary
            .iter()
            .flat_map(|a| symmetry.secondary.iter().map(move |b| (a, b)))
            .map(|(a, b)| turn(a).inverse() * relative * turn(b))
            .collect();
        let along = |m: &Pose| m.translation.vector.dot(&position_key);
        let key = |m: &Pose, axis: Vector3<f64>| (m.rotation * axis).dot(&rotation_key);
        let furthest = members.iter().map(along).fold(f64::NEG_INFINITY, f64::max);
        let near: Vec<&Pose> =
            members.iter().filter(|m| along(m) >= furthest - POSITION_BAND).collect();
        let best_x = near.iter().map(|m| key(m, Vector3::x())).fold(f64::NEG_INFINITY, f64::max);
        let mut best: Option<(&Pose, f64)> = None;
        for m in near.into_iter().filter(|m| key(m, Vector3::x()) >= best_x - ROTATION_TIE) {
            let y = key(m, Vector3::y());
            if best.is_none_or(|(_, best_y)| y > best_y + ROTATION_TIE) {
                best = Some((m, y));
            }
        }
        *best.expect("an orbit has members").0
    }

    #[test]
    fn the_representative_is_the_listed_definition_bit_for_bit() {
        use rand::{RngExt as _, SeedableRng as _};
        let quarter_turns: Vec<UnitQuaternion<f64>> = (0..4)
            .map(|k| UnitQuaternion::from_axis_angle(&Vector3::z_axis(), f64::from(k) * FRAC_PI_2))
            .collect();
        let symmetries = [
            blocks(),
            PairSymmetry::new(quarter_turns.clone(), quarter_turns.clone()).expect("symmetric"),
            PairSymmetry::new(vec![half_turn()], quarter_turns).expect("symmetric"),
        ];
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for symmetry in &symmetries {
            for draw in 0..2000 {
                // Half the draws on the axis, where the position key ties and rotations decide.
                let (x, y) = if draw % 2 == 0 {
                    (rng.random_range(-0.1..0.1), rng.random_range(-0.1..0.1))
                } else {
                    (rng.random_range(-0.001..0.001), rng.random_range(-0.001..0.001))
                };
                let relative = Pose::from_parts(
                    Translation3::new(x, y, rng.random_range(-0.1..0.1)),
                    UnitQuaternion::from_euler_angles(
                        rng.random_range(-PI..PI),
                        rng.random_range(-1.5..1.5),
                        rng.random_range(-PI..PI),
                    ),
                );
                let listed = listed_representative(symmetry, &relative);
                let found = symmetry.canonical(&relative);
                assert_eq!(found.translation, listed.translation, "{relative}");
                assert_eq!(found.rotation, listed.rotation, "{relative}");
            }
        }
    }

    #[test]
    fn the_four_frames_of_one_block_across_another_are_one_pose() {
        // A Jenga block across another: a corner above it, turned a quarter turn.
        let symmetry = blocks();
        let upper = pose(0.051, 0.051, 0.032, FRAC_PI_2);
        let representative = symmetry.canonical(&upper);
        let turn = Isometry3::from_parts(Translation3::identity(), half_turn());
        for member in [upper, turn.inverse() * upper, upper * turn, turn.inverse() * upper * turn] {
            assert!(same(&symmetry.canonical(&member), &representative), "{member}");
        }
        // The other corner and the other turn are other rests.
        let other = symmetry.canonical(&pose(0.051, -0.051, 0.032, FRAC_PI_2));
        assert!(!same(&other, &representative));
    }

    #[test]
    fn placement_noise_keeps_the_representative_of_a_rest() {
        let symmetry = blocks();
        let reference = symmetry.canonical(&pose(0.051, 0.051, 0.032, FRAC_PI_2));
        for (dx, dy, dyaw) in [(0.002, -0.002, 0.02), (-0.003, 0.001, -0.02), (0.0, 0.003, 0.01)] {
            let noisy = symmetry.canonical(&pose(0.051 + dx, 0.051 + dy, 0.032, FRAC_PI_2 + dyaw));
            let moved = (noisy.translation.vector - reference.translation.vector).norm();
            assert!(
                moved < 0.005 && noisy.rotation.angle_to(&reference.rotation) < 0.03,
                "{noisy}"
            );
        }
        // A post centred on a plank, noise on the symmetry's axis: decided by the rotation.
        let post = symmetry.canonical(&pose(0.0, 0.0, 0.0665, 0.3));
        for (dx, dy) in [(0.001, 0.0), (-0.001, 0.0005), (0.0, -0.001)] {
            let noisy = symmetry.canonical(&pose(dx, dy, 0.0665, 0.3));
            assert!(noisy.rotation.angle_to(&post.rotation) < 1e-6, "{noisy}");
        }
    }

    #[test]
    fn without_a_turn_there_is_no_symmetry_and_the_wire_form_round_trips() {
        assert_eq!(PairSymmetry::new(vec![UnitQuaternion::identity()], Vec::new()), None);
        let symmetry = blocks();
        let text = serde_json::to_string(&symmetry).expect("serialises");
        let back: PairSymmetry = serde_json::from_str(&text).expect("deserialises");
        assert_eq!(back.primary.len(), 2);
        assert!(back.secondary[1].angle_to(&half_turn()) < 1e-12);
        let broken = r#"{"primary":[[0.0,0.0,0.0,1.0]],"secondary":[[1.0,0.0,0.0,0.0]]}"#;
        assert!(serde_json::from_str::<PairSymmetry>(broken).is_err(), "identity first");
    }
}
