//! Occupancy and criticality (paper Def. 1): the share of demonstrations that visit each (voxel, g) cell.
//!
//! Each demonstration counts at most once per cell, however long it stays there.
//! A cell is critical iff its count ÷ the number of demonstrations in which the pair occurs is at least θ.
//! A cell visited by fewer than a minimum number of demonstrations is never critical, so that one or two
//! demonstrations cannot invent regions out of single trajectories.
//! Per critical cell, the rotation cells used by at least a set share of its visiting demonstrations are kept,
//! and always the most used one (ties: the smallest cell index).

use std::collections::{BTreeMap, BTreeSet};

use crate::discretise::{RotationCell, Voxel};

/// Shares are compared with this slack so that θ · N landing a rounding error above an integer still admits it.
pub const SHARE_TOLERANCE: f64 = 1e-9;

/// A position cell in one held-flag slice.
pub type Cell = (u8, Voxel);

/// Visit counts of one type pair.
#[derive(Debug, Clone, Default)]
pub struct Occupancy {
    demonstrations: usize,
    visits: BTreeMap<Cell, CellVisits>,
}

#[derive(Debug, Clone, Default)]
struct CellVisits {
    demonstrations: usize,
    rotations: BTreeMap<RotationCell, usize>,
}

impl Occupancy {
    /// Adds one demonstration's visited cells: each (g, voxel, rotation) it entered, in any order, repeats allowed.
    pub fn add_demonstration(
        &mut self,
        visited: impl IntoIterator<Item = (u8, Voxel, RotationCell)>,
    ) {
        let distinct: BTreeSet<(u8, Voxel, RotationCell)> = visited.into_iter().collect();
        self.demonstrations += 1;
        let cells: BTreeSet<Cell> = distinct.iter().map(|(g, voxel, _)| (*g, *voxel)).collect();
        for cell in cells {
            self.visits.entry(cell).or_default().demonstrations += 1;
        }
        for (g, voxel, rotation) in distinct {
            *self.visits.entry((g, voxel)).or_default().rotations.entry(rotation).or_default() += 1;
        }
    }

    /// The number of demonstrations added.
    pub fn demonstrations(&self) -> usize {
        self.demonstrations
    }

    /// How many demonstrations visited a cell.
    pub fn count(&self, cell: Cell) -> usize {
        self.visits.get(&cell).map_or(0, |visits| visits.demonstrations)
    }

    /// The critical cells under threshold θ and a minimum number of visiting demonstrations, each with its kept
    /// rotation cells.
    pub fn critical(
        &self,
        threshold: f64,
        min_support: usize,
        rotation_share: f64,
    ) -> BTreeMap<Cell, BTreeSet<RotationCell>> {
        let needed =
            (threshold * self.demonstrations as f64 - SHARE_TOLERANCE).max(min_support as f64);
        let mut critical = BTreeMap::new();
        for (cell, visits) in &self.visits {
            if (visits.demonstrations as f64) < needed {
                continue;
            }
            let needed_rotation = rotation_share * visits.demonstrations as f64 - SHARE_TOLERANCE;
            let mut kept: BTreeSet<RotationCell> = visits
                .rotations
                .iter()
                .filter(|(_, count)| **count as f64 >= needed_rotation)
                .map(|(rotation, _)| *rotation)
                .collect();
            // max_by_key keeps the last maximum, so iterate in reverse to prefer the smallest cell on ties.
            if let Some((most_used, _)) =
                visits.rotations.iter().rev().max_by_key(|(_, count)| **count)
            {
                kept.insert(*most_used);
            }
            critical.insert(*cell, kept);
        }
        critical
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const R0: RotationCell = [0, 0, 0];
    const R1: RotationCell = [0, 0, 1];

    #[test]
    fn a_demonstration_counts_once_per_cell() {
        let mut occupancy = Occupancy::default();
        occupancy.add_demonstration([(0, [1, 1, 1], R0), (0, [1, 1, 1], R0), (0, [1, 1, 1], R1)]);
        occupancy.add_demonstration([(0, [1, 1, 1], R0)]);
        assert_eq!(occupancy.count((0, [1, 1, 1])), 2);
        assert_eq!(occupancy.count((1, [1, 1, 1])), 0);
    }

    #[test]
    fn threshold_is_inclusive_and_exact_at_the_edges() {
        let mut occupancy = Occupancy::default();
        for demo in 0..10 {
            let mut visited = vec![(0, [0, 0, 0], R0)];
            if demo < 3 {
                visited.push((0, [5, 5, 5], R0));
            }
            occupancy.add_demonstration(visited);
        }
        // 3 of 10 is exactly θ = 0.3 (0.3 · 10 is slightly above 3 in floating point).
        assert!(occupancy.critical(0.3, 1, 0.1).contains_key(&(0, [5, 5, 5])));
        assert!(!occupancy.critical(0.31, 1, 0.1).contains_key(&(0, [5, 5, 5])));
        // θ = 1 needs every demonstration.
        let all = occupancy.critical(1.0, 1, 0.1);
        assert_eq!(all.keys().copied().collect::<Vec<_>>(), vec![(0, [0, 0, 0])]);
    }

    #[test]
    fn minimum_support_overrides_a_low_threshold() {
        let mut occupancy = Occupancy::default();
        occupancy.add_demonstration([(0, [0, 0, 0], R0)]);
        occupancy.add_demonstration([(0, [0, 0, 0], R0)]);
        assert_eq!(occupancy.critical(0.5, 2, 0.1).len(), 1);
        assert!(occupancy.critical(0.5, 3, 0.1).is_empty());
    }

    #[test]
    fn rare_rotations_are_dropped_but_one_is_always_kept() {
        let mut occupancy = Occupancy::default();
        for demo in 0..10 {
            let rotation = if demo == 0 { R1 } else { R0 };
            occupancy.add_demonstration([(1, [2, 2, 2], rotation)]);
        }
        assert_eq!(occupancy.critical(0.5, 1, 0.2)[&(1, [2, 2, 2])], BTreeSet::from([R0]));
        assert_eq!(occupancy.critical(0.5, 1, 0.1)[&(1, [2, 2, 2])], BTreeSet::from([R0, R1]));
        // A share nobody reaches still keeps the most used rotation; ties go to the smaller cell.
        let mut tie = Occupancy::default();
        tie.add_demonstration([(0, [0, 0, 0], R1)]);
        tie.add_demonstration([(0, [0, 0, 0], R0)]);
        assert_eq!(tie.critical(1.0, 1, 1.0)[&(0, [0, 0, 0])], BTreeSet::from([R0]));
    }
}
