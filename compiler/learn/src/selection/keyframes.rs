//! Keyframes: the time steps of a pair's relative motion where something happens.
//!
//! A region is where demonstrations stop or change contact, not every pose a carry passes through. So the
//! selection looks only at
//! - **contact changes**: the step where an object of the pair is grasped or let go of, and the step before;
//! - **rest**: the first and the last step of a run of at least [`REST_FRAMES`] steps over which the pair's
//!   relative pose stays still, where motion comes before (an arrival) or after (a departure).
//!
//! "Still" allows for noise: a step is still when it moves less than [`NOISE_MULTIPLE`] times the pair's
//! tenth-percentile change of step ([`noise_tolerance`]), and never less than a floor that noise-free recordings
//! fall under.
//!
//! A rest counts only where the scene goes on moving: the steps of a run in which nothing recorded moves at all
//! ([`scene_pauses`]: the robot waiting out a grasp, or a logger recording on at a fixed rate while everything
//! stands) are not rest of any pair. A gripper that stops over a can for the half second its fingers take rests
//! relative to the table too, at every spot a can was ever picked from; a base standing at a table while the
//! arm works, or an arm tucked while the base drives, rests while the rest of the scene moves.
//!
//! Of the keyframes at one step, each participant keeps only its nearest partner of the other type, both ways:
//! a can let go of in the box also comes to rest relative to every other fixed surface in the room, and those
//! distant relations would otherwise recur as clusters of their own. Two movable objects are the exception
//! ([`keyframes_with_every_partner`]): they count only where they touch, and one may touch several partners.

use std::collections::{BTreeMap, BTreeSet};

use crate::demo::Pose;

/// The fewest steps of unchanged relative pose that count as rest.
pub const REST_FRAMES: usize = 3;
/// A still step moves less than this many times the tenth-percentile change of step: with Gaussian noise of
/// σ per axis, 7.5 σ, where 99.9 % of the steps of a body at rest stay under 5.7 σ.
pub const NOISE_MULTIPLE: f64 = 4.0;
/// Steps below this much translation (m) are still even in a noise-free recording.
pub const STILL_POSITION_FLOOR: f64 = 1e-6;
/// Steps below this much rotation (rad) are still even in a noise-free recording.
pub const STILL_ROTATION_FLOOR: f64 = 1e-5;

/// One participant pair's relative motion through one demonstration.
#[derive(Debug, Clone)]
pub struct Track {
    /// The demonstration's index.
    pub demonstration: usize,
    /// The primary participant's index.
    pub primary: usize,
    /// The secondary participant's index.
    pub secondary: usize,
    /// One frame per recorded step.
    pub frames: Vec<TrackFrame>,
}

/// The pair at one step.
#[derive(Debug, Clone, Copy)]
pub struct TrackFrame {
    /// The held flag of the pair.
    pub g: u8,
    /// The secondary's pose in the primary's frame.
    pub pose: Pose,
    /// Whether one of the two was grasped or let go of at this step.
    pub contact: bool,
    /// Whether nothing in the scene moved into this step ([`scene_pauses`]).
    pub paused: bool,
}

/// A frame of a track where something happens.
#[derive(Debug, Clone, Copy)]
pub struct Keyframe {
    /// The demonstration's index.
    pub demonstration: usize,
    /// The step's index.
    pub step: usize,
    /// The primary participant.
    pub primary: usize,
    /// The secondary participant.
    pub secondary: usize,
    /// The held flag.
    pub g: u8,
    /// The relative pose.
    pub pose: Pose,
    /// Whether the pair's own held flag changes here: the primary grasps or lets go of the secondary.
    pub grip: bool,
}

/// How far a step may move and still be rest, in translation (m) and rotation (rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stillness {
    /// Translation per step.
    pub position: f64,
    /// Rotation per step.
    pub rotation: f64,
}

/// The rest tolerances of a pair, from the noise in its tracks ([`noise_tolerance`]).
pub fn stillness(tracks: &[Track]) -> Stillness {
    noise_tolerance(tracks.iter().map(|track| track.frames.iter().map(|frame| frame.pose)))
}

