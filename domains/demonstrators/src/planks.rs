//! Keva plank structures: planks lying flat or standing upright, pis (two upright legs and a
//! lintel across them), log-cabin layers, and the training structures the Keva demonstrator
//! builds from them (at most three planks).
//!
//! A plank's frame is at the centre of its bottom face (the 117 × 23 mm face), x along its
//! length, z through its thickness. A structure is a list of plank poses in its anchor's frame
//! (the anchor lies on the table top, z up), in building order: a plank is placed only once every
//! plank it rests on is, and a leg is placed before the leg whose grasp side faces it (the
//! gripper holds a plank by its top face, so it comes at an upright leg from that face's side).
//! The constructions are those of `domains/tools/make_problems.py`, which writes the bundled
//! structures.

use std::f64::consts::FRAC_PI_2;

use lamp_geometry::Pose;
use lamp_world::RESTING_GAP;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::skills::pose;

/// Centre-to-centre distance of a pi's legs (the reference's 7.75 cm).
pub(crate) const PI_SPAN: f64 = 0.0775;
/// Centre-to-centre distance of the two planks of a log-cabin layer.
pub(crate) const LOG_SPAN: f64 = 0.09;

/// The size of a plank: length (its x), width (its y) and thickness (its z), metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PlankSize {
    pub(crate) length: f64,
    pub(crate) width: f64,
    pub(crate) thickness: f64,
}

impl PlankSize {
    /// A plank lying flat, centred at (x, y), its length along `yaw`, on a support whose top is
    /// at height `base`, 1 mm above it.
    pub(crate) fn flat(&self, x: f64, y: f64, base: f64, yaw: f64) -> Pose {
        pose(x, y, base + RESTING_GAP, 0.0, 0.0, yaw)
    }

    /// A plank standing on its end, 1 mm above `base`, centred at (x, y), its width along `yaw`
    /// and its thickness across it: pitch −90° turns its length up and yaw + 90° puts its frame's
    /// z (the thickness, from the bottom face) along −(across), so the frame sits half a
    /// thickness to the other side of the centre.
    pub(crate) fn upright(&self, x: f64, y: f64, base: f64, yaw: f64) -> Pose {
        let (sin, cos) = yaw.sin_cos();
        let half = self.thickness / 2.0;
        let (ox, oy) = (-sin * half, cos * half);
        pose(
            x + ox,
            y + oy,
            base + RESTING_GAP + self.length / 2.0,
            0.0,
            -FRAC_PI_2,
            yaw + FRAC_PI_2,
        )
    }

    /// A pi on a support at height `base`: two upright legs [`PI_SPAN`] apart across `yaw` (each
    /// 23 mm wide along `yaw`), then a lintel lying across their tops. The leg on the +across side
    /// comes first: the other leg's grasp side faces away from it.
    pub(crate) fn pi(&self, base: f64) -> [Pose; 3] {
        [
            self.upright(0.0, PI_SPAN / 2.0, base, 0.0),
            self.upright(0.0, -PI_SPAN / 2.0, base, 0.0),
            self.flat(0.0, 0.0, base + RESTING_GAP + self.length, FRAC_PI_2),
        ]
    }

    /// Height of the top face of a flat plank resting on the table.
    fn flat_top(&self) -> f64 {
        RESTING_GAP + self.thickness
    }
}

/// A training structure: the plank poses in building order; the demonstration places all but
/// the last beforehand and moves the last.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Training {
    pub(crate) name: &'static str,
    pub(crate) poses: Vec<Pose>,
}

