//! The pipeline up to induced actions, generic over how a region becomes a membership test.
//!
//! Stages: validate → objects steadied between grasps ([`rigid`]) → type pairs → per pair: occupancy over all demonstrations → critical cells → regions with
//! provenance → one classifier per region (fitted in region order from one seeded generator) → vocabulary →
//! abstraction of every snapshot → demonstrations cut where a release rests undescribed ([`resting`]) → actions.

use std::collections::{BTreeMap, BTreeSet};

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::abstraction::{self, RegionClassifier};
use crate::actions::{self, AbstractDemonstration, Action};
use crate::capacity::{self, RegionSides, ShapeOracle};
use crate::config::{LearnConfig, PairSettings, TypePair};
use crate::demo::{self, Demonstration, Pose, Role};
use crate::discretise::{Bounds, Grid, RotationCell, Voxel};
use crate::error::LearnError;
use crate::features::{FEATURE_DIMENSION, pose_features};
use crate::occupancy::Occupancy;
use crate::pairs;
use crate::regions::{self, RegionCells};
use crate::relations::PairVocabulary;
use crate::resting::{self, UndescribedRest};
use crate::rigid;
use crate::selection::{self, Selection, Track, TrackFrame};
use crate::symmetry_choice::{self, SymmetryChoice};

/// Where a region came from and what it looks like.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionSummary {
    /// The held flag of its slice.
    pub g: u8,
    /// Its cells.
    pub cells: RegionCells,
    /// Demonstrations that visited it.
    pub demonstrations: usize,
    /// Time steps (over all demonstrations and participant pairs) observed in it.
    pub time_steps: usize,
    /// The observed relative pose closest (in feature space) to the mean of the observations in it.
    pub representative: Pose,
    /// Mean observed position in the primary's frame (m).
    pub centre: [f64; 3],
    /// Standard deviation of the observed positions per axis (m).
    pub spread: [f64; 3],
    /// The extent of its voxels per axis, `(low, high)` (m).
    pub bounds: [(f64, f64); 3],
    /// Whether it has a clear and a nowhere relation, and why.
    pub sides: RegionSides,
}

/// A type pair with its regions, in relation order.
#[derive(Debug, Clone, PartialEq)]
pub struct PairRegions {
    /// The ordered type pair.
    pub pair: TypePair,
    /// Its settings.
    pub settings: PairSettings,
    /// How the settings the spec left out were chosen; `None` when every one was pinned.
    pub selection: Option<Selection>,
    /// Its discretisation.
    pub grid: Grid,
    /// The number of demonstrations in which the pair occurs (the denominator of criticality).
    pub demonstrations: usize,
    /// Its regions; region k is at index k − 1.
    pub regions: Vec<RegionSummary>,
    /// The shapes' symmetry its relative poses are compared up to, if any: every pose it was
    /// learned from is its orbit's representative.
    pub symmetry: Option<lamp_abstraction::PairSymmetry>,
    /// With `symmetry auto`, how the places found folded compared with those found as recorded
    /// (whether the symmetry was taken); `None` where it was not in question.
    pub symmetry_choice: Option<SymmetryChoice>,
}

impl PairRegions {
    /// The pair's relations: its regions' held flags and the sides each region has.
    pub fn vocabulary(&self) -> PairVocabulary {
        PairVocabulary {
            pair: self.pair.clone(),
            region_flags: self.regions.iter().map(|region| region.g).collect(),
            clear: self.regions.iter().map(|region| region.sides.clear.on).collect(),
            nowhere: self.regions.iter().map(|region| region.sides.nowhere.on).collect(),
        }
    }
}

/// Everything learned, with classifiers of type `C`.
pub(crate) struct Induced<C> {
    pub roles: BTreeMap<String, Role>,
    /// Pairs with at least one region.
    pub pairs: Vec<PairRegions>,
    /// Pairs that occur in some demonstration but yielded no region.
    pub empty_pairs: Vec<TypePair>,
    pub classifiers: Vec<Vec<C>>,
    pub actions: Vec<Action>,
    /// Demonstrations learned from only up to a grasp ([`resting`]), in demonstration order.
    pub undescribed_rests: Vec<UndescribedRest>,
}

