//! A region's membership test and generator, behind [`RegionClassifier`]: the paper's Gaussian mixture over
//! continuous pose features with a log-density threshold.
//!
//! Fitting draws poses uniformly over the region's cells, maps them to the 9-D feature of
//! [`crate::features`], fits a full-covariance mixture with lamp-gmm (component count by BIC up to the pair's
//! cap) and calibrates the threshold ε so that the pair's cover share of those samples is inside.
//! A pose's margin is its log density minus ε; sampling draws a feature and projects it back to a pose.
//! Everything else in the pipeline only sees [`RegionClassifier`] and [`RegionModel::sample`].

use lamp_gmm::{FitConfig, GaussianMixture, calibrate_threshold};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::abstraction::RegionClassifier;
use crate::demo::Pose;
use crate::discretise::{RotationCell, Voxel};
use crate::features::{FEATURE_DIMENSION, features_pose, pose_features};
use crate::learner::PairRegions;
use crate::regions::RegionCells;

/// Draws of the mixture per sample before one outside the region's extent is returned anyway.
pub const EXTENT_DRAWS: usize = 64;

/// The model of one region: a mixture over pose features, the log-density threshold ε of
/// membership, and the box its cells span in position.
///
/// A pose is in the region iff its position lies in that box and its log density is at least ε.
/// The box matters: a mixture fitted to a region of uniform cells leaks a component's tail past
/// the cells (a Gaussian of a box's spread accepts points well beyond its edges when the other
/// features match closely), and such a pose was never seen in a demonstration — a can beside the
/// box would count as in it.
///
/// Serialised as `{ "g", "mixture", "threshold", "extent" }`, the mixture in lamp-gmm's parameter
/// layout; deserialising the mixture validates it, and [`RegionModel::validate`] checks the rest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RegionModel {
    g: u8,
    mixture: GaussianMixture,
    /// ε: a pose is inside iff its log density is at least this.
    threshold: f64,
    /// Per axis, the lowest and highest position coordinate of the region's cells.
    extent: [[f64; 2]; 3],
}

impl RegionModel {
    /// The model of region `index` of a pair, fitted to `samples` poses drawn uniformly over its cells with `rng`.
    pub fn fit(
        pair: &PairRegions,
        index: usize,
        samples: usize,
        rng: &mut ChaCha8Rng,
    ) -> Result<Self, String> {
        let region = pair.regions.get(index).ok_or_else(|| format!("no region {}", index + 1))?;
        let cells = cell_list(&region.cells);
        if cells.is_empty() {
            return Err("the region has no cells".to_string());
        }
        if samples == 0 {
            return Err("no samples to fit the mixture to".to_string());
        }
        let features: Vec<Vec<f64>> = (0..samples)
            .map(|_| {
                let (voxel, rotation) = cells[rng.random_range(0..cells.len())];
                pose_features(&pair.grid.sample_cell(voxel, rotation, rng)).to_vec()
            })
            .collect();
        let config =
            FitConfig { max_components: pair.settings.max_components, ..FitConfig::default() };
        let mixture = lamp_gmm::fit(&features, &config, rng).map_err(|error| error.to_string())?;
        let threshold = calibrate_threshold(&mixture, &features, pair.settings.cover)
            .map_err(|error| error.to_string())?;
        let mut extent = [[f64::INFINITY, f64::NEG_INFINITY]; 3];
        for voxel in region.cells.voxels.keys() {
            for (axis, (low, high)) in pair.grid.voxel_bounds(*voxel).into_iter().enumerate() {
                extent[axis][0] = extent[axis][0].min(low);
                extent[axis][1] = extent[axis][1].max(high);
            }
        }
        let model = RegionModel { g: region.g, mixture, threshold, extent };
        model.validate()?;
        Ok(model)
    }

    /// Draws a relative pose: a feature from the mixture, its rotation columns projected to a
    /// rotation, redrawn (up to [`EXTENT_DRAWS`] times) while its position is outside the
    /// region's extent.
    pub fn sample(&self, rng: &mut ChaCha8Rng) -> Pose {
        let mut pose = features_pose(&self.mixture.sample(rng));
        for _ in 1..EXTENT_DRAWS {
            if self.outside(&pose) == 0.0 {
                break;
            }
            pose = features_pose(&self.mixture.sample(rng));
        }
        pose
    }

