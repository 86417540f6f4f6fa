//! Fitting a region's membership test and generator (lamp-abstraction's [`RegionModel`]): the paper's
//! Gaussian mixture over continuous pose features with a log-density threshold.
//!
//! Fitting draws poses uniformly over the region's cells, maps them to the 9-D feature of
//! [`lamp_abstraction::features`], fits a full-covariance mixture with lamp-gmm (component count by BIC up to the pair's
//! cap) and calibrates the threshold ε so that the pair's cover share of those samples is inside.
//! Everything else in the pipeline only sees [`RegionClassifier`](crate::RegionClassifier) and
//! [`RegionModel::sample`].

use lamp_gmm::{FitConfig, calibrate_threshold};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::discretise::{RotationCell, Voxel};
use crate::learner::PairRegions;
use crate::regions::RegionCells;
pub(crate) use lamp_abstraction::region_model::RegionModel;

/// The model of region `index` of a pair, fitted to `samples` poses drawn uniformly over its cells with `rng`.
pub fn fit(
    pair: &PairRegions,
    index: usize,
    samples: usize,
    rng: &mut ChaCha8Rng,
) -> Result<RegionModel, String> {
    let region = pair.regions.get(index).ok_or_else(|| format!("no region {}", index + 1))?;
    let cells = cell_list(&region.cells);
    if cells.is_empty() {
        return Err("the region has no cells".to_string());
    }
    if samples == 0 {
        return Err("no samples to fit the mixture to".to_string());
    }
    let free_turn = pair.grid.free_turn();
    let features: Vec<Vec<f64>> = (0..samples)
        .map(|_| {
            let (voxel, rotation) = cells[rng.random_range(0..cells.len())];
            let pose = pair.grid.sample_cell(voxel, rotation, rng);
            RegionModel::features_with(free_turn.as_ref(), &pose)
        })
        .collect();
    let config = FitConfig { max_components: pair.settings.max_components, ..FitConfig::default() };
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
    Ok(RegionModel::new(region.g, mixture, threshold, extent, free_turn)?
        .with_symmetry(pair.symmetry.clone()))
}

