//! Tracking noise: with `noise D A`, every tracked body's recorded pose lies within D per axis
//! and A of the noise-free recording, step by step; robot configurations, times, grasps and
//! markers are as recorded without noise; the same seed gives the same bytes, however the
//! demonstrations are generated; and no noise gives the noise-free files byte for byte.

mod support;

use std::sync::LazyLock;

use lamp_demonstrators::{
    DemoError, Demonstration, Demonstrator, Simulation, generate, generate_all,
};
use lamp_spec::{Spec, TrackingNoise};
use lamp_world::SpecWorld;

static PACKING: LazyLock<(Spec, SpecWorld)> = LazyLock::new(|| support::domain("packing"));
static KEVA: LazyLock<(Spec, SpecWorld)> = LazyLock::new(|| support::domain("keva"));

/// `noise 2 mm 1 deg`.
const NOISE: TrackingNoise =
    TrackingNoise { position: 0.002, rotation: 0.017_453_292_519_943_295, dropped: 0.0 };

/// Rounding of composing a pose with a small offset and turn.
const ROUNDING: f64 = 1e-12;

fn packing(cut_fraction: f64, noise: TrackingNoise) -> Simulation {
    Simulation {
        demonstrator: Demonstrator::Packing,
        count: 4,
        cut_fraction,
        objects: 1,
        seed: 5,
        noise,
        rate: None,
    }
}

fn bytes(demonstrations: &[Demonstration]) -> Vec<Vec<u8>> {
    demonstrations.iter().map(|demo| demo.to_bytes().expect("a demonstration encodes")).collect()
}

/// Asserts that `noisy` is `clean` with each body's pose within the noise (or, for a body of an
/// untracked type, equal), robots and times unchanged; returns the largest offset along an axis
/// and the largest turn seen among tracked bodies.
fn within_noise(
    clean: &Demonstration,
    noisy: &Demonstration,
    noise: TrackingNoise,
    untracked: &[&str],
) -> (f64, f64) {
    let (clean, noisy) = (&clean.trajectory, &noisy.trajectory);
    assert_eq!(clean.header.bodies, noisy.header.bodies);
    assert_eq!(clean.header.robots, noisy.header.robots);
    assert_eq!(clean.steps.len(), noisy.steps.len(), "noise drops no step");
    let (mut offset, mut turn) = (0.0_f64, 0.0_f64);
    for (index, (a, b)) in clean.steps.iter().zip(&noisy.steps).enumerate() {
        assert_eq!(a.time_nanoseconds, b.time_nanoseconds);
        assert_eq!(a.robots, b.robots, "step {index}: configurations and grasps are the encoders'");
        for ((body, pa), pb) in clean.header.bodies.iter().zip(&a.body_poses).zip(&b.body_poses) {
            if untracked.contains(&body.type_name.as_str()) {
                assert_eq!(pa, pb, "step {index}: {} is not tracked", body.name);
                continue;
            }
            let along = (pb.translation.vector - pa.translation.vector).abs().max();
            let angle = pa.rotation.angle_to(&pb.rotation);
            assert!(along <= noise.position + ROUNDING, "step {index}, {}: {along} m", body.name);
            assert!(angle <= noise.rotation + ROUNDING, "step {index}, {}: {angle} rad", body.name);
            offset = offset.max(along);
            turn = turn.max(angle);
        }
    }
    (offset, turn)
}

#[test]
fn object_poses_stay_within_the_noise_and_nothing_else_changes() {
    let (_, world) = &*PACKING;
    let clean = generate_all(world, &packing(0.5, TrackingNoise::NONE), |_| {}).unwrap();
    let noisy = generate_all(world, &packing(0.5, NOISE), |_| {}).unwrap();
    let (mut offset, mut turn) = (0.0_f64, 0.0_f64);
    for (clean, noisy) in clean.iter().zip(&noisy) {
        assert_eq!(clean.cut_at, noisy.cut_at, "the noise does not change where a cut falls");
        let (o, t) = within_noise(clean, noisy, NOISE, &[]);
        offset = offset.max(o);
        turn = turn.max(t);
        let provenance = &noisy.trajectory.header.provenance;
        assert_eq!(provenance["tracking_noise"], "0.002 m 0.017453292519943295 rad");
        assert!(!clean.trajectory.header.provenance.contains_key("tracking_noise"));
    }
    // Hundreds of draws of each: the largest come near the bounds, so the noise is applied whole.
    assert!(offset > 0.9 * NOISE.position, "largest offset {offset} m");
    assert!(turn > 0.9 * NOISE.rotation, "largest turn {turn} rad");
}

