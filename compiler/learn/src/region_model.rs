//! A region's membership test and generator, behind [`RegionClassifier`].
//!
//! The paper models each region with a Gaussian mixture over continuous pose features and tests membership by a
//! likelihood threshold; that model needs lamp-gmm, which this build does not have yet.
//! Until it is wired in, a region model is the region's exact cells (the reference code's discrete test):
//! a pose is inside iff its (g, voxel, rotation cell) is one of the region's cells, and sampling draws a cell
//! uniformly and a pose uniformly inside it.
//! Everything else in the pipeline only sees [`RegionClassifier`] and [`RegionModel::sample`], so the swap is local.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::abstraction::RegionClassifier;
use crate::demo::Pose;
use crate::discretise::{Grid, RotationCell, Voxel};
use crate::learner::PairRegions;
use crate::regions::RegionCells;

/// The model of one region.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RegionModel {
    grid: Grid,
    g: u8,
    /// The region's cells, sorted (searched by bisection).
    cells: Vec<(Voxel, RotationCell)>,
}

/// The margin of a pose inside the region (exact cells have no depth).
const INSIDE: f64 = 0.0;
/// The margin of a pose outside the region.
const OUTSIDE: f64 = -1.0;

impl RegionModel {
    /// The model of region `index` of a pair; `samples` and `rng` are for fitted models and unused by exact cells.
    pub fn fit(
        pair: &PairRegions,
        index: usize,
        _samples: usize,
        _rng: &mut ChaCha8Rng,
    ) -> Result<Self, String> {
        let region = pair.regions.get(index).ok_or_else(|| format!("no region {}", index + 1))?;
        if region.cells.cell_count() == 0 {
            return Err("the region has no cells".to_string());
        }
        Ok(RegionModel { grid: pair.grid.clone(), g: region.g, cells: cell_list(&region.cells) })
    }

    /// Draws a relative pose: a cell uniformly, then a pose uniformly inside it.
    pub fn sample(&self, rng: &mut ChaCha8Rng) -> Pose {
        let (voxel, rotation) = self.cells[rng.random_range(0..self.cells.len())];
        self.grid.sample_cell(voxel, rotation, rng)
    }

    /// The number of (voxel, rotation) cells.
    pub fn cell_count(&self) -> usize {
        self.cells.len()
    }

    /// The held flag of the region.
    pub fn held_flag(&self) -> u8 {
        self.g
    }

    /// Checks a deserialised model.
    pub fn validate(&self) -> Result<(), String> {
        if self.cells.is_empty() {
            return Err("the region has no cells".to_string());
        }
        if !self.cells.is_sorted() {
            return Err("the region's cells are not sorted".to_string());
        }
        let bins = self.grid.bins();
        let rotation_bins = self.grid.rotation_bins();
        let outside = |(voxel, rotation): &(Voxel, RotationCell)| {
            voxel.iter().zip(bins).any(|(index, count)| *index >= count)
                || rotation.iter().any(|i| *i >= rotation_bins)
        };
        if self.cells.iter().any(outside) {
            return Err("a cell lies outside the grid".to_string());
        }
        Ok(())
    }
}

fn cell_list(cells: &RegionCells) -> Vec<(Voxel, RotationCell)> {
    // BTreeMap and BTreeSet iterate in order, so the list comes out sorted.
    cells
        .voxels
        .iter()
        .flat_map(|(voxel, rotations)| rotations.iter().map(move |rotation| (*voxel, *rotation)))
        .collect()
}

impl RegionClassifier for RegionModel {
    fn margin(&self, relative: &Pose) -> f64 {
        let inside = self.grid.voxel(relative).is_some_and(|voxel| {
            self.cells.binary_search(&(voxel, self.grid.rotation_cell(relative))).is_ok()
        });
        if inside { INSIDE } else { OUTSIDE }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{PairSettings, TypePair};
    use crate::learner::RegionSummary;
    use rand::SeedableRng;
    use std::collections::{BTreeMap, BTreeSet};

    fn pair_with(cells: RegionCells) -> PairRegions {
        let settings = PairSettings::default();
        let summary = RegionSummary {
            g: cells.g,
            cells,
            demonstrations: 1,
            time_steps: 1,
            representative: Pose::identity(),
            centre: [0.0; 3],
            spread: [0.0; 3],
            bounds: [(0.0, 0.0); 3],
        };
        PairRegions {
            pair: TypePair::new("surface", "can"),
            grid: Grid::new(&settings),
            settings,
            demonstrations: 1,
            regions: vec![summary],
        }
    }

    #[test]
    fn samples_are_members_and_straddle_the_half_turn() {
        let cells = RegionCells {
            g: 0,
            voxels: BTreeMap::from([([8, 8, 8], BTreeSet::from([[12, 12, 0], [12, 12, 23]]))]),
        };
        let pair = pair_with(cells);
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let model = RegionModel::fit(&pair, 0, 100, &mut rng).expect("fits");
        let mut signs = BTreeSet::new();
        for _ in 0..100 {
            let pose = model.sample(&mut rng);
            assert!(model.margin(&pose) >= 0.0);
            let yaw = pose.rotation.euler_angles().2;
            assert!(yaw.abs() > std::f64::consts::PI - 0.3, "yaw {yaw}");
            signs.insert(yaw > 0.0);
        }
        assert_eq!(signs.len(), 2);
        assert!(model.margin(&Pose::translation(0.1, 0.0, 0.0)) < 0.0);
        assert!(RegionModel::fit(&pair, 1, 100, &mut rng).is_err());
    }

    #[test]
    fn a_model_survives_serialisation() {
        let cells = RegionCells {
            g: 1,
            voxels: BTreeMap::from([([1, 2, 3], BTreeSet::from([[4, 5, 6]]))]),
        };
        let pair = pair_with(cells);
        let model =
            RegionModel::fit(&pair, 0, 100, &mut ChaCha8Rng::seed_from_u64(1)).expect("fits");
        let text = serde_json::to_string(&model).expect("serialises");
        let back: RegionModel = serde_json::from_str(&text).expect("deserialises");
        assert_eq!(back, model);
        assert_eq!(back.validate(), Ok(()));
    }
}
