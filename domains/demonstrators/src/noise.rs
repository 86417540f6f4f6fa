//! Tracking noise: the recorded object poses perturbed as a motion-capture system or a perception
//! pipeline records them, each step on its own, and some of them missed.
//!
//! Only what such a system tracks is perturbed: bodies with a shape (movable and static objects,
//! the world included). Robot configurations come from joint encoders, and markers are where the
//! demonstrator put something (they carry their own placement noise), so both stay as simulated.

use std::collections::BTreeSet;

use lamp_geometry::Pose;
use lamp_spec::TrackingNoise;
use lamp_trajectory::{Step, TrajectoryHeader};
use nalgebra::{Translation3, Unit, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The first ChaCha8 stream of tracking noise: demonstration `i` draws its script from stream `i`
/// (a `u32`), its noise from stream `NOISE_STREAMS + i`, and which poses the tracker misses from
/// stream `DROP_STREAMS + i`, so that no noise stream is a script stream of the same seed,
/// turning the noise on changes no layout, path or cut, and turning drops on changes no pose the
/// tracker sees.
const NOISE_STREAMS: u64 = 1 << 32;
const DROP_STREAMS: u64 = 2 << 32;

/// Below this length a direction drawn in the unit ball is too short to normalise reliably; it
/// is drawn again (a chance of about 1e-18 per draw).
const SHORTEST_AXIS_DRAW: f64 = 1e-6;

/// The generator of demonstration `index`'s tracking noise: seeded with `seed`, on a stream of
/// its own, apart from every demonstration's script stream.
pub fn noise_rng(seed: u64, index: u32) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(NOISE_STREAMS | u64::from(index));
    rng
}

/// The generator of which of demonstration `index`'s tracked poses are missed: seeded with
/// `seed`, on a stream apart from its script and its noise.
pub fn drop_rng(seed: u64, index: u32) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(DROP_STREAMS | u64::from(index));
    rng
}

/// Perturbs every tracked body's pose in `steps`: step by step, body by body in the header's
/// order, three uniform offsets in `[-position, position]` (x, y, z of the world frame), then a
/// turn about a uniformly random axis by a uniform angle in `[0, rotation]`, applied in the world
/// frame about the body's origin (drawn from `rng`); then, with `dropped` above 0, from the
/// second step on, one uniform draw from `drops` per tracked body in the same order, below
/// `dropped` meaning that the tracker missed it: its pose is the one recorded at the step before.
/// The draws run step-major, so the steps of a cut recording carry the same noise as the same
/// steps of the full one. No noise leaves the steps untouched and draws nothing.
pub(crate) fn perturb(
    steps: &mut [Step],
    header: &TrajectoryHeader,
    untracked_types: &BTreeSet<String>,
    noise: TrackingNoise,
    rng: &mut ChaCha8Rng,
    drops: &mut ChaCha8Rng,
) {
    if noise.is_none() {
        return;
    }
    let tracked: Vec<bool> =
        header.bodies.iter().map(|body| !untracked_types.contains(&body.type_name)).collect();
    let mut recorded_before: Option<Vec<Pose>> = None;
    for step in steps {
        for (pose, _) in step.body_poses.iter_mut().zip(&tracked).filter(|(_, tracked)| **tracked) {
            let offset = Vector3::from_fn(|_, _| draw_symmetric(rng, noise.position));
            let turn =
                UnitQuaternion::from_axis_angle(&random_axis(rng), draw_up_to(rng, noise.rotation));
            pose.translation = Translation3::from(pose.translation.vector + offset);
            pose.rotation = turn * pose.rotation;
        }
        if noise.dropped <= 0.0 {
            continue;
        }
        // A missed pose is what a logger has at that instant: the last one the tracker sent
        // (a tf buffer's latest transform), so a run of misses holds one pose.
        if let Some(before) = &recorded_before {
            for (index, _) in tracked.iter().enumerate().filter(|(_, tracked)| **tracked) {
                if drops.random::<f64>() < noise.dropped {
                    step.body_poses[index] = before[index];
                }
            }
        }
        recorded_before = Some(step.body_poses.clone());
    }
}

/// A uniform draw from `[-half, half]`; 0 for a zero half-width (without a draw, so that a
/// noise-free axis does not shift the others' draws).
fn draw_symmetric(rng: &mut ChaCha8Rng, half: f64) -> f64 {
    if half > 0.0 { rng.random_range(-half..=half) } else { 0.0 }
}

/// A uniform draw from `[0, most]`; 0 for a zero bound, without a draw.
fn draw_up_to(rng: &mut ChaCha8Rng, most: f64) -> f64 {
    if most > 0.0 { rng.random_range(0.0..=most) } else { 0.0 }
}

/// A direction uniform on the sphere: a point uniform in the unit ball (by rejection from the
/// cube), normalised.
fn random_axis(rng: &mut ChaCha8Rng) -> Unit<Vector3<f64>> {
    loop {
        let point = Vector3::from_fn(|_, _| rng.random_range(-1.0..=1.0));
        let length = point.norm();
        if length > SHORTEST_AXIS_DRAW && length <= 1.0 {
            return Unit::new_unchecked(point / length);
        }
    }
}