/// How far a pose may move in one step and still be at rest, from the noise in `sequences` of successive poses:
/// [`NOISE_MULTIPLE`] times the tenth percentile of the change of step (the second difference), never less than
/// [`STILL_POSITION_FLOOR`] and [`STILL_ROTATION_FLOOR`].
///
/// Noise is told from motion by how a step changes, not by how large it is. A body moving smoothly changes its
/// step only by its acceleration times the sampling period squared (at 50 Hz, 0.4 mm for a gripper slowing at
/// 1 m/s²), while noise changes every step by about its own size, in motion and at rest alike. The step itself
/// measures noise only in a recording that rests more than a tenth of the time: at a fixed rate, a motion's
/// slow first and last samples are a tenth of the steps, and a gripper easing into a grasp would count as
/// resting over a metre of approach.
pub fn noise_tolerance<S, P>(sequences: S) -> Stillness
where
    S: IntoIterator<Item = P>,
    P: IntoIterator<Item = Pose>,
{
    let mut moves = Vec::new();
    let mut turns = Vec::new();
    for sequence in sequences {
        let poses: Vec<Pose> = sequence.into_iter().collect();
        for window in poses.windows(3) {
            let [before, now, after] = [&window[0], &window[1], &window[2]];
            let step = now.translation.vector - before.translation.vector;
            let next = after.translation.vector - now.translation.vector;
            moves.push((next - step).norm());
            let turn = now.rotation * before.rotation.inverse();
            let next_turn = after.rotation * now.rotation.inverse();
            turns.push(next_turn.angle_to(&turn));
        }
    }
    Stillness {
        position: (NOISE_MULTIPLE * tenth_percentile(&mut moves)).max(STILL_POSITION_FLOOR),
        rotation: (NOISE_MULTIPLE * tenth_percentile(&mut turns)).max(STILL_ROTATION_FLOOR),
    }
}

impl Stillness {
    /// Whether the move from `before` to `now` is within these tolerances.
    pub fn holds(&self, before: &Pose, now: &Pose) -> bool {
        (now.translation.vector - before.translation.vector).norm() <= self.position
            && now.rotation.angle_to(&before.rotation) <= self.rotation
    }
}

/// Per step of a recording given as world poses per step (every participant's, in one order), whether nothing
/// moved into it: each participant moved no more than its own [`noise_tolerance`] over the recording. The first
/// step has nothing before it and is not a pause.
pub fn scene_pauses(steps: &[&[Pose]]) -> Vec<bool> {
    let participants = steps.first().map_or(0, |poses| poses.len());
    let tolerances: Vec<Stillness> = (0..participants)
        .map(|participant| noise_tolerance([steps.iter().map(|poses| poses[participant])]))
        .collect();
    (0..steps.len())
        .map(|step| {
            step > 0
                && tolerances.iter().enumerate().all(|(participant, still)| {
                    still.holds(&steps[step - 1][participant], &steps[step][participant])
                })
        })
        .collect()
}

fn tenth_percentile(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    values[values.len() / 10]
}

/// The keyframes of a pair's tracks, each participant with its nearest partner only, one per pose and track.
pub fn keyframes(tracks: &[Track], still: Stillness) -> Vec<Keyframe> {
    deduplicate(nearest_partners(events(tracks, still)))
}

/// The keyframes of a pair's tracks with every partner, one per pose and track: for two movable objects, whose
/// keyframes count only where they touch, so that a lintel let go of across two legs relates to both.
pub fn keyframes_with_every_partner(tracks: &[Track], still: Stillness) -> Vec<Keyframe> {
    deduplicate(events(tracks, still))
}

fn events(tracks: &[Track], still: Stillness) -> Vec<Keyframe> {
    let mut found = Vec::new();
    for track in tracks {
        let mut steps = BTreeSet::new();
        let mut grips = BTreeSet::new();
        for (step, frame) in track.frames.iter().enumerate() {
            if frame.contact && step > 0 {
                steps.insert(step - 1);
                steps.insert(step);
                if frame.g != track.frames[step - 1].g {
                    grips.insert(step - 1);
                    grips.insert(step);
                }
            }
        }
        for (first, last) in rests(&track.frames, still) {
            if first > 0 {
                steps.insert(first);
            }
            if last + 1 < track.frames.len() {
                steps.insert(last);
            }
        }
        for step in steps {
            let frame = &track.frames[step];
            found.push(Keyframe {
                demonstration: track.demonstration,
                step,
                primary: track.primary,
                secondary: track.secondary,
                g: frame.g,
                pose: frame.pose,
                grip: grips.contains(&step),
            });
        }
    }
    found
}

/// Runs of frames, each still relative to the one before, with at least [`REST_FRAMES`] − 1 of those steps
/// taken while the scene moved (not [`TrackFrame::paused`]): `(first, last)` indices.
fn rests(frames: &[TrackFrame], still: Stillness) -> Vec<(usize, usize)> {
    let mut runs = Vec::new();
    let mut start = 0;
    let mut moving_steps = 0;
    for step in 1..=frames.len() {
        let continues =
            step < frames.len() && still.holds(&frames[step - 1].pose, &frames[step].pose);
        if continues {
            moving_steps += usize::from(!frames[step].paused);
        } else {
            if moving_steps + 1 >= REST_FRAMES {
                runs.push((start, step - 1));
            }
            start = step;
            moving_steps = 0;
        }
    }
    runs
}