fn cell_list(cells: &RegionCells) -> Vec<(Voxel, RotationCell)> {
    // BTreeMap and BTreeSet iterate in order, so the list (and so the draws) is deterministic.
    cells
        .voxels
        .iter()
        .flat_map(|(voxel, rotations)| rotations.iter().map(move |rotation| (*voxel, *rotation)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abstraction::RegionClassifier;
    use crate::config::{PairSettings, TypePair};
    use crate::demo::Pose;
    use crate::discretise::Grid;
    use crate::learner::RegionSummary;
    use rand::SeedableRng;
    use std::collections::{BTreeMap, BTreeSet};
    use std::f64::consts::PI;

    const SAMPLES: usize = 400;

    fn pair_with(cells: RegionCells) -> PairRegions {
        let settings = PairSettings {
            position_bins: [16; 3],
            half_range: [0.2; 3],
            rotation_bins: 24,
            max_components: 4,
            ..PairSettings::DEFAULT
        };
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
            selection: None,
            demonstrations: 1,
            regions: vec![summary],
            symmetry: None,
            symmetry_choice: None,
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
        let model = fit(&pair, 0, SAMPLES, &mut rng).expect("fits");
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
        assert!(fit(&pair, 1, SAMPLES, &mut rng).is_err());
    }

    #[test]
    fn a_free_turn_is_neither_tested_nor_fitted_and_drawn_at_every_angle() {
        // A can upright on a surface at any yaw: one voxel, the middle rotation cell, the yaw left free.
        let mut pair = pair_with(RegionCells {
            g: 0,
            voxels: BTreeMap::from([([8, 8, 8], BTreeSet::from([[12, 12, 0]]))]),
        });
        let free_turn = Some(crate::discretise::FreeTurn {
            reference: nalgebra::UnitQuaternion::from_euler_angles(0.0, 0.0, 1.0),
            axis: 2,
        });
        pair.settings.free_turn = free_turn;
        pair.grid = Grid::new(&pair.settings);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let model = fit(&pair, 0, SAMPLES, &mut rng).expect("fits");
        assert_eq!(model.free_turn(), free_turn);
        let at = |roll: f64, yaw: f64| {
            Pose::from_parts(
                nalgebra::Translation3::new(0.0125, 0.0125, 0.0125),
                nalgebra::UnitQuaternion::from_euler_angles(roll, 0.0, yaw),
            )
        };
        let upright = model.margin(&at(0.0, 0.0));
        assert!(upright >= 0.0);
        for yaw in [-3.0, -1.2, 0.7, 2.5, PI] {
            assert!((model.margin(&at(0.0, yaw)) - upright).abs() < 1e-6, "yaw {yaw}");
            assert!(model.margin(&at(0.5, yaw)) < 0.0, "tilted at yaw {yaw}");
        }
        let yaws: Vec<f64> =
            (0..400).map(|_| model.sample(&mut rng).rotation.euler_angles().2).collect();
        for quarter in 0..4 {
            let low = -PI + f64::from(quarter) * PI / 2.0;
            let count = yaws.iter().filter(|yaw| (low..low + PI / 2.0).contains(*yaw)).count();
            assert!(count > 60, "{count} of 400 draws in the quarter turn from {low}");
        }
    }

    #[test]
    fn a_region_folded_by_a_half_turn_of_its_primary_is_whole_again() {
        // A can upright anywhere on a square floor, compared up to the floor's half turn: the
        // folded poses cover one half of the floor (x from 0 to 75 mm), up to the fold at x = 0.
        let voxels = (8..11)
            .flat_map(|x| (6..10).map(move |y| ([x, y, 8], BTreeSet::from([[12, 12, 0]]))))
            .collect();
        let mut pair = pair_with(RegionCells { g: 0, voxels });
        pair.settings.free_turn = Some(crate::discretise::FreeTurn {
            reference: nalgebra::UnitQuaternion::identity(),
            axis: 2,
        });
        pair.grid = Grid::new(&pair.settings);
        let folded = fit(&pair, 0, SAMPLES, &mut ChaCha8Rng::seed_from_u64(2)).expect("fits");
        let half_turn = nalgebra::UnitQuaternion::from_euler_angles(0.0, 0.0, PI);
        let quarter_turns = (1..4).map(|k| {
            nalgebra::UnitQuaternion::from_euler_angles(0.0, 0.0, f64::from(k) * PI / 2.0)
        });
        let whole = folded.clone().with_symmetry(lamp_abstraction::PairSymmetry::new(
            vec![half_turn],
            quarter_turns.collect(),
        ));
        let at = |x: f64, y: f64| Pose::translation(x, y, 0.0125);
        // Deep in the folded half nothing changes: the secondary's turns, which a free turn
        // makes idle, are not counted again.
        assert!((whole.margin(&at(0.05, 0.0)) - folded.margin(&at(0.05, 0.0))).abs() < 1e-3);
        // The other half is the same place seen from the turned frame.
        assert!(folded.margin(&at(-0.05, 0.0)) < 0.0);
        assert!(whole.margin(&at(-0.05, 0.0)) >= 0.0);
        assert!((whole.margin(&at(-0.05, 0.01)) - whole.margin(&at(0.05, -0.01))).abs() < 1e-9);
        // At the fold both halves' tails add up: the centre gains what its mirror image holds.
        let centre = whole.margin(&at(0.0, 0.0)) - folded.margin(&at(0.0, 0.0));
        assert!((centre - 2f64.ln()).abs() < 1e-9, "the centre gains {centre}");
        // Draws fill the whole floor, not the folded half.
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let xs: Vec<f64> = (0..400).map(|_| whole.sample(&mut rng).translation.vector.x).collect();
        let negative = xs.iter().filter(|x| **x < 0.0).count();
        assert!((150..250).contains(&negative), "{negative} of 400 draws on the turned side");
    }

    #[test]
    fn the_threshold_accepts_the_cover_share_of_uniform_draws() {
        let pair = half_turn_pair();
        let model = fit(&pair, 0, SAMPLES, &mut ChaCha8Rng::seed_from_u64(3)).expect("fits");
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
        let expected =
            model.mixture().log_density(&crate::features::pose_features(&pose)) - model.threshold();
        assert_eq!(model.margin(&pose), expected);
    }

    #[test]
    fn fitting_is_deterministic_in_the_seed() {
        let pair = half_turn_pair();
        let fit =
            |seed| fit(&pair, 0, SAMPLES, &mut ChaCha8Rng::seed_from_u64(seed)).expect("fits");
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
        let model = fit(&pair, 0, SAMPLES, &mut ChaCha8Rng::seed_from_u64(1)).expect("fits");
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