struct Observation {
    demonstration: usize,
    g: u8,
    voxel: Voxel,
    rotation: RotationCell,
    pose: Pose,
}

/// Runs the pipeline; `fit` turns a region into a classifier, drawing randomness only from the generator it gets;
/// `shapes` answers the capacity tests of `auto` sides.
pub(crate) fn induce<C: RegionClassifier>(
    demonstrations: &[Demonstration],
    config: &LearnConfig,
    shapes: &dyn ShapeOracle,
    mut fit: impl FnMut(&PairRegions, usize, &mut ChaCha8Rng) -> Result<C, LearnError>,
) -> Result<Induced<C>, LearnError> {
    config.validate()?;
    let roles = demo::validate(demonstrations)?;
    let steadied: Vec<Demonstration> = demonstrations.iter().map(rigid::steady).collect();
    let demonstrations = steadied.as_slice();
    let pauses: Vec<Vec<bool>> = demonstrations.iter().map(scene_pauses).collect();
    let mut learned = Vec::new();
    let mut empty_pairs = Vec::new();
    for pair in pairs::type_pairs(&roles, config) {
        let primary_moves = roles.get(&pair.primary).is_some_and(|role| role.is_robot_part());
        let movable = |name: &str| matches!(roles.get(name), Some(Role::Object { movable: true }));
        let both_movable = movable(&pair.primary) && movable(&pair.secondary);
        let pair_regions = find_regions(
            demonstrations,
            &pauses,
            config,
            shapes,
            &pair,
            primary_moves,
            both_movable,
        );
        if pair_regions.demonstrations == 0 {
            continue;
        }
        if pair_regions.regions.is_empty() {
            empty_pairs.push(pair);
        } else {
            learned.push(pair_regions);
        }
    }
    if learned.is_empty() {
        return Err(LearnError::NoRegions { demonstrations: demonstrations.len() });
    }
    let mut rng = ChaCha8Rng::seed_from_u64(config.seed);
    let mut classifiers = Vec::with_capacity(learned.len());
    for pair_regions in &learned {
        let mut fitted = Vec::with_capacity(pair_regions.regions.len());
        for index in 0..pair_regions.regions.len() {
            fitted.push(fit(pair_regions, index, &mut rng)?);
        }
        classifiers.push(fitted);
    }
    let vocabulary: Vec<PairVocabulary> = learned.iter().map(PairRegions::vocabulary).collect();
    let related: BTreeSet<TypePair> =
        learned.iter().map(|pair| pair.pair.clone()).chain(empty_pairs.iter().cloned()).collect();
    let mut undescribed_rests = Vec::new();
    let abstracted: Vec<AbstractDemonstration<'_>> = demonstrations
        .iter()
        .map(|demonstration| {
            let mut states: Vec<_> = demonstration
                .steps
                .iter()
                .map(|snapshot| {
                    abstraction::abstract_facts(
                        &vocabulary,
                        &classifiers,
                        &demonstration.participants,
                        snapshot,
                    )
                })
                .collect();
            let rest = resting::first_undescribed_rest(
                demonstration,
                &states,
                &related,
                shapes,
                config.release_tolerance,
            );
            if let Some(rest) = rest {
                states.truncate(rest.kept_steps);
                undescribed_rests.push(rest);
            }
            AbstractDemonstration {
                id: &demonstration.id,
                participants: &demonstration.participants,
                states,
            }
        })
        .collect();
    let actions = actions::induce(&vocabulary, &abstracted);
    Ok(Induced { roles, pairs: learned, empty_pairs, classifiers, actions, undescribed_rests })
}

