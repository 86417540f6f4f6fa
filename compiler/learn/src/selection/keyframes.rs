//! Keyframes: the time steps of a pair's relative motion where something happens.
//!
//! A region is where demonstrations stop or change contact, not every pose a carry passes through. So the
//! selection looks only at
//! - **contact changes**: the step where an object of the pair is grasped or let go of, and the step before;
//! - **rest**: the first and the last step of a run of at least [`REST_FRAMES`] steps over which the pair's
//!   relative pose stays still, where motion comes before (an arrival) or after (a departure).
//!
//! "Still" allows for tracking noise: a step is still when it moves less than [`NOISE_MULTIPLE`] times the
//! tenth-percentile step of the pair (a recording is still far more than a tenth of the time), and never less
//! than a floor that noise-free recordings fall under.
//!
//! Of the keyframes at one step, each participant keeps only its nearest partner of the other type, both ways:
//! a can let go of in the box also comes to rest relative to every other fixed surface in the room, and those
//! distant relations would otherwise recur as clusters of their own. Two movable objects are the exception
//! ([`keyframes_with_every_partner`]): they count only where they touch, and one may touch several partners.

use std::collections::{BTreeMap, BTreeSet};

use crate::demo::Pose;

/// The fewest steps of unchanged relative pose that count as rest.
pub const REST_FRAMES: usize = 3;
/// A still step moves less than this many times the pair's tenth-percentile step: with Gaussian tracking
/// noise, about three times the median still step, which noise alone almost never exceeds.
pub const NOISE_MULTIPLE: f64 = 5.0;
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

/// The rest tolerances of a pair, from the size of its steps.
pub fn stillness(tracks: &[Track]) -> Stillness {
    let mut moves = Vec::new();
    let mut turns = Vec::new();
    for track in tracks {
        for pair in track.frames.windows(2) {
            moves.push((pair[1].pose.translation.vector - pair[0].pose.translation.vector).norm());
            turns.push(pair[1].pose.rotation.angle_to(&pair[0].pose.rotation));
        }
    }
    Stillness {
        position: (NOISE_MULTIPLE * tenth_percentile(&mut moves)).max(STILL_POSITION_FLOOR),
        rotation: (NOISE_MULTIPLE * tenth_percentile(&mut turns)).max(STILL_ROTATION_FLOOR),
    }
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

/// Runs of at least [`REST_FRAMES`] frames, each still relative to the one before: `(first, last)` indices.
fn rests(frames: &[TrackFrame], still: Stillness) -> Vec<(usize, usize)> {
    let mut runs = Vec::new();
    let mut start = 0;
    for step in 1..=frames.len() {
        let continues = step < frames.len() && {
            let (before, now) = (&frames[step - 1].pose, &frames[step].pose);
            (now.translation.vector - before.translation.vector).norm() <= still.position
                && now.rotation.angle_to(&before.rotation) <= still.rotation
        };
        if !continues {
            if step - start >= REST_FRAMES {
                runs.push((start, step - 1));
            }
            start = step;
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
        TrackFrame { g: 0, pose: Pose::translation(x, 0.0, 0.0), contact }
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
        // A millimetre of jitter while at rest, 5 cm steps while moving.
        let jitter = [0.0, 0.001, -0.0008, 0.0005, 0.0];
        let mut path: Vec<f64> = jitter.to_vec();
        path.extend([0.05, 0.1, 0.15]);
        path.extend(jitter.iter().map(|j| 0.2 + j));
        path.extend(jitter.iter().map(|j| 0.2 + j));
        let tracks = [track(&path)];
        let still = stillness(&tracks);
        assert!(still.position > 0.002 && still.position < 0.05, "{still:?}");
        let steps: Vec<usize> = keyframes(&tracks, still).iter().map(|k| k.step).collect();
        assert_eq!(steps, [4, 8]);
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