#[test]
fn the_same_seed_gives_the_same_bytes_whatever_the_threads() {
    let (_, world) = &*PACKING;
    let simulation = packing(0.5, NOISE);
    let parallel = bytes(&generate_all(world, &simulation, |_| {}).unwrap());
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let serial = pool.install(|| bytes(&generate_all(world, &simulation, |_| {}).unwrap()));
    assert_eq!(parallel, serial);
    let one: Vec<Demonstration> =
        (0..4).map(|i| generate(world, &simulation, i).unwrap()).collect();
    assert_eq!(parallel, bytes(&one));
    let other = generate(world, &Simulation { seed: 6, ..simulation }, 0).unwrap();
    assert_ne!(parallel[0], other.to_bytes().unwrap(), "another seed, other noise");
}

#[test]
fn zero_noise_gives_the_noise_free_files() {
    let (_, world) = &*PACKING;
    let zero = TrackingNoise { position: 0.0, rotation: 0.0, dropped: 0.0 };
    let absent = bytes(&generate_all(world, &packing(0.5, TrackingNoise::NONE), |_| {}).unwrap());
    assert_eq!(bytes(&generate_all(world, &packing(0.5, zero), |_| {}).unwrap()), absent);
}

/// The noise of a step does not depend on where the recording is cut: a cut demonstration's
/// steps carry the same noise as the same steps of the full one.
#[test]
fn a_cut_recording_carries_the_noise_of_the_full_one() {
    let (_, world) = &*PACKING;
    let full = generate(world, &packing(0.0, NOISE), 1).unwrap();
    let cut = generate(world, &packing(1.0, NOISE), 1).unwrap();
    let kept = cut.cut_at.expect("a cut fraction of 1 cuts every demonstration");
    assert_eq!(cut.trajectory.steps, full.trajectory.steps[..kept]);
}

#[test]
fn only_one_kind_of_noise_perturbs_only_that_part() {
    let (_, world) = &*PACKING;
    let clean = generate(world, &packing(0.5, TrackingNoise::NONE), 0).unwrap();
    let position_only = TrackingNoise { position: 0.002, rotation: 0.0, dropped: 0.0 };
    let shifted = generate(world, &packing(0.5, position_only), 0).unwrap();
    let (offset, turn) = within_noise(&clean, &shifted, position_only, &[]);
    assert!(offset > 0.0 && turn < ROUNDING, "{offset} m, {turn} rad");
    let rotation_only = TrackingNoise { position: 0.0, rotation: 0.017, dropped: 0.0 };
    let turned = generate(world, &packing(0.5, rotation_only), 0).unwrap();
    let (offset, turn) = within_noise(&clean, &turned, rotation_only, &[]);
    assert!(offset < ROUNDING && turn > 0.0, "{offset} m, {turn} rad");
}

/// Keva's marker type and world.
fn keva_marker() -> (&'static lamp_spec::ObjectType, &'static SpecWorld) {
    let (spec, world) = &*KEVA;
    let marker = spec
        .object_types
        .iter()
        .find(|ty| ty.mobility == lamp_spec::Mobility::Marker)
        .expect("Keva declares a marker type");
    (marker, world)
}

/// One Keva demonstration of three planks, uncut, recorded with `noise` at `rate`.
fn keva_once(noise: TrackingNoise, rate: Option<f64>) -> Simulation {
    Simulation {
        demonstrator: Demonstrator::Keva,
        count: 1,
        cut_fraction: 0.0,
        objects: 3,
        seed: 5,
        noise,
        rate,
    }
}