    /// Whether a pose's position lies within the region's cells' bounding box (a coarser test
    /// than membership, which also weighs the rotation and the mixture's shape).
    pub fn spans(&self, relative: &Pose) -> bool {
        self.outside(relative) == 0.0
    }

    /// How far (summed over axes, metres) a pose's position is outside the region's extent.
    fn outside(&self, relative: &Pose) -> f64 {
        let position = relative.translation.vector;
        (0..3)
            .map(|axis| {
                let [low, high] = self.extent[axis];
                (low - position[axis]).max(position[axis] - high).max(0.0)
            })
            .sum()
    }

    /// The number of mixture components BIC chose.
    pub fn component_count(&self) -> usize {
        self.mixture.component_count()
    }

    /// The mixture over pose features.
    pub fn mixture(&self) -> &GaussianMixture {
        &self.mixture
    }

    /// The log-density threshold ε of membership.
    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    /// The held flag of the region.
    pub fn held_flag(&self) -> u8 {
        self.g
    }

    /// Checks a deserialised model (the mixture itself was validated when it was built).
    pub fn validate(&self) -> Result<(), String> {
        if self.mixture.dimension() != FEATURE_DIMENSION {
            return Err(format!(
                "the mixture is over {} features, not {FEATURE_DIMENSION}",
                self.mixture.dimension()
            ));
        }
        if !self.threshold.is_finite() {
            return Err("the likelihood threshold is not finite".to_string());
        }
        if self.g > 1 {
            return Err(format!("the held flag is {}, not 0 or 1", self.g));
        }
        if self
            .extent
            .iter()
            .any(|[low, high]| !(low.is_finite() && high.is_finite() && low <= high))
        {
            return Err("the region's extent is not a box".to_string());
        }
        Ok(())
    }
}

fn cell_list(cells: &RegionCells) -> Vec<(Voxel, RotationCell)> {
    // BTreeMap and BTreeSet iterate in order, so the list (and so the draws) is deterministic.
    cells
        .voxels
        .iter()
        .flat_map(|(voxel, rotations)| rotations.iter().map(move |rotation| (*voxel, *rotation)))
        .collect()
}