/// Occupancy, critical cells and regions with provenance of one type pair.
fn find_regions(
    demonstrations: &[Demonstration],
    pauses: &[Vec<bool>],
    config: &LearnConfig,
    shapes: &dyn ShapeOracle,
    pair: &TypePair,
    primary_moves: bool,
    both_movable: bool,
) -> PairRegions {
    let type_pairs = [pair.clone()];
    let pinned = config.pinned(pair);
    // Two movable objects relate only where they touch (`selection::Contact`); that needs both shapes.
    let release_tolerance = config.release_tolerance;
    let touching = |pose: &Pose| {
        shapes.gap(&pair.primary, &pair.secondary, pose).is_none_or(|gap| gap <= release_tolerance)
    };
    let knows_shapes = shapes.gap(&pair.primary, &pair.secondary, &Pose::identity()).is_some();
    let contact: Option<selection::Contact<'_>> =
        (both_movable && knows_shapes).then_some(&touching);
    // A round object's angle at rest means nothing; in a robot's hand its cells stay as the grasps
    // show them (coarser cells there admit tilted grasps: Dinner's `set_table_8_02` took 1386
    // candidates against 184).
    let round = (!primary_moves).then(|| shapes.round_axis(&pair.secondary)).flatten();
    // How one movable object rests against another depends on which faces touch, so their rests are told apart
    // by pose (`selection::pose_distance`).
    let probes = contact.and(shapes.bounding_box(&pair.secondary)).map(|(low, high)| {
        let round = shapes.round_axis(&pair.secondary);
        let turns = config.symmetries.get(&pair.secondary).map_or(&[][..], Vec::as_slice);
        selection::pose_distance::Probes::of_box(low, high, round, turns)
    });
    let select = |tracks: &[Track]| {
        pinned.leaves_a_choice().then(|| {
            let occurring = tracks.iter().map(|track| track.demonstration).collect::<BTreeSet<_>>();
            selection::select(
                &pinned,
                tracks,
                occurring.len(),
                config.min_support,
                config.rotation_share,
                config.release_tolerance,
                selection::ShapeFacts { contact, round, probes: probes.as_ref() },
            )
        })
    };
    // One pass over the recordings per way of comparing poses: the selection and the occupancy
    // both read these tracks.
    let read = |symmetry: Option<&lamp_abstraction::PairSymmetry>| {
        let tracks = tracks(demonstrations, pauses, &type_pairs, symmetry);
        let selection = select(&tracks);
        (tracks, selection)
    };
    let Reading { symmetry, symmetry_choice, tracks, selection } =
        read_with_symmetry(config.pair_symmetry(pair), config.symmetry_from_data, read);
    let settings = match &selection {
        Some(selection) => selection.settings.clone(),
        None => pinned.resolve(&PairSettings::DEFAULT),
    };
    let grid = selection.as_ref().map_or_else(|| Grid::new(&settings), Selection::grid);
    let (occupancy, observations) = occupancy_of(&tracks, &grid);
    let mut critical =
        occupancy.critical(settings.threshold, config.min_support, config.rotation_share);
    if let Some(selection) = &selection {
        if !selection.learns_regions() {
            critical.clear();
        } else if !selection.groups.is_empty() {
            // Chosen settings make regions only where demonstrations stop or change contact.
            critical.retain(|cell, _| selection.cells.contains_key(cell));
        }
    }
    // With chosen settings a region is one place: neighbouring cells of two places stay two regions.
    let place =
        |cell: &crate::occupancy::Cell| selection.as_ref().and_then(|s| s.cells.get(cell).copied());
    let regions = regions::components(&critical, |a, b| place(a) == place(b))
        .into_iter()
        .map(|cells| {
            let demonstrated = selection
                .as_ref()
                .map_or_else(Vec::new, |selection| demonstrated_boxes(selection, &grid, &cells));
            let sides = capacity::decide(
                pair,
                primary_moves,
                &settings,
                &grid,
                &cells,
                &demonstrated,
                shapes,
            );
            summarise(&grid, cells, sides, &observations)
        })
        .collect();
    PairRegions {
        pair: pair.clone(),
        settings,
        selection,
        grid,
        demonstrations: occupancy.demonstrations(),
        regions,
        symmetry,
        symmetry_choice,
    }
}