/// Keeps a keyframe only if, at its step, its secondary is the primary's nearest partner and its primary the
/// secondary's nearest partner (ties: the earlier participant index).
fn nearest_partners(keyframes: Vec<Keyframe>) -> Vec<Keyframe> {
    let distance = |k: &Keyframe| k.pose.translation.vector.norm();
    let mut nearest_of_primary: BTreeMap<(usize, usize, usize), (f64, usize)> = BTreeMap::new();
    let mut nearest_of_secondary: BTreeMap<(usize, usize, usize), (f64, usize)> = BTreeMap::new();
    let better = |kept: &(f64, usize), candidate: (f64, usize)| {
        candidate.0 < kept.0 || (candidate.0 == kept.0 && candidate.1 < kept.1)
    };
    for k in &keyframes {
        let by_primary = nearest_of_primary
            .entry((k.demonstration, k.step, k.primary))
            .or_insert((distance(k), k.secondary));
        if better(by_primary, (distance(k), k.secondary)) {
            *by_primary = (distance(k), k.secondary);
        }
        let by_secondary = nearest_of_secondary
            .entry((k.demonstration, k.step, k.secondary))
            .or_insert((distance(k), k.primary));
        if better(by_secondary, (distance(k), k.primary)) {
            *by_secondary = (distance(k), k.primary);
        }
    }
    keyframes
        .into_iter()
        .filter(|k| {
            nearest_of_primary[&(k.demonstration, k.step, k.primary)].1 == k.secondary
                && nearest_of_secondary[&(k.demonstration, k.step, k.secondary)].1 == k.primary
        })
        .collect()
}

