//! Relational critical regions: 6-connected components of critical voxels, one held-flag slice at a time.
//!
//! Only position connects voxels (faces, not edges or corners); rotation never splits or joins a region.
//! Regions of a pair are ordered by (g, smallest voxel in (x, y, z) order), which also numbers their relations.

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use crate::discretise::{RotationCell, Voxel};
use crate::occupancy::Cell;

/// The cells of one region.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionCells {
    /// The held flag of the slice it lives in.
    pub g: u8,
    /// Its voxels, each with the rotation cells it keeps.
    pub voxels: BTreeMap<Voxel, BTreeSet<RotationCell>>,
}

impl RegionCells {
    /// The number of (voxel, rotation) cells.
    pub fn cell_count(&self) -> usize {
        self.voxels.values().map(BTreeSet::len).sum()
    }

    /// Whether the region holds a (g, voxel, rotation) cell.
    pub fn contains(&self, g: u8, voxel: Voxel, rotation: RotationCell) -> bool {
        self.g == g
            && self.voxels.get(&voxel).is_some_and(|rotations| rotations.contains(&rotation))
    }
}

/// Splits critical cells into 6-connected components, in (g, smallest voxel) order; two neighbouring cells
/// are connected only where `joined` says so (cells of two different places stay apart).
pub fn components(
    critical: &BTreeMap<Cell, BTreeSet<RotationCell>>,
    joined: impl Fn(&Cell, &Cell) -> bool,
) -> Vec<RegionCells> {
    let mut seen: BTreeSet<Cell> = BTreeSet::new();
    let mut regions = Vec::new();
    for &start in critical.keys() {
        if seen.contains(&start) {
            continue;
        }
        let (g, _) = start;
        let mut voxels = BTreeMap::new();
        let mut queue = VecDeque::from([start]);
        seen.insert(start);
        while let Some(cell) = queue.pop_front() {
            voxels.insert(cell.1, critical[&cell].clone());
            for neighbour in face_neighbours(cell.1) {
                let next = (g, neighbour);
                if critical.contains_key(&next) && joined(&cell, &next) && seen.insert(next) {
                    queue.push_back(next);
                }
            }
        }
        regions.push(RegionCells { g, voxels });
    }
    // Keys iterate by (g, voxel), so each region's first-seen voxel is its smallest, and regions come out sorted.
    regions
}

/// The up to six voxels sharing a face (indices never go below zero; the upper edge is checked by membership).
fn face_neighbours(voxel: Voxel) -> Vec<Voxel> {
    let mut neighbours = Vec::with_capacity(6);
    for axis in 0..3 {
        if voxel[axis] > 0 {
            let mut below = voxel;
            below[axis] -= 1;
            neighbours.push(below);
        }
        let mut above = voxel;
        above[axis] += 1;
        neighbours.push(above);
    }
    neighbours
}

#[cfg(test)]
mod tests {
    use super::*;

    fn critical(cells: &[(u8, Voxel)]) -> BTreeMap<Cell, BTreeSet<RotationCell>> {
        cells.iter().map(|cell| (*cell, BTreeSet::from([[0, 0, 0]]))).collect()
    }

    #[test]
    fn neighbouring_cells_of_two_places_stay_two_regions() {
        let cells = critical(&[(0, [1, 1, 1]), (0, [1, 1, 2]), (0, [1, 1, 3])]);
        // The lowest cell is one place, the two above it another.
        let place = |cell: &Cell| cell.1[2] > 1;
        let regions = components(&cells, |a, b| place(a) == place(b));
        assert_eq!(regions.len(), 2);
        assert_eq!(
            regions[1].voxels.keys().copied().collect::<Vec<_>>(),
            vec![[1, 1, 2], [1, 1, 3]]
        );
    }

    #[test]
    fn face_neighbours_join_and_diagonals_do_not() {
        let regions = components(
            &critical(&[(0, [1, 1, 1]), (0, [1, 1, 2]), (0, [2, 2, 2]), (0, [3, 3, 3])]),
            |_, _| true,
        );
        assert_eq!(regions.len(), 3);
        assert_eq!(
            regions[0].voxels.keys().copied().collect::<Vec<_>>(),
            vec![[1, 1, 1], [1, 1, 2]]
        );
        // [1,1,2] and [2,2,2] share only an edge, [2,2,2] and [3,3,3] only a corner.
        assert_eq!(regions[1].voxels.len(), 1);
        assert_eq!(regions[2].voxels.len(), 1);
    }

    #[test]
    fn held_slices_never_join_and_order_is_g_then_smallest_voxel() {
        let regions =
            components(&critical(&[(1, [0, 0, 0]), (0, [5, 0, 0]), (0, [0, 0, 0])]), |_, _| true);
        let keys: Vec<(u8, Voxel)> =
            regions.iter().map(|r| (r.g, *r.voxels.keys().next().expect("non-empty"))).collect();
        assert_eq!(keys, vec![(0, [0, 0, 0]), (0, [5, 0, 0]), (1, [0, 0, 0])]);
    }

    #[test]
    fn a_snake_is_one_region() {
        let snake: Vec<(u8, Voxel)> = vec![
            (0, [0, 0, 0]),
            (0, [0, 1, 0]),
            (0, [1, 1, 0]),
            (0, [2, 1, 0]),
            (0, [2, 0, 0]),
            (0, [2, 0, 1]),
        ];
        let regions = components(&critical(&snake), |_, _| true);
        assert_eq!(regions.len(), 1);
        assert_eq!(regions[0].cell_count(), 6);
    }
}