/// The training structures and their shares of the draws. Every local arrangement of the
/// bundled structures is one placement of one of them (docs/demonstrations.md):
/// - `flat`, `upright`: one plank on the table, lying flat or standing upright (a first leg);
/// - `legs`: a pi's second leg beside the first;
/// - `pi`: a lintel across two legs;
/// - `on_flat`: a leg standing on a flat plank (a lintel) at either leg position along it;
/// - `legs_on_flat`: the second leg beside the first, both on a flat plank (stacked pis, the
///   house's walls);
/// - `across`: a flat plank across two parallel flat ones (a log-cabin layer), at either slot,
///   turned +90° or −90° from them;
/// - `post`: an upright centred on a flat plank, its width along it (the house's post);
/// - `roof`: a flat plank centred on an upright (the house's roof).
const SHARES: [(&str, f64); 9] = [
    ("flat", 0.05),
    ("upright", 0.05),
    ("legs", 0.06),
    ("pi", 0.14),
    ("on_flat", 0.12),
    ("legs_on_flat", 0.08),
    ("across", 0.34),
    ("post", 0.08),
    ("roof", 0.08),
];

/// The training structure called `name` (random choices: which slot, which turn, which first).
pub(crate) fn training(size: &PlankSize, name: &str, rng: &mut ChaCha8Rng) -> Option<Training> {
    let on_flat = size.flat_top();
    let lintel = size.flat(0.0, 0.0, 0.0, FRAC_PI_2);
    let [first_leg, second_leg, top] = size.pi(0.0);
    let (name, poses) = match name {
        "flat" => ("flat", vec![size.flat(0.0, 0.0, 0.0, 0.0)]),
        "upright" => ("upright", vec![size.upright(0.0, 0.0, 0.0, 0.0)]),
        "legs" => ("legs", vec![first_leg, second_leg]),
        "pi" => ("pi", vec![first_leg, second_leg, top]),
        "on_flat" => {
            let side = if rng.random::<bool>() { 1.0 } else { -1.0 };
            ("on_flat", vec![lintel, size.upright(0.0, side * PI_SPAN / 2.0, on_flat, 0.0)])
        }
        "legs_on_flat" => {
            let [first, second, _] = size.pi(on_flat);
            ("legs_on_flat", vec![lintel, first, second])
        }
        "across" => {
            // The lower pair along x or along y of the anchor, the upper plank turned a quarter
            // turn from it, at either slot; either lower plank first.
            let lower_along_y = rng.random::<bool>();
            let slot = if rng.random::<bool>() { 1.0 } else { -1.0 };
            let half = LOG_SPAN / 2.0;
            let (mut lower, upper) = if lower_along_y {
                (
                    vec![
                        size.flat(half, 0.0, 0.0, FRAC_PI_2),
                        size.flat(-half, 0.0, 0.0, FRAC_PI_2),
                    ],
                    size.flat(0.0, slot * half, on_flat, 0.0),
                )
            } else {
                (
                    vec![size.flat(0.0, half, 0.0, 0.0), size.flat(0.0, -half, 0.0, 0.0)],
                    size.flat(slot * half, 0.0, on_flat, FRAC_PI_2),
                )
            };
            if rng.random::<bool>() {
                lower.swap(0, 1);
            }
            lower.push(upper);
            ("across", lower)
        }
        "post" => ("post", vec![lintel, size.upright(0.0, 0.0, on_flat, FRAC_PI_2)]),
        "roof" => (
            "roof",
            vec![
                size.upright(0.0, 0.0, 0.0, FRAC_PI_2),
                size.flat(0.0, 0.0, RESTING_GAP + size.length, 0.0),
            ],
        ),
        _ => return None,
    };
    Some(Training { name, poses })
}

/// The names of the training structures, in draw order.
#[cfg(test)]
pub(crate) fn training_names() -> impl Iterator<Item = &'static str> {
    SHARES.iter().map(|(name, _)| *name)
}

/// Draws a training structure of at most `objects` planks, by the shares of [`SHARES`] among
/// those that fit.
pub(crate) fn draw_training(size: &PlankSize, objects: usize, rng: &mut ChaCha8Rng) -> Training {
    let fits = |name: &str| {
        // Only the count matters; the probe's draws are thrown away.
        let mut probe = ChaCha8Rng::seed_from_u64(0);
        training(size, name, &mut probe).is_some_and(|t| t.poses.len() <= objects)
    };
    let eligible: Vec<(&str, f64)> =
        SHARES.iter().copied().filter(|(name, _)| fits(name)).collect();
    let total: f64 = eligible.iter().map(|(_, share)| share).sum();
    let mut u = rng.random::<f64>() * total;
    let mut chosen = eligible.first().map_or("flat", |(name, _)| name);
    for (name, share) in &eligible {
        chosen = name;
        if u < *share {
            break;
        }
        u -= share;
    }
    // Every name in SHARES is a training structure.
    training(size, chosen, rng)
        .unwrap_or_else(|| Training { name: "flat", poses: vec![size.flat(0.0, 0.0, 0.0, 0.0)] })
}