/// One keyframe per track, held flag and pose (to 0.1 mm): an arrival and the departure from the same rest are
/// one observation, not two. The one kept is a grip if any of them is.
fn deduplicate(keyframes: Vec<Keyframe>) -> Vec<Keyframe> {
    let mut kept: Vec<Keyframe> = Vec::new();
    let mut index = BTreeMap::new();
    for k in keyframes {
        let position = k.pose.translation.vector.map(|v| (v * 1e4).round() as i64);
        let key =
            (k.demonstration, k.primary, k.secondary, k.g, [position[0], position[1], position[2]]);
        match index.get(&key) {
            Some(&at) => {
                let first: &mut Keyframe = &mut kept[at];
                first.grip |= k.grip;
            }
            None => {
                index.insert(key, kept.len());
                kept.push(k);
            }
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(x: f64, contact: bool) -> TrackFrame {
        TrackFrame { g: 0, pose: Pose::translation(x, 0.0, 0.0), contact, paused: false }
    }

    fn track(xs: &[f64]) -> Track {
        Track {
            demonstration: 0,
            primary: 0,
            secondary: 1,
            frames: xs.iter().map(|x| frame(*x, false)).collect(),
        }
    }

    #[test]
    fn arrivals_and_departures_of_rests_are_keyframes_and_passing_motion_is_not() {
        // Still at 0 from the start, moves through 0.1 and 0.2, rests at 0.3, moves on, rests at the end.
        let path = [0.0, 0.0, 0.0, 0.1, 0.2, 0.3, 0.3, 0.3, 0.3, 0.4, 0.5, 0.5, 0.5];
        let still = Stillness { position: STILL_POSITION_FLOOR, rotation: STILL_ROTATION_FLOOR };
        let found = keyframes(&[track(&path)], still);
        let steps: Vec<usize> = found.iter().map(|k| k.step).collect();
        // The departure from the start (step 2), the arrival at 0.3 (its departure is the same pose), the
        // arrival at the end.
        assert_eq!(steps, [2, 5, 10]);
    }

    #[test]
    fn contact_changes_mark_the_step_and_the_one_before() {
        let mut moving = track(&[0.0, 0.1, 0.2, 0.3, 0.4]);
        moving.frames[3].contact = true;
        let still = Stillness { position: STILL_POSITION_FLOOR, rotation: STILL_ROTATION_FLOOR };
        let steps: Vec<usize> = keyframes(&[moving], still).iter().map(|k| k.step).collect();
        assert_eq!(steps, [2, 3]);
    }

    #[test]
    fn noise_below_the_step_size_still_counts_as_rest() {
        // A millimetre of jitter on every step, at rest and while moving in 5 cm steps, as a tracker adds it.
        let jitter = [0.0, 0.001, -0.0008, 0.0005, -0.0002, 0.0009, -0.0007, 0.0003];
        let clean: Vec<f64> =
            [0.0; 5].into_iter().chain([0.05, 0.1, 0.15]).chain([0.2; 10]).collect();
        let path: Vec<f64> =
            clean.iter().enumerate().map(|(i, x)| x + jitter[i % jitter.len()]).collect();
        let tracks = [track(&path)];
        let still = stillness(&tracks);
        assert!(still.position > 0.002 && still.position < 0.05, "{still:?}");
        let steps: Vec<usize> = keyframes(&tracks, still).iter().map(|k| k.step).collect();
        assert_eq!(steps, [4, 8]);
    }

    /// Positions of a move from 0 to 0.3 m sampled at 50 Hz: accelerating at 1 m/s² to 0.2 m/s, cruising,
    /// slowing at 1 m/s² to rest, then resting for a tenth of a second: rest is less than a tenth of its steps.
    fn eased_move() -> Vec<f64> {
        let (acceleration, speed, period) = (1.0, 0.2, 0.02);
        let ramp = speed / acceleration;
        let ramp_length = 0.5 * acceleration * ramp * ramp;
        let cruise = (0.3 - 2.0 * ramp_length) / speed;
        let total = 2.0 * ramp + cruise;
        let at = |t: f64| -> f64 {
            if t <= ramp {
                0.5 * acceleration * t * t
            } else if t <= ramp + cruise {
                ramp_length + speed * (t - ramp)
            } else if t <= total {
                let left = total - t;
                0.3 - 0.5 * acceleration * left * left
            } else {
                0.3
            }
        };
        (0..=((total + 0.1) / period).round() as usize).map(|k| at(k as f64 * period)).collect()
    }

    #[test]
    fn a_smooth_move_at_a_fixed_rate_is_no_noise_and_its_slow_samples_are_not_rest() {
        let path = eased_move();
        let tracks = [track(&path)];
        let still = stillness(&tracks);
        assert_eq!(still.position, STILL_POSITION_FLOOR, "{still:?}");
        // The slowest samples of the ease-in, 0.2 mm a step, move: the only keyframe is the arrival, after the
        // last sample in motion.
        let arrival = path.iter().position(|x| *x == 0.3).expect("the move ends at 0.3");
        let steps: Vec<usize> = keyframes(&tracks, still).iter().map(|k| k.step).collect();
        assert_eq!(steps, [arrival]);
    }

    #[test]
    fn a_rest_while_nothing_in_the_scene_moves_is_no_rest() {
        // Moves, waits out a grasp while the whole scene stands, moves on.
        let path = [0.0, 0.1, 0.2, 0.2, 0.2, 0.2, 0.2, 0.3, 0.4];
        let still = Stillness { position: STILL_POSITION_FLOOR, rotation: STILL_ROTATION_FLOOR };
        let mut waiting = track(&path);
        for frame in &mut waiting.frames[3..=6] {
            frame.paused = true;
        }
        assert!(keyframes(&[waiting], still).is_empty());
        // The same rest while something else moves (a base standing while the arm works) is one.
        let steps: Vec<usize> = keyframes(&[track(&path)], still).iter().map(|k| k.step).collect();
        assert_eq!(steps, [2]);
    }

    #[test]
    fn the_scene_pauses_where_no_participant_moves() {
        let at = |x: f64| Pose::translation(x, 0.0, 0.0);
        // A table that never moves and a gripper that moves, stops for two steps and moves on.
        let gripper = [0.0, 0.1, 0.2, 0.2, 0.2, 0.3];
        let steps: Vec<[Pose; 2]> = gripper.iter().map(|x| [at(1.0), at(*x)]).collect();
        let world: Vec<&[Pose]> = steps.iter().map(|poses| poses.as_slice()).collect();
        assert_eq!(scene_pauses(&world), [false, false, false, true, true, false]);
    }

    #[test]
    fn each_participant_keeps_its_nearest_partner() {
        // Object 1 comes to rest 0.1 from surface 0 and 2.0 from surface 2.
        let near = track(&[0.3, 0.2, 0.1, 0.1, 0.1]);
        let mut far = track(&[2.2, 2.1, 2.0, 2.0, 2.0]);
        far.primary = 2;
        let still = Stillness { position: STILL_POSITION_FLOOR, rotation: STILL_ROTATION_FLOOR };
        let found = keyframes(&[far, near], still);
        assert_eq!(found.len(), 1);
        assert_eq!((found[0].primary, found[0].step), (0, 2));
    }

    #[test]
    fn an_object_let_go_of_across_two_partners_relates_to_both_when_every_partner_counts() {
        // A lintel (1) comes to rest across two legs, 3.5 cm from one (0) and 4.2 cm from the other (2).
        let near = track(&[0.3, 0.2, 0.035, 0.035, 0.035]);
        let mut other = track(&[0.3, 0.2, 0.042, 0.042, 0.042]);
        other.primary = 2;
        let still = Stillness { position: STILL_POSITION_FLOOR, rotation: STILL_ROTATION_FLOOR };
        let tracks = [near, other];
        assert_eq!(keyframes(&tracks, still).len(), 1);
        let every = keyframes_with_every_partner(&tracks, still);
        let primaries: BTreeSet<usize> = every.iter().map(|k| k.primary).collect();
        assert_eq!(primaries, BTreeSet::from([0, 2]));
    }
}
