//! A grid, rotation bins and a threshold that keep each selected cluster whole.
//!
//! Per position axis: the finest grid over a symmetric range in which every cluster, padded, lies inside one
//! cell, at least [`MIN_MARGIN`] of a cell (or the placement tolerance, if that is less) from its edges, so
//! that a pose a little off the demonstrated ones still falls in the same cell. The range is the clusters' extent, widened by up to [`RANGE_SLACK`] where
//! that lets the edges fall between clusters or away from them.
//!
//! Rotation: the largest odd bin count (an odd count puts "not turned" mid-cell) at which the rotation cells
//! that learning keeps in a voxel, those holding at least the rotation share of its demonstrations, still hold
//! every keyframe of every cluster. A keyframe left outside would be a demonstration whose state lacks the
//! region's relation, and an action's preconditions, the intersection of its demonstrated states, would lose it.

use std::collections::{BTreeMap, BTreeSet};

use crate::config::PairSettings;
use crate::demo::Pose;
use crate::discretise::{FreeTurn, Grid};

/// The least distance of a cluster from its cell's edges, as a share of the cell's width.
pub const MIN_MARGIN: f64 = 0.1;
/// How much wider than the clusters' extent the range may be made: a quarter, what a single cell needs to keep
/// its cluster [`MIN_MARGIN`] from both edges.
pub const RANGE_SLACK: f64 = 0.25;
/// Widths tried between the extent and the slack.
const RANGE_STEPS: u32 = 50;
/// The most bins per axis.
pub const MAX_BINS: usize = 400;
/// The narrowest cell (m).
pub const MIN_CELL: f64 = 1e-4;

/// One axis of the chosen grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisChoice {
    /// Half-range (m).
    pub half_range: f64,
    /// Bins.
    pub bins: usize,
    /// The least margin of a cluster from its cell's edges, as a share of the cell.
    pub margin: f64,
}

/// The grid of one axis for the padded cluster intervals `(low, high)`, keeping what the user pinned; a margin of
/// `tolerance` (m) from the cells' edges is always enough.
pub fn choose_axis(
    intervals: &[(f64, f64)],
    pinned_range: Option<f64>,
    pinned_bins: Option<usize>,
    tolerance: f64,
) -> AxisChoice {
    let extent = intervals.iter().map(|(low, high)| low.abs().max(high.abs())).fold(0.0, f64::max);
    let ranges: Vec<f64> = match pinned_range {
        Some(range) => vec![range],
        None => (0..=RANGE_STEPS)
            .map(|step| extent * (1.0 + RANGE_SLACK * f64::from(step) / f64::from(RANGE_STEPS)))
            .collect(),
    };
    let mut best: Option<((bool, usize, f64), AxisChoice)> = None;
    for &half_range in &ranges {
        let counts: Vec<usize> = match pinned_bins {
            Some(bins) => vec![bins],
            None => (1..=MAX_BINS)
                .take_while(|&bins| bins == 1 || 2.0 * half_range / bins as f64 >= MIN_CELL)
                .collect(),
        };
        for bins in counts {
            let Some(margin) = margin(intervals, half_range, bins) else { continue };
            let width = 2.0 * half_range / bins as f64;
            let enough = margin >= MIN_MARGIN || margin * width >= tolerance;
            // Enough margin first, then the finest grid, then the tightest range (else the widest margin).
            let key =
                (enough, if enough { bins } else { 0 }, if enough { -half_range } else { margin });
            if best.as_ref().is_none_or(|(kept, _)| key > *kept) {
                best = Some((key, AxisChoice { half_range, bins, margin }));
            }
        }
    }
    best.map(|(_, choice)| choice).unwrap_or(AxisChoice {
        half_range: pinned_range.unwrap_or(extent),
        bins: pinned_bins.unwrap_or(1),
        margin: 0.0,
    })
}