/// Keva records a marker at each placed plank: where the demonstrator put it, not a tracked body,
/// so it stays as recorded while the planks and the table move.
#[test]
fn markers_are_not_tracked() {
    let (marker, world) = keva_marker();
    let keva = |noise| keva_once(noise, None);
    let clean = generate(world, &keva(TrackingNoise::NONE), 0).unwrap();
    let noisy = generate(world, &keva(NOISE), 0).unwrap();
    assert!(
        clean.trajectory.header.bodies.iter().any(|body| body.type_name == marker.name),
        "the demonstration records a marker"
    );
    let (offset, turn) = within_noise(&clean, &noisy, NOISE, &[marker.name.as_str()]);
    assert!(offset > 0.0 && turn > 0.0);
}

#[test]
fn noise_out_of_range_is_refused_as_a_typed_error() {
    let (_, world) = &*PACKING;
    for noise in [
        TrackingNoise { position: -0.001, rotation: 0.0, dropped: 0.0 },
        TrackingNoise { position: 0.2, rotation: 0.0, dropped: 0.0 },
        TrackingNoise { position: 0.0, rotation: 1.0, dropped: 0.0 },
        TrackingNoise { position: f64::NAN, rotation: 0.0, dropped: 0.0 },
        TrackingNoise { position: 0.0, rotation: 0.0, dropped: 0.95 },
        TrackingNoise { position: 0.0, rotation: 0.0, dropped: -0.1 },
    ] {
        let result = generate(world, &packing(0.5, noise), 0);
        assert!(
            matches!(&result, Err(DemoError::Unsupported { reason, .. }) if reason.starts_with("tracking noise")),
            "{noise:?}: {result:?}"
        );
    }
}

/// With `dropped F`, a tracked pose missed at a step is the one recorded at the step before, as a
/// logger's latest transform is: about a share F of the tracked poses after the first step repeat
/// the step before while the clean recording moves; the rest carry the noise as without drops;
/// robots, times and untracked markers are untouched.
#[test]
fn dropped_poses_repeat_the_pose_recorded_before() {
    let (marker, world) = keva_marker();
    let keva = |noise| keva_once(noise, Some(50.0));
    let dropping = TrackingNoise { dropped: 0.2, ..NOISE };
    let clean = generate(world, &keva(TrackingNoise::NONE), 0).unwrap();
    let noisy = generate(world, &keva(NOISE), 0).unwrap();
    let dropped = generate(world, &keva(dropping), 0).unwrap();
    let provenance = &dropped.trajectory.header.provenance;
    assert_eq!(provenance.get("dropped_poses").map(String::as_str), Some("0.2"));
    assert!(!noisy.trajectory.header.provenance.contains_key("dropped_poses"));
    let (clean, noisy, dropped) = (&clean.trajectory, &noisy.trajectory, &dropped.trajectory);
    assert_eq!(clean.steps.len(), dropped.steps.len(), "a missed pose drops no step");
    let (mut tracked, mut repeated) = (0_usize, 0_usize);
    for index in 1..clean.steps.len() {
        let (step, before) = (&dropped.steps[index], &dropped.steps[index - 1]);
        assert_eq!(step.time_nanoseconds, clean.steps[index].time_nanoseconds);
        assert_eq!(step.robots, clean.steps[index].robots, "the encoders miss nothing");
        for (body, ty) in clean.header.bodies.iter().enumerate() {
            let pose = step.body_poses[body];
            if ty.type_name == marker.name {
                assert_eq!(pose, clean.steps[index].body_poses[body], "markers are not tracked");
                continue;
            }
            tracked += 1;
            if pose == before.body_poses[body] {
                repeated += 1;
            } else {
                // Seen: the pose with this step's noise, as without drops.
                assert_eq!(pose, noisy.steps[index].body_poses[body], "step {index}, {}", ty.name);
            }
        }
    }
    let share = repeated as f64 / tracked as f64;
    assert!((0.15..0.25).contains(&share), "{repeated} of {tracked} poses repeated");
}
