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
//! stay separate cells.

use std::f64::consts::{PI, TAU};

use nalgebra::UnitQuaternion;

use crate::discretise::FreeTurn;
use lamp_abstraction::free_turn::twist;

/// The widest gap between the twists of a group's keyframes, around the circle, for the turn to count as free: a
/// sixth of a turn. Four grasp sides leave gaps of a quarter turn; 40 twists drawn at random leave about 35°.
pub const FREE_GAP: f64 = PI / 3.0;

/// The free turn of groups of keyframe rotations (the best-supported group first), if there is one: the axis whose
/// widest gap, over the groups, is least.
pub fn free_turn(groups: &[Vec<UnitQuaternion<f64>>]) -> Option<FreeTurn> {
    let reference = *groups.first()?.first()?;
    let gaps = [0, 1, 2].map(|axis| {
        groups.iter().map(|rotations| widest_gap(rotations, &reference, axis)).fold(0.0, f64::max)
    });
    let (axis, gap) =
        gaps.iter().copied().enumerate().min_by(|a, b| a.1.total_cmp(&b.1)).expect("three axes");
    (gap < FREE_GAP).then_some(FreeTurn { reference, axis })
}

/// The widest gap between consecutive twists around the circle (a full turn when there are none).
pub(crate) fn widest_gap(
    rotations: &[UnitQuaternion<f64>],
    reference: &UnitQuaternion<f64>,
    axis: usize,
) -> f64 {
    let mut twists: Vec<f64> =
        rotations.iter().map(|rotation| twist(reference, rotation, axis)).collect();
    twists.sort_by(f64::total_cmp);
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

    #[test]
    fn a_can_at_every_yaw_turns_freely_about_its_own_axis() {
        let angles: Vec<f64> = (0..40).map(|i| -PI + (i as f64 + 0.37) * TAU / 40.0).collect();
        let grasps: Vec<_> = angles.iter().map(|a| magnet_grasp(*a)).collect();
        let set_down: Vec<_> = angles.iter().rev().map(|a| yaw(*a)).collect();
        let turn = free_turn(std::slice::from_ref(&grasps)).expect("free");
        assert_eq!(turn.axis, 2);
        assert_eq!(turn.reference, grasps[0]);
        // Every grasp is a turn about the can's z from the first one.
        for (grasp, angle) in grasps.iter().zip(&angles) {
            let found = twist(&turn.reference, grasp, 2);
            let difference = (found - (angle - angles[0]) + PI).rem_euclid(TAU) - PI;
            assert!(difference.abs() < 1e-9, "{found} for {angle}");
        }
        assert_eq!(free_turn(&[set_down]).map(|turn| turn.axis), Some(2));
    }

    #[test]
    fn four_grasp_sides_a_narrow_yaw_or_one_group_not_turning_stay_cells() {
        let sides: Vec<_> =
            (0..40).map(|i| yaw((i % 4) as f64 * FRAC_PI_2 + 0.001 * i as f64)).collect();
        assert_eq!(free_turn(&[sides]), None);
        let narrow: Vec<_> = (0..40).map(|i| yaw(0.02 * (i as f64 / 40.0 - 0.5))).collect();
        assert_eq!(free_turn(std::slice::from_ref(&narrow)), None);
        let every: Vec<_> = (0..40).map(|i| yaw(-PI + i as f64 * TAU / 40.0)).collect();
        assert_eq!(free_turn(&[every.clone(), narrow]), None);
        assert!(free_turn(&[every.clone(), every]).is_some());
        assert_eq!(free_turn(&[]), None);
    }
}