/// The least margin of the intervals from their cells' edges, or `None` if one spans two cells or leaves the range.
fn margin(intervals: &[(f64, f64)], half_range: f64, bins: usize) -> Option<f64> {
    let width = 2.0 * half_range / bins as f64;
    let mut least = f64::INFINITY;
    for &(low, high) in intervals {
        if low < -half_range || high > half_range {
            return None;
        }
        let (from, to) = ((low + half_range) / width, (high + half_range) / width);
        let cell = from.floor();
        let at_the_top = to == bins as f64 && cell + 1.0 == to;
        if to.floor() != cell && !at_the_top {
            return None;
        }
        least = least.min((from - cell).min(cell + 1.0 - to));
    }
    Some(least)
}

/// The rotation bins for the clusters' keyframe rotations, each with its demonstration, at most `most`, with
/// rotation cells taken as `free_turn` says.
///
/// With `round` (the axis of its own frame the secondary's shape is round about, `ShapeOracle::round_axis`), a
/// cluster whose keyframes show the object turned about that axis more than half the way round must keep every
/// angle of the turn in a cell its demonstrations visit enough: the angle of a round can means nothing, and cells
/// that hold only the angles a few demonstrations happened to show leave out a can upright at any other (the
/// `in_box` example of Packing from 20 demonstrations). Clusters that hold the object at one angle are not touched.
pub fn choose_rotation_bins(
    clusters: &[Vec<(usize, Pose)>],
    rotation_share: f64,
    most: usize,
    free_turn: Option<FreeTurn>,
    round: Option<usize>,
) -> usize {
    let fits = |bins: usize| {
        let grid =
            Grid::new(&PairSettings { rotation_bins: bins, free_turn, ..PairSettings::DEFAULT });
        clusters.iter().all(|keyframes| {
            let demonstrations: BTreeSet<usize> = keyframes.iter().map(|(d, _)| *d).collect();
            let mut cells: BTreeMap<[usize; 3], BTreeSet<usize>> = BTreeMap::new();
            for (demonstration, pose) in keyframes {
                cells.entry(grid.rotation_cell(pose)).or_default().insert(*demonstration);
            }
            let needed = rotation_share * demonstrations.len() as f64;
            let kept = |pose: &Pose| {
                cells.get(&grid.rotation_cell(pose)).is_some_and(|d| d.len() as f64 >= needed)
            };
            let covered = keyframes.iter().filter(|(_, pose)| kept(pose)).count();
            covered == keyframes.len()
                && round.is_none_or(|axis| whole_turn_kept(keyframes, axis, &kept))
        })
    };
    let largest_odd = if most % 2 == 1 { most } else { most.saturating_sub(1).max(1) };
    (1..=largest_odd).rev().step_by(2).find(|&bins| fits(bins)).unwrap_or(1)
}

/// Angles of a round object's turn tried for [`choose_rotation_bins`]: every 5°.
const TURN_STEPS: usize = 72;