impl RegionClassifier for RegionModel {
    fn margin(&self, relative: &Pose) -> f64 {
        let outside = self.outside(relative);
        if outside > 0.0 {
            // Below zero, and lower the further out.
            return -1.0 - outside;
        }
        self.mixture.log_density(&pose_features(relative)) - self.threshold
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{PairSettings, TypePair};
    use crate::discretise::Grid;
    use crate::learner::RegionSummary;
    use rand::SeedableRng;
    use std::collections::{BTreeMap, BTreeSet};
    use std::f64::consts::PI;

    const SAMPLES: usize = 400;

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
            sides: crate::capacity::RegionSides::default(),
        };
        PairRegions {
            pair: TypePair::new("surface", "can"),
            grid: Grid::new(&settings),
            settings,
            demonstrations: 1,
            regions: vec![summary],
        }
    }

    /// One voxel just off the origin, with a yaw cell either side of the half turn.
    fn half_turn_pair() -> PairRegions {
        pair_with(RegionCells {
            g: 0,
            voxels: BTreeMap::from([([8, 8, 8], BTreeSet::from([[12, 12, 0], [12, 12, 23]]))]),
        })
    }

    fn share(count: usize, total: usize) -> f64 {
        count as f64 / total as f64
    }

    #[test]
    fn samples_are_members_and_straddle_the_half_turn() {
        let pair = half_turn_pair();
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let model = RegionModel::fit(&pair, 0, SAMPLES, &mut rng).expect("fits");
        assert!((1..=4).contains(&model.component_count()));
        let poses: Vec<Pose> = (0..200).map(|_| model.sample(&mut rng)).collect();
        let members = poses.iter().filter(|pose| model.margin(pose) >= 0.0).count();
        // The threshold accepts 99 % of the fitting draws; the mixture's own draws are more
        // spread (about 89 % are members, so the refiner rejects by margin).
        assert!(share(members, poses.len()) > 0.85, "{members} of {} are members", poses.len());
        let yaws: Vec<f64> = poses.iter().map(|pose| pose.rotation.euler_angles().2).collect();
        let near_half_turn = yaws.iter().filter(|yaw| yaw.abs() > PI - 0.4).count();
        assert!(share(near_half_turn, yaws.len()) > 0.95, "{near_half_turn} near the half turn");
        assert!(yaws.iter().any(|yaw| *yaw > 0.0) && yaws.iter().any(|yaw| *yaw < 0.0));
        // Both sides of the wrap are inside, the identity rotation and a far position are not.
        // The cells' rotation vectors have x and y in [0, 15°], so the test poses sit mid-cell in those.
        for z in [PI - 0.05, -PI + 0.05] {
            let pose = Pose::from_parts(
                nalgebra::Translation3::new(0.0125, 0.0125, 0.0125),
                nalgebra::UnitQuaternion::from_scaled_axis(nalgebra::Vector3::new(0.13, 0.13, z)),
            );
            assert!(model.margin(&pose) >= 0.0, "rotation vector z {z}");
        }
        assert!(model.margin(&Pose::translation(0.0125, 0.0125, 0.0125)) < 0.0);
        assert!(model.margin(&Pose::translation(0.1, 0.0, 0.0)) < 0.0);
        assert!(RegionModel::fit(&pair, 1, SAMPLES, &mut rng).is_err());
    }

    #[test]
    fn the_threshold_accepts_the_cover_share_of_uniform_draws() {
        let pair = half_turn_pair();
        let model =
            RegionModel::fit(&pair, 0, SAMPLES, &mut ChaCha8Rng::seed_from_u64(3)).expect("fits");
        // Fresh uniform draws over the cells, from another stream than the fit's.
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        let cells = cell_list(&pair.regions[0].cells);
        let draws = 1000;
        let inside = (0..draws)
            .filter(|_| {
                let (voxel, rotation) = cells[rng.random_range(0..cells.len())];
                model.margin(&pair.grid.sample_cell(voxel, rotation, &mut rng)) >= 0.0
            })
            .count();
        let accepted = share(inside, draws);
        assert!(accepted > 0.95 && accepted <= 1.0, "accepted {accepted}, cover 0.99");
        // The margin is the log density above ε.
        let pose = model.sample(&mut rng);
        let expected = model.mixture().log_density(&pose_features(&pose)) - model.threshold();
        assert_eq!(model.margin(&pose), expected);
    }

    #[test]
    fn fitting_is_deterministic_in_the_seed() {
        let pair = half_turn_pair();
        let fit = |seed| {
            RegionModel::fit(&pair, 0, SAMPLES, &mut ChaCha8Rng::seed_from_u64(seed)).expect("fits")
        };
        assert_eq!(fit(9), fit(9));
        assert_ne!(fit(9), fit(10));
    }

    #[test]
    fn a_model_survives_serialisation() {
        let cells = RegionCells {
            g: 1,
            voxels: BTreeMap::from([([1, 2, 3], BTreeSet::from([[4, 5, 6]]))]),
        };
        let pair = pair_with(cells);
        let model =
            RegionModel::fit(&pair, 0, SAMPLES, &mut ChaCha8Rng::seed_from_u64(1)).expect("fits");
        assert_eq!(model.held_flag(), 1);
        let text = serde_json::to_string(&model).expect("serialises");
        let back: RegionModel = serde_json::from_str(&text).expect("deserialises");
        assert_eq!(back, model);
        assert_eq!(back.validate(), Ok(()));
        let mut value: serde_json::Value = serde_json::from_str(&text).expect("parses");
        assert!(value["mixture"]["weights"].is_array() && value["threshold"].is_number());
        value["g"] = serde_json::json!(2);
        let bad: RegionModel = serde_json::from_value(value.clone()).expect("deserialises");
        assert!(bad.validate().is_err());
        value["mixture"]["weights"] = serde_json::json!([2.0]);
        assert!(serde_json::from_value::<RegionModel>(value).is_err(), "invalid mixtures fail");
    }
}