/// A pair's recordings read one way: the symmetry folded by (none: as recorded), how it was
/// chosen, the tracks and the selection made from them.
struct Reading {
    symmetry: Option<lamp_abstraction::PairSymmetry>,
    symmetry_choice: Option<SymmetryChoice>,
    tracks: Vec<Track>,
    selection: Option<Selection>,
}

/// Reads a pair's recordings as recorded, folded by its `symmetry`, or, when the choice is the
/// data's (`from_data`), both ways, keeping the way `symmetry_choice::choose` takes.
fn read_with_symmetry(
    symmetry: Option<lamp_abstraction::PairSymmetry>,
    from_data: bool,
    read: impl Fn(Option<&lamp_abstraction::PairSymmetry>) -> (Vec<Track>, Option<Selection>) + Sync,
) -> Reading {
    let Some(symmetry) = symmetry else {
        let (tracks, selection) = read(None);
        return Reading { symmetry: None, symmetry_choice: None, tracks, selection };
    };
    if !from_data {
        let (tracks, selection) = read(Some(&symmetry));
        return Reading { symmetry: Some(symmetry), symmetry_choice: None, tracks, selection };
    }
    // The two readings are independent: on two cores, the choice costs no more time than one
    // of them.
    let ((recorded_tracks, recorded), (folded_tracks, folded)) = std::thread::scope(|scope| {
        let folded = scope.spawn(|| read(Some(&symmetry)));
        let as_recorded = read(None);
        let folded = folded.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (as_recorded, folded)
    });
    let choice = symmetry_choice::choose(
        recorded.as_ref().map(|selection| selection.groups.as_slice()),
        folded.as_ref().map(|selection| selection.groups.as_slice()),
        |pose| symmetry.canonical(pose).translation.vector.into(),
        |[x, y, z]| {
            let centre = Pose::translation(x, y, z);
            symmetry.members(&centre, false).map(|m| m.translation.vector.into()).collect()
        },
    );
    if choice.folded {
        let symmetry = Some(symmetry);
        Reading {
            symmetry,
            symmetry_choice: Some(choice),
            tracks: folded_tracks,
            selection: folded,
        }
    } else {
        let (tracks, selection) = (recorded_tracks, recorded);
        Reading { symmetry: None, symmetry_choice: Some(choice), tracks, selection }
    }
}

/// The grid cells the tracks visit, each counted once per demonstration, and every observation
/// in a cell. Tracks come per demonstration, in instance order; observations stay in step order
/// within one.
fn occupancy_of(tracks: &[Track], grid: &Grid) -> (Occupancy, Vec<Observation>) {
    let mut occupancy = Occupancy::default();
    let mut observations = Vec::new();
    for own in tracks.chunk_by(|a, b| a.demonstration == b.demonstration) {
        let mut visited = Vec::new();
        for step in 0..own[0].frames.len() {
            for track in own {
                let TrackFrame { g, pose, .. } = track.frames[step];
                let Some(voxel) = grid.voxel(&pose) else { continue };
                let rotation = grid.rotation_cell(&pose);
                visited.push((g, voxel, rotation));
                let demonstration = track.demonstration;
                observations.push(Observation { demonstration, g, voxel, rotation, pose });
            }
        }
        occupancy.add_demonstration(visited);
    }
    (occupancy, observations)
}