#[cfg(test)]
mod tests {
    use lamp_geometry::math::relative_pose;

    use super::*;

    const KEVA: PlankSize = PlankSize { length: 0.117, width: 0.023, thickness: 0.007 };

    #[test]
    fn a_pi_matches_the_bundled_structure_and_its_lintel_rests_a_millimetre_above_the_legs() {
        let [a, b, lintel] = KEVA.pi(0.0);
        let p = |pose: &Pose| pose.translation.vector;
        // The bundled pi_tower_3: legs at y = 0.04225 and −0.03525, 0.0595 up; lintel 0.119 up.
        assert!((p(&a).y - 0.04225).abs() < 1e-12 && (p(&a).z - 0.0595).abs() < 1e-12);
        assert!((p(&b).y + 0.03525).abs() < 1e-12);
        assert!((p(&lintel).z - 0.119).abs() < 1e-12);
        // The leg's top is 0.0585 along its x from its frame; the lintel 1 mm above it.
        let top = relative_pose(&a, &lintel).translation.vector;
        assert!((top.x - (KEVA.length / 2.0 + RESTING_GAP)).abs() < 1e-12, "{top:?}");
    }

    #[test]
    fn the_first_leg_is_the_one_whose_grasp_side_faces_the_other() {
        let [first, second, _] = KEVA.pi(0.0);
        // The gripper holds a plank from its frame's +z side.
        let side = |leg: &Pose| leg.rotation * nalgebra::Vector3::z();
        let towards_second = second.translation.vector - first.translation.vector;
        assert!(side(&first).dot(&towards_second) > 0.0);
        let towards_first = -towards_second;
        assert!(side(&second).dot(&towards_first) < 0.0);
    }

    #[test]
    fn every_training_structure_fits_in_three_planks() {
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        for name in training_names() {
            let training = training(&KEVA, name, &mut rng).expect("a training structure");
            assert!((1..=3).contains(&training.poses.len()), "{name}");
        }
    }

    #[test]
    fn every_training_structure_stands_under_gravity_in_every_variant() {
        use lamp_geometry::{Shape, Vec3};
        use lamp_physics::{PhysicsBody, first_unsettled};
        let table = [(
            pose(0.0, 0.0, -0.025, 0.0, 0.0, 0.0),
            Shape::Box { half_extents: Vec3::new(0.6, 0.6, 0.025) },
        )];
        let plank = [(
            pose(0.0, 0.0, KEVA.thickness / 2.0, 0.0, 0.0, 0.0),
            Shape::Box {
                half_extents: Vec3::new(KEVA.length / 2.0, KEVA.width / 2.0, KEVA.thickness / 2.0),
            },
        )];
        let names = ["plank1", "plank2", "plank3"];
        for name in training_names() {
            // Enough draws to meet every slot, turn and order.
            for seed in 0..8 {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                let training = training(&KEVA, name, &mut rng).expect("a training structure");
                let mut bodies = vec![PhysicsBody {
                    name: "table",
                    parts: &table,
                    pose: Pose::identity(),
                    fixed: true,
                }];
                for (index, at) in training.poses.iter().enumerate() {
                    bodies.push(PhysicsBody {
                        name: names[index],
                        parts: &plank,
                        pose: *at,
                        fixed: false,
                    });
                }
                let drift = first_unsettled(&bodies, RESTING_GAP).expect("planks simulate");
                assert_eq!(drift, None, "{name}, draw {seed}");
            }
        }
    }
}
