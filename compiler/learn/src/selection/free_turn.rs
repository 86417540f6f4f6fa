//! A turn the demonstrations leave free: the secondary seen at every angle about one axis of its own frame, in
//! every group of the pair (a round can set down at any yaw, or grasped by a magnet at any yaw).
//!
//! Such a turn puts the rotation vector anywhere on a circle, so no grid of equal bins per component keeps both the
//! turn whole and the other rotations narrow: a can under a magnet at every yaw is a rotation by π about every
//! horizontal axis, and only one bin per component holds it, which then admits a can held on its side as well.
//! Taken from one demonstrated rotation, in the secondary's frame, the same rotations are turns about one axis, and
//! one bin along that axis keeps them while the other two components stay as fine as the demonstrations allow.
//!
//! The test: from the first keyframe of the best-supported group, every keyframe's rotation is split into a swing
//! and a twist about the axis; the turn is free when, in every group, the twists leave no gap wider than
//! [`FREE_GAP`] around the circle. A few turns (a can grasped from one of its four sides) leave wider gaps and
//! stay separate cells. Few keyframes drawn at every angle leave wide gaps by chance too (15 leave about 80°), so a
//! group whose twists are many distinct turns ([`LEAST_DISTINCT`]) may leave a gap as wide as uniformly drawn
//! twists leave but once in a hundred, up to three eighths of a turn ([`allowed_gap`]).

use std::f64::consts::{PI, TAU};

use nalgebra::UnitQuaternion;

use crate::discretise::FreeTurn;
use lamp_abstraction::free_turn::twist;

/// The widest gap between the twists of a group's keyframes, around the circle, for the turn to count as free: a
/// sixth of a turn. Four grasp sides leave gaps of a quarter turn; 40 twists drawn at random leave about 35°.
pub const FREE_GAP: f64 = PI / 3.0;

/// Twists farther apart than this are distinct turns (7°): a grasp side's spread is a few degrees.
const DISTINCT_TWIST: f64 = 7.0 * PI / 180.0;

/// The least number of distinct turns for a group of few keyframes to count as turning freely: more than the
/// sides of any object grasped side by side (a hexagonal prism has six).
pub const LEAST_DISTINCT: usize = 7;

/// The widest gap few keyframes may leave and still turn freely, however few they are: three eighths of a turn.
/// Fewer than about 15 twists drawn at random leave wider gaps often, and then cannot tell a free turn from
/// twists over a part of the circle (grasps from one side of an object).
const WIDEST_ALLOWED_GAP: f64 = 0.75 * PI;

/// How rarely twists drawn uniformly around the circle leave a gap wider than [`allowed_gap`]: once in a hundred.
const UNIFORM_MISS: f64 = 0.01;

/// The keyframe rotations of one group, and how many independent draws they are: the demonstrations they come
/// from (one demonstration's keyframes share its grasp, and count once).
pub struct GroupRotations {
    pub rotations: Vec<UnitQuaternion<f64>>,
    pub draws: usize,
}