/// The keyframe boxes of the selection's groups whose centre lies in the region: where the demonstrations put
/// the secondary in it, without the tolerance its cells add around them.
fn demonstrated_boxes(selection: &Selection, grid: &Grid, cells: &RegionCells) -> Vec<Bounds> {
    selection
        .groups
        .iter()
        .filter(|group| {
            let centre = Pose::translation(group.centre[0], group.centre[1], group.centre[2]);
            group.g == cells.g
                && grid.voxel(&centre).is_some_and(|voxel| cells.voxels.contains_key(&voxel))
        })
        .map(|group| [0, 1, 2].map(|axis| (group.low[axis], group.high[axis])))
        .collect()
}

/// The steps of a demonstration into which nothing moved ([`selection::keyframes::scene_pauses`]).
fn scene_pauses(demonstration: &Demonstration) -> Vec<bool> {
    let world: Vec<&[Pose]> =
        demonstration.steps.iter().map(|snapshot| snapshot.poses.as_slice()).collect();
    selection::keyframes::scene_pauses(&world)
}

/// Every participant pair's relative motion through every demonstration, with held flags, contact changes and
/// the scene's pauses (one list per demonstration).
fn tracks(
    demonstrations: &[Demonstration],
    pauses: &[Vec<bool>],
    type_pairs: &[TypePair],
    symmetry: Option<&lamp_abstraction::PairSymmetry>,
) -> Vec<Track> {
    let mut tracks = Vec::new();
    for ((index, demonstration), paused) in demonstrations.iter().enumerate().zip(pauses) {
        let held: Vec<BTreeSet<usize>> = demonstration
            .steps
            .iter()
            .map(|snapshot| snapshot.held.iter().map(|(_, object)| *object).collect())
            .collect();
        for instance in pairs::instances(type_pairs, &demonstration.participants) {
            let changed = |step: usize, participant: usize| {
                step > 0
                    && held[step].contains(&participant) != held[step - 1].contains(&participant)
            };
            let frames = demonstration
                .steps
                .iter()
                .enumerate()
                .map(|(step, snapshot)| TrackFrame {
                    g: pairs::held_flag(snapshot, instance),
                    pose: {
                        let relative = pairs::relative_pose(snapshot, instance);
                        symmetry.map_or(relative, |symmetry| symmetry.canonical(&relative))
                    },
                    contact: changed(step, instance.primary) || changed(step, instance.secondary),
                    paused: paused[step],
                })
                .collect();
            tracks.push(Track {
                demonstration: index,
                primary: instance.primary,
                secondary: instance.secondary,
                frames,
            });
        }
    }
    tracks
}

fn summarise(
    grid: &Grid,
    cells: RegionCells,
    sides: RegionSides,
    observations: &[Observation],
) -> RegionSummary {
    let inside: Vec<&Observation> =
        observations.iter().filter(|o| cells.contains(o.g, o.voxel, o.rotation)).collect();
    let demonstrations = inside.iter().map(|o| o.demonstration).collect::<BTreeSet<_>>().len();
    let count = inside.len().max(1) as f64;
    let mut centre = [0.0; 3];
    let mut mean_features = [0.0; FEATURE_DIMENSION];
    for observation in &inside {
        let features = pose_features(&observation.pose);
        for (mean, value) in mean_features.iter_mut().zip(features) {
            *mean += value / count;
        }
    }
    centre.copy_from_slice(&mean_features[..3]);
    let mut spread = [0.0; 3];
    for observation in &inside {
        for (axis, deviation) in spread.iter_mut().enumerate() {
            *deviation +=
                (observation.pose.translation.vector[axis] - centre[axis]).powi(2) / count;
        }
    }
    let spread = spread.map(f64::sqrt);
    let distance = |pose: &Pose| -> f64 {
        pose_features(pose).iter().zip(&mean_features).map(|(a, b)| (a - b).powi(2)).sum()
    };
    // The first observation (in demonstration and time order) wins ties.
    let representative = inside
        .iter()
        .map(|o| (distance(&o.pose), o.pose))
        .fold(None, |best: Option<(f64, Pose)>, candidate| match best {
            Some(kept) if kept.0 <= candidate.0 => Some(kept),
            _ => Some(candidate),
        })
        .map_or_else(|| first_cell_centre(grid, &cells), |(_, pose)| pose);
    let mut bounds = [(f64::INFINITY, f64::NEG_INFINITY); 3];
    for voxel in cells.voxels.keys() {
        for (axis, (low, high)) in grid.voxel_bounds(*voxel).into_iter().enumerate() {
            bounds[axis].0 = bounds[axis].0.min(low);
            bounds[axis].1 = bounds[axis].1.max(high);
        }
    }
    RegionSummary {
        g: cells.g,
        time_steps: inside.len(),
        demonstrations,
        representative,
        centre,
        spread,
        bounds,
        cells,
        sides,
    }
}