/// Whether every angle of the turn about `axis` from the first keyframe's rotation is `kept`, or the keyframes
/// show the object turned less than half the way round (then its angle is what was demonstrated, not free).
fn whole_turn_kept(keyframes: &[(usize, Pose)], axis: usize, kept: &dyn Fn(&Pose) -> bool) -> bool {
    let Some((_, reference)) = keyframes.first() else { return true };
    let rotations: Vec<_> = keyframes.iter().map(|(_, pose)| pose.rotation).collect();
    if super::free_turn::widest_gap(&rotations, &reference.rotation, axis) >= std::f64::consts::PI {
        return true;
    }
    let turn = FreeTurn { reference: reference.rotation, axis };
    (0..TURN_STEPS).all(|step| {
        let angle = std::f64::consts::TAU * step as f64 / TURN_STEPS as f64;
        kept(&Pose::from_parts(reference.translation, turn.turned(&reference.rotation, angle)))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn the_finest_grid_keeps_each_cluster_in_one_cell_away_from_its_edges() {
        // Two clusters 4 cm wide, at −0.1 and +0.1 m.
        let intervals = [(-0.12, -0.08), (0.08, 0.12)];
        let choice = choose_axis(&intervals, None, None, 0.002);
        let width = 2.0 * choice.half_range / choice.bins as f64;
        assert!(choice.margin >= MIN_MARGIN || choice.margin * width >= 0.002, "{choice:?}");
        assert!(
            choice.half_range >= 0.12 && choice.half_range <= 0.12 * (1.0 + RANGE_SLACK) + 1e-12
        );
        // No finer grid would do: one more bin breaks a cluster or the margin.
        for range_step in 0..=RANGE_STEPS {
            let range = 0.12 * (1.0 + RANGE_SLACK * f64::from(range_step) / f64::from(RANGE_STEPS));
            for bins in choice.bins + 1..=MAX_BINS {
                let width = 2.0 * range / bins as f64;
                assert!(
                    margin(&intervals, range, bins)
                        .is_none_or(|m| m < MIN_MARGIN && m * width < 0.002)
                );
            }
        }
        // A wide group needs only the tolerance: its range is not inflated by a tenth of its cell.
        let wide = choose_axis(&[(-0.35, 0.35)], None, None, 0.002);
        assert_eq!(wide.bins, 1);
        assert!(wide.half_range <= 0.36, "{wide:?}");
    }

    #[test]
    fn pinned_values_are_kept() {
        let choice = choose_axis(&[(0.01, 0.02)], Some(0.3), Some(4), 0.002);
        assert_eq!((choice.half_range, choice.bins), (0.3, 4));
        let bins_only = choose_axis(&[(0.01, 0.02)], Some(0.3), None, 0.002);
        assert_eq!(bins_only.half_range, 0.3);
        assert!(bins_only.margin >= MIN_MARGIN);
    }

    #[test]
    fn rotation_bins_shrink_until_a_spread_of_yaws_fills_its_cells() {
        let yaw = |angle: f64| Pose::rotation(nalgebra::Vector3::z() * angle);
        // One yaw within a degree: the finest count is kept.
        let upright: Vec<(usize, Pose)> =
            (0..40).map(|d| (d, yaw((d as f64 - 20.0) * 0.0008))).collect();
        assert_eq!(choose_rotation_bins(&[upright], 0.1, 61, None, None), 61);
        // Yaws spread over the whole turn: each kept cell must hold a tenth of the demonstrations.
        let any: Vec<(usize, Pose)> =
            (0..90).map(|d| (d, yaw(-PI + (d as f64 + 0.5) * 2.0 * PI / 90.0))).collect();
        let bins = choose_rotation_bins(&[any], 0.1, 61, None, None);
        assert_eq!(bins, 9);
    }

    #[test]
    fn a_round_object_seen_at_a_few_yaws_keeps_every_yaw() {
        let yaw = |angle: f64| Pose::rotation(nalgebra::Vector3::z() * angle);
        // Ten cans set down at yaws a few demonstrations happened to show (as from 20 Packing
        // demonstrations): alone, each keeps its own fine cell and the yaws between are left out.
        let few: Vec<(usize, Pose)> = [-2.9, -2.2, -1.1, -0.6, 0.4, 0.9, 1.7, 2.1, 2.6, 3.0]
            .iter()
            .copied()
            .map(yaw)
            .enumerate()
            .collect();
        let alone = choose_rotation_bins(std::slice::from_ref(&few), 0.1, 61, None, None);
        assert_eq!(alone, 61);
        // Round about z: cells that hold every yaw, each visited by a tenth of them.
        let round = choose_rotation_bins(std::slice::from_ref(&few), 0.1, 61, None, Some(2));
        assert!(round < alone, "{round}");
        let grid = Grid::new(&PairSettings { rotation_bins: round, ..PairSettings::DEFAULT });
        let visited: BTreeSet<[usize; 3]> =
            few.iter().map(|(_, pose)| grid.rotation_cell(pose)).collect();
        for step in 0..360 {
            let cell = grid.rotation_cell(&yaw(-PI + step as f64 * PI / 180.0));
            assert!(visited.contains(&cell), "{round} bins leave out yaw {step}°");
        }
        // Held at one yaw (a bowl set on its place as its marker turns), a round object's
        // angle is what was demonstrated: its cells stay as fine.
        let upright: Vec<(usize, Pose)> =
            (0..40).map(|d| (d, yaw((d as f64 - 20.0) * 0.0008))).collect();
        assert_eq!(choose_rotation_bins(&[upright], 0.1, 61, None, Some(2)), 61);
    }
}