/// The free turn of groups of keyframe rotations (the best-supported group first), if there is one: of the axes
/// about which every group turns freely, the one whose widest gap, over the groups, is least.
pub fn free_turn(groups: &[GroupRotations]) -> Option<FreeTurn> {
    let reference = *groups.first()?.rotations.first()?;
    let free_gaps = [0, 1, 2].map(|axis| {
        groups.iter().try_fold(0.0, |widest: f64, group| {
            let twists = twists(&group.rotations, &reference, axis);
            turns_freely(&twists, group.draws).then(|| widest.max(widest_gap_of(&twists)))
        })
    });
    let (axis, _) = free_gaps
        .iter()
        .enumerate()
        .filter_map(|(axis, gap)| gap.map(|gap| (axis, gap)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    Some(FreeTurn { reference, axis })
}

/// Whether sorted twists, `draws` independent ones among them, look drawn from the whole circle: no gap wider than
/// [`FREE_GAP`], or many distinct turns leaving no gap wider than as many uniform draws would ([`allowed_gap`]).
fn turns_freely(twists: &[f64], draws: usize) -> bool {
    let gap = widest_gap_of(twists);
    gap < FREE_GAP || (distinct_turns(twists) >= LEAST_DISTINCT && gap < allowed_gap(draws))
}

/// The gap that `count` twists drawn uniformly around the circle exceed with probability [`UNIFORM_MISS`] (the
/// chance that some gap exceeds a share `x` of the circle is at most `count · (1 − x)^(count − 1)`), at most
/// [`WIDEST_ALLOWED_GAP`].
pub(crate) fn allowed_gap(count: usize) -> f64 {
    if count < 2 {
        return 0.0;
    }
    let count = count as f64;
    let uniform = TAU * (1.0 - (UNIFORM_MISS / count).powf(1.0 / (count - 1.0)));
    uniform.min(WIDEST_ALLOWED_GAP)
}

/// How many distinct turns sorted twists make: runs of twists each within [`DISTINCT_TWIST`] of the next count
/// once.
fn distinct_turns(twists: &[f64]) -> usize {
    let (Some(first), Some(last)) = (twists.first(), twists.last()) else { return 0 };
    let around = first + TAU - last;
    let separations = twists.windows(2).map(|pair| pair[1] - pair[0]).chain([around]);
    separations.filter(|gap| *gap > DISTINCT_TWIST).count().max(1)
}

/// The twists of `rotations` about `axis` from `reference`, sorted.
fn twists(
    rotations: &[UnitQuaternion<f64>],
    reference: &UnitQuaternion<f64>,
    axis: usize,
) -> Vec<f64> {
    let mut twists: Vec<f64> =
        rotations.iter().map(|rotation| twist(reference, rotation, axis)).collect();
    twists.sort_by(f64::total_cmp);
    twists
}

/// The widest gap between consecutive twists around the circle (a full turn when there are none).
pub(crate) fn widest_gap(
    rotations: &[UnitQuaternion<f64>],
    reference: &UnitQuaternion<f64>,
    axis: usize,
) -> f64 {
    widest_gap_of(&twists(rotations, reference, axis))
}

/// [`widest_gap`] of twists already sorted.
fn widest_gap_of(twists: &[f64]) -> f64 {
    let (Some(first), Some(last)) = (twists.first(), twists.last()) else { return TAU };
    let around = first + TAU - last;
    twists.windows(2).map(|pair| pair[1] - pair[0]).fold(around, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    fn yaw(angle: f64) -> UnitQuaternion<f64> {
        UnitQuaternion::from_euler_angles(0.0, 0.0, angle)
    }

    /// A magnet pointing down grasps a can at every yaw: the can in the gripper's frame is flipped (a half turn
    /// about x) and turned about its own axis.
    fn magnet_grasp(angle: f64) -> UnitQuaternion<f64> {
        UnitQuaternion::from_euler_angles(PI, 0.0, 0.0) * yaw(angle)
    }

    /// A group of rotations, each from its own demonstration.
    fn group(rotations: Vec<UnitQuaternion<f64>>) -> GroupRotations {
        GroupRotations { draws: rotations.len(), rotations }
    }

    #[test]
    fn a_can_at_every_yaw_turns_freely_about_its_own_axis() {
        let angles: Vec<f64> = (0..40).map(|i| -PI + (i as f64 + 0.37) * TAU / 40.0).collect();
        let grasps: Vec<_> = angles.iter().map(|a| magnet_grasp(*a)).collect();
        let set_down: Vec<_> = angles.iter().rev().map(|a| yaw(*a)).collect();
        let turn = free_turn(&[group(grasps.clone())]).expect("free");
        assert_eq!(turn.axis, 2);
        assert_eq!(turn.reference, grasps[0]);
        // Every grasp is a turn about the can's z from the first one.
        for (grasp, angle) in grasps.iter().zip(&angles) {
            let found = twist(&turn.reference, grasp, 2);
            let difference = (found - (angle - angles[0]) + PI).rem_euclid(TAU) - PI;
            assert!(difference.abs() < 1e-9, "{found} for {angle}");
        }
        assert_eq!(free_turn(&[group(set_down)]).map(|turn| turn.axis), Some(2));
    }

    #[test]
    fn four_grasp_sides_a_narrow_yaw_or_one_group_not_turning_stay_cells() {
        let sides: Vec<_> =
            (0..40).map(|i| yaw((i % 4) as f64 * FRAC_PI_2 + 0.001 * i as f64)).collect();
        assert_eq!(free_turn(&[group(sides)]), None);
        let narrow: Vec<_> = (0..40).map(|i| yaw(0.02 * (i as f64 / 40.0 - 0.5))).collect();
        assert_eq!(free_turn(&[group(narrow.clone())]), None);
        let every: Vec<_> = (0..40).map(|i| yaw(-PI + i as f64 * TAU / 40.0)).collect();
        assert_eq!(free_turn(&[group(every.clone()), group(narrow)]), None);
        assert!(free_turn(&[group(every.clone()), group(every)]).is_some());
        assert_eq!(free_turn(&[]), None);
    }

    /// Twists of a fixed pseudo-random stream (a linear congruential generator), in [−π, π).
    fn random_twists(count: usize, seed: u64) -> Vec<f64> {
        let mut state = seed;
        (0..count)
            .map(|_| {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                -PI + TAU * ((state >> 11) as f64 / (1u64 << 53) as f64)
            })
            .collect()
    }

    #[test]
    fn few_grasps_at_random_yaws_turn_freely_and_part_of_the_circle_does_not() {
        // Fifteen grasps at random yaws, as twenty demonstrations give, in 200 draws: most leave a gap wider than
        // a sixth of a turn, and nearly all turn freely.
        let (mut wide, mut free) = (0, 0);
        for seed in 0..200 {
            let grasps: Vec<_> = random_twists(15, seed).iter().map(|a| magnet_grasp(*a)).collect();
            wide += usize::from(widest_gap(&grasps, &grasps[0], 2) >= FREE_GAP);
            free += usize::from(free_turn(&[group(grasps.clone())]).is_some());
        }
        assert!(wide > 100, "most leave a wide gap: {wide}");
        assert!(free >= 190, "nearly all turn freely: {free} of 200");
        // Fifteen yaws over 0.6 of a turn, or over four or five sides, are no free turn.
        let part: Vec<_> = (0..15).map(|i| yaw(-0.6 * PI + 1.2 * PI * i as f64 / 14.0)).collect();
        assert_eq!(free_turn(&[group(part)]), None);
        for sides in [4, 5] {
            let at: Vec<_> = (0..15)
                .map(|i| yaw((i % sides) as f64 * TAU / sides as f64 + 0.01 * i as f64))
                .collect();
            assert_eq!(free_turn(&[group(at)]), None, "{sides} sides");
        }
    }

    /// Thirty demonstrations that each show their grasp twice (hovering, then touching) are thirty draws, not
    /// sixty: their gaps are those of thirty.
    #[test]
    fn keyframes_of_one_demonstration_count_once() {
        let mut free = 0;
        for seed in 0..100 {
            let once: Vec<_> = random_twists(30, seed).iter().map(|a| magnet_grasp(*a)).collect();
            let twice: Vec<_> = once.iter().flat_map(|rotation| [*rotation, *rotation]).collect();
            free +=
                usize::from(free_turn(&[GroupRotations { rotations: twice, draws: 30 }]).is_some());
        }
        assert!(free >= 97, "{free} of 100");
    }

    #[test]
    fn the_allowed_gap_shrinks_with_the_twists() {
        assert_eq!(allowed_gap(10), WIDEST_ALLOWED_GAP);
        let gap = allowed_gap(20).to_degrees();
        assert!((gap - 118.7).abs() < 0.1, "{gap}");
        assert!(allowed_gap(40) < allowed_gap(20));
        assert!(allowed_gap(200) < FREE_GAP);
        assert_eq!(allowed_gap(1), 0.0);
    }
}