fn first_cell_centre(grid: &Grid, cells: &RegionCells) -> Pose {
    let voxel = cells.voxels.keys().next().copied().unwrap_or_default();
    let centre = grid.voxel_centre(voxel);
    Pose::translation(centre[0], centre[1], centre[2])
}

/// For tests: a region's classifier is its exact cells, so that what is learned does not depend on a fit.
#[cfg(test)]
pub(crate) fn cells(
    pair: &PairRegions,
    index: usize,
    _: &mut ChaCha8Rng,
) -> Result<crate::abstraction::CellClassifier, LearnError> {
    Ok(crate::abstraction::CellClassifier {
        grid: pair.grid.clone(),
        cells: pair.regions[index].cells.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::capacity::NoShapes;
    use crate::synthetic::{packing_config, packing_demonstrations};

    #[test]
    fn packing_with_exact_cells_finds_the_paper_vocabulary() {
        let demonstrations = packing_demonstrations(40, 11);
        let induced = induce(&demonstrations, &packing_config(), &NoShapes, cells).expect("learns");
        let stems: Vec<String> = induced.pairs.iter().map(|p| p.pair.stem()).collect();
        assert_eq!(stems, ["gripper_can", "surface_can"]);
        let flags: Vec<u8> = induced.pairs[0].regions.iter().map(|r| r.g).collect();
        assert_eq!(flags, [0, 1]);
        // Both gripper–can regions sit where the can is at the grasp: 0.21 m below the gripper frame.
        for region in &induced.pairs[0].regions {
            assert!((region.centre[2] + 0.21).abs() < 0.01, "{:?}", region.centre);
            assert!(region.demonstrations >= 16 && region.demonstrations <= 40);
        }
        let in_box = &induced.pairs[1].regions[0];
        // The can sits in the box turned by π ± 0.15: one voxel, with rotation cells on both sides of the jump.
        assert_eq!(in_box.cells.voxels.len(), 1);
        let rotations = in_box.cells.voxels.values().next().expect("one voxel");
        let last = induced.pairs[1].settings.rotation_bins - 1;
        assert!(
            rotations.iter().any(|cell| cell[2] == 0)
                && rotations.iter().any(|cell| cell[2] == last)
        );
        assert!(in_box.centre.iter().all(|c| c.abs() < 0.01));
        assert_eq!(induced.actions.len(), 5);
        assert_eq!(induced.empty_pairs, vec![]);
    }

    #[test]
    fn a_pair_seen_in_no_demonstration_window_has_no_regions() {
        let mut config = packing_config();
        config.pairs.get_mut(&TypePair::new("surface", "can")).expect("configured").half_range =
            Some([0.001; 3]);
        let induced =
            induce(&packing_demonstrations(20, 5), &config, &NoShapes, cells).expect("learns");
        assert_eq!(induced.empty_pairs, vec![TypePair::new("surface", "can")]);
    }

    #[test]
    fn too_few_demonstrations_is_an_error_not_an_empty_domain() {
        let result = induce(&packing_demonstrations(2, 3), &packing_config(), &NoShapes, cells);
        assert!(matches!(result, Err(LearnError::NoRegions { demonstrations: 2 })));
    }
}
