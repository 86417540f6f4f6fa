//! Axes along which no demonstration ever moves a pair: what they hold says which participants these are, not
//! where one was put relative to the other.
//!
//! A mobile base drives on the floor, so a table's height in the base's frame is the table's own height, the
//! same from the first step to the last. Rests at a low table and at a high counter then differ only along that
//! axis, and a grid that split them would learn "standing at the table" and "standing at the counter" as two
//! places, so that no action learned at one applies at the other. The selection therefore clusters keyframes
//! without such an axis and gives it one cell across every value the demonstrations show.
//!
//! An axis is fixed when, in every track, the spread of the coordinate between its 1st and 99th percentile
//! stays within the stillness tolerance of one step: tracking noise never exceeds it, and an object lifted, a
//! plank slid or a gripper moved for even a hundredth of a track does.

use super::keyframes::{Stillness, Track};

/// The share of a track's steps cut from each end of a coordinate's spread: single noisy samples do not make
/// an axis move.
pub const TAIL_SHARE: f64 = 0.01;

/// Per position axis, whether every track keeps the coordinate within `still` over its whole length.
pub fn fixed_axes(tracks: &[Track], still: Stillness) -> [bool; 3] {
    let mut fixed = [!tracks.is_empty(); 3];
    for track in tracks {
        for (axis, is_fixed) in fixed.iter_mut().enumerate() {
            if *is_fixed && spread(track, axis) > still.position {
                *is_fixed = false;
            }
        }
    }
    fixed
}

/// The spread of one coordinate of a track between its tail percentiles.
fn spread(track: &Track, axis: usize) -> f64 {
    let mut values: Vec<f64> =
        track.frames.iter().map(|frame| frame.pose.translation.vector[axis]).collect();
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let last = values.len() - 1;
    let cut = (TAIL_SHARE * values.len() as f64).floor() as usize;
    values[last - cut.min(last)] - values[cut.min(last)]
}

#[cfg(test)]
mod tests {
    use super::super::keyframes::TrackFrame;
    use super::*;
    use crate::demo::Pose;

    fn track(demonstration: usize, points: &[[f64; 3]]) -> Track {
        Track {
            demonstration,
            primary: 0,
            secondary: 1,
            frames: points
                .iter()
                .map(|p| TrackFrame {
                    g: 0,
                    pose: Pose::translation(p[0], p[1], p[2]),
                    contact: false,
                    paused: false,
                })
                .collect(),
        }
    }

    #[test]
    fn a_height_that_differs_between_tracks_but_never_within_one_is_fixed() {
        let still = Stillness { position: 0.004, rotation: 0.01 };
        // A base drives up to a low table in one demonstration and to a high counter in another.
        let low: Vec<[f64; 3]> =
            (0..200).map(|i| [2.0 - 0.01 * i as f64, 0.1 + 0.001 * i as f64, 0.73]).collect();
        let high: Vec<[f64; 3]> = (0..200).map(|i| [0.5 + 0.002 * i as f64, -0.3, 0.90]).collect();
        assert_eq!(fixed_axes(&[track(0, &low), track(1, &high)], still), [false, false, true]);
    }

    #[test]
    fn noise_does_not_move_an_axis_and_a_short_lift_does() {
        let still = Stillness { position: 0.004, rotation: 0.01 };
        // A millimetre of deterministic jitter around a resting height.
        let jitter = |i: usize| 0.001 * (((i * 7919) % 13) as f64 / 6.0 - 1.0);
        let resting: Vec<[f64; 3]> = (0..500).map(|i| [0.0, 0.0, 0.02 + jitter(i)]).collect();
        assert!(fixed_axes(&[track(0, &resting)], still)[2]);
        // The same object lifted 5 cm for 20 of 500 steps in one demonstration moves along z.
        let mut lifted = resting.clone();
        for point in &mut lifted[200..220] {
            point[2] += 0.05;
        }
        assert!(!fixed_axes(&[track(0, &resting), track(1, &lifted)], still)[2]);
    }
}
