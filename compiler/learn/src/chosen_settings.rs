//! Settings chosen from the demonstrations (`selection`), end to end on tasks whose answer is known: where a block comes to rest on a target, how many places it
//! rests in, tracking noise, and a waypoint every carry passes that must not become a region.

use crate::capacity::NoShapes;
use crate::config::{LearnConfig, PinnedSettings, TypePair};
use crate::error::LearnError;
use crate::learner::{PairRegions, cells, induce};
use crate::synthetic::{
    PLACE_GRASP_DEPTH, PLACE_WAYPOINT, PLACED_YAW, PlaceTask, place_demonstrations,
    place_participants,
};

const DEMONSTRATIONS: usize = 40;

fn learn_pairs(task: &PlaceTask, config: &LearnConfig) -> Vec<PairRegions> {
    let demonstrations = place_demonstrations(task, DEMONSTRATIONS, 5);
    induce(&demonstrations, config, &NoShapes, cells).expect("learns").pairs
}

fn pair<'a>(pairs: &'a [PairRegions], stem: &str) -> &'a PairRegions {
    pairs.iter().find(|p| p.pair.stem() == stem).unwrap_or_else(|| panic!("no {stem} regions"))
}

/// Whether a region's cells contain a position (m) in the primary's frame.
fn contains(pair: &PairRegions, region: usize, position: [f64; 3]) -> bool {
    let pose = crate::demo::Pose::translation(position[0], position[1], position[2]);
    pair.grid
        .voxel(&pose)
        .is_some_and(|voxel| pair.regions[region].cells.voxels.contains_key(&voxel))
}

#[test]
fn a_known_resting_offset_becomes_the_one_region_and_the_waypoint_none() {
    let task = PlaceTask {
        spots: vec![[0.0, 0.0, 0.05]],
        noise: 0.0,
        placed_yaw: PLACED_YAW,
        grasp_yaw: None,
    };
    let pairs = learn_pairs(&task, &LearnConfig::default());
    let target_block = pair(&pairs, "target_block");
    assert_eq!(target_block.regions.len(), 1, "{:?}", target_block.selection);
    let region = &target_block.regions[0];
    assert_eq!(region.g, 0);
    assert!(contains(target_block, 0, [0.0, 0.0, 0.05]));
    assert!((region.centre[2] - 0.05).abs() < 0.002, "{:?}", region.centre);
    // Every carry passes the waypoint, and more demonstrations pass it than rest on the target.
    assert!(!contains(target_block, 0, PLACE_WAYPOINT));
    let selection = target_block.selection.as_ref().expect("chosen");
    assert_eq!(selection.groups.len(), 1);
    // The gripper at the grasp, before (g = 0) and while holding (g = 1).
    let gripper_block = pair(&pairs, "gripper_block");
    let flags: Vec<u8> = gripper_block.regions.iter().map(|r| r.g).collect();
    assert_eq!(flags, [0, 1]);
    for (index, region) in gripper_block.regions.iter().enumerate() {
        assert!(contains(gripper_block, index, [0.0, 0.0, -PLACE_GRASP_DEPTH]), "{region:?}");
    }
}

#[test]
fn the_grasp_region_still_holds_an_object_that_settled_after_its_release() {
    let task = PlaceTask {
        spots: vec![[0.0, 0.0, 0.05]],
        noise: 0.0,
        placed_yaw: PLACED_YAW,
        grasp_yaw: None,
    };
    let config = LearnConfig { release_tolerance: 0.005, ..LearnConfig::default() };
    let pairs = learn_pairs(&task, &config);
    let gripper_block = pair(&pairs, "gripper_block");
    let released = gripper_block.regions.iter().position(|r| r.g == 0).expect("a grasp region");
    // Let go of 4.5 mm above its support, the block drops that far below the gripper's grasp.
    for offset in [-0.0045, 0.0045] {
        let settled = [0.0, 0.0, -PLACE_GRASP_DEPTH + offset];
        assert!(contains(gripper_block, released, settled), "{offset}");
    }
}

/// Whether a region's cells contain a pose of the secondary in the primary's frame.
fn contains_pose(pair: &PairRegions, region: usize, pose: &crate::demo::Pose) -> bool {
    let cells = &pair.regions[region].cells;
    pair.grid
        .voxel(pose)
        .is_some_and(|voxel| cells.contains(cells.g, voxel, pair.grid.rotation_cell(pose)))
}

#[test]
fn a_block_set_down_at_any_yaw_keeps_plain_cells_that_hold_it_upright_at_every_yaw() {
    use std::f64::consts::PI;
    // A turn about one fixed axis, which a few bins of one rotation-vector component hold: plain cells tell
    // upright from lying, so no turn is left free.
    let task =
        PlaceTask { spots: vec![[0.0, 0.0, 0.05]], noise: 0.0, placed_yaw: PI, grasp_yaw: None };
    let pairs = learn_pairs(&task, &LearnConfig::default());
    let target_block = pair(&pairs, "target_block");
    assert_eq!(target_block.regions.len(), 1, "{:?}", target_block.selection);
    assert_eq!(target_block.settings.free_turn, None);
    assert!(target_block.settings.rotation_bins > 1);
    let at = |roll: f64, yaw: f64| {
        let rotation = nalgebra::UnitQuaternion::from_euler_angles(roll, 0.0, yaw);
        crate::demo::Pose::from_parts(nalgebra::Translation3::new(0.0, 0.0, 0.05), rotation)
    };
    for yaw in [-3.1, -1.7, 0.0, 0.4, 2.2, PI] {
        assert!(contains_pose(target_block, 0, &at(0.0, yaw)), "upright at yaw {yaw}");
        assert!(!contains_pose(target_block, 0, &at(PI / 2.0, yaw)), "lying at yaw {yaw}");
    }
}

#[test]
fn a_block_taken_by_a_magnet_at_any_yaw_turns_freely_and_is_never_held_tilted() {
    use std::f64::consts::PI;
    // Flipped under a magnet at every yaw: a half turn about every horizontal axis, which only one bin per
    // rotation-vector component holds. The turn about the block's own axis is left free instead.
    let task = PlaceTask {
        spots: vec![[0.0, 0.0, 0.05]],
        noise: 0.0,
        placed_yaw: PLACED_YAW,
        grasp_yaw: Some(PI),
    };
    let pairs = learn_pairs(&task, &LearnConfig::default());
    let gripper_block = pair(&pairs, "gripper_block");
    let turn = gripper_block.settings.free_turn.expect("the grasp's yaw is left free");
    assert_eq!(turn.axis, 2);
    let held = gripper_block.regions.iter().position(|region| region.cells.g == 1).expect("a hold");
    let at = |roll: f64, yaw: f64| {
        let flipped = nalgebra::UnitQuaternion::from_euler_angles(PI, 0.0, 0.0);
        let rotation = flipped * nalgebra::UnitQuaternion::from_euler_angles(roll, 0.0, yaw);
        let depth = crate::synthetic::PLACE_GRASP_DEPTH;
        crate::demo::Pose::from_parts(nalgebra::Translation3::new(0.0, 0.0, depth), rotation)
    };
    for yaw in [-3.1, -1.7, 0.0, 0.4, 2.2, PI] {
        assert!(contains_pose(gripper_block, held, &at(0.0, yaw)), "held at yaw {yaw}");
        assert!(!contains_pose(gripper_block, held, &at(0.35, yaw)), "tilted 20° at yaw {yaw}");
    }
    // Taken square, nothing turns freely.
    let square = learn_pairs(&PlaceTask { grasp_yaw: None, ..task }, &LearnConfig::default());
    assert_eq!(pair(&square, "gripper_block").settings.free_turn, None);
}

#[test]
fn two_resting_places_are_two_regions() {
    let task = PlaceTask {
        spots: vec![[0.08, 0.0, 0.05], [-0.08, 0.0, 0.05]],
        noise: 0.0,
        placed_yaw: PLACED_YAW,
        grasp_yaw: None,
    };
    let pairs = learn_pairs(&task, &LearnConfig::default());
    let target_block = pair(&pairs, "target_block");
    assert_eq!(target_block.regions.len(), 2, "{:?}", target_block.selection);
    let mut centres: Vec<f64> = target_block.regions.iter().map(|r| r.centre[0]).collect();
    centres.sort_by(f64::total_cmp);
    assert!((centres[0] + 0.08).abs() < 0.002 && (centres[1] - 0.08).abs() < 0.002, "{centres:?}");
}

#[test]
fn tracking_noise_leaves_the_regions_as_they_were() {
    let clean = learn_pairs(
        &PlaceTask {
            spots: vec![[0.0, 0.0, 0.05]],
            noise: 0.0,
            placed_yaw: PLACED_YAW,
            grasp_yaw: None,
        },
        &LearnConfig::default(),
    );
    let noisy = learn_pairs(
        &PlaceTask {
            spots: vec![[0.0, 0.0, 0.05]],
            noise: 0.001,
            placed_yaw: PLACED_YAW,
            grasp_yaw: None,
        },
        &LearnConfig::default(),
    );
    let shape = |pairs: &[PairRegions]| -> Vec<(String, Vec<u8>)> {
        pairs.iter().map(|p| (p.pair.stem(), p.regions.iter().map(|r| r.g).collect())).collect()
    };
    assert_eq!(shape(&noisy), shape(&clean));
    let target_block = pair(&noisy, "target_block");
    assert!(contains(target_block, 0, [0.0, 0.0, 0.05]));
    assert!((target_block.regions[0].centre[2] - 0.05).abs() < 0.003);
    // The target is static and the block rests between grasps: both are steadied before anything is
    // chosen, so the pair's steps at rest are as still as without noise.
    let selection = target_block.selection.as_ref().expect("chosen");
    let clean_selection = pair(&clean, "target_block").selection.as_ref().expect("chosen");
    assert_eq!(selection.stillness, clean_selection.stillness);
}

#[test]
fn pinned_settings_are_kept_and_the_rest_chosen_around_them() {
    let mut config = LearnConfig::default();
    config.pairs.insert(
        TypePair::new("target", "block"),
        PinnedSettings {
            rotation_bins: Some(5),
            half_range: Some([0.2; 3]),
            ..PinnedSettings::default()
        },
    );
    let pairs = learn_pairs(
        &PlaceTask {
            spots: vec![[0.0, 0.0, 0.05]],
            noise: 0.0,
            placed_yaw: PLACED_YAW,
            grasp_yaw: None,
        },
        &config,
    );
    let target_block = pair(&pairs, "target_block");
    assert_eq!(
        (target_block.settings.rotation_bins, target_block.settings.half_range),
        (5, [0.2; 3])
    );
    let chosen = target_block.selection.as_ref().expect("chosen").chosen;
    assert!(
        chosen.position_bins && chosen.threshold && !chosen.rotation_bins && !chosen.half_range
    );
    assert!(contains(target_block, 0, [0.0, 0.0, 0.05]));
}

#[test]
fn the_selection_is_deterministic() {
    let task = PlaceTask {
        spots: vec![[0.0, 0.0, 0.05]],
        noise: 0.001,
        placed_yaw: PLACED_YAW,
        grasp_yaw: None,
    };
    let first = learn_pairs(&task, &LearnConfig::default());
    let second = learn_pairs(&task, &LearnConfig::default());
    assert_eq!(first, second);
}

#[test]
fn the_report_says_what_was_chosen_and_how_to_pin_it() {
    let task = PlaceTask {
        spots: vec![[0.0, 0.0, 0.05]],
        noise: 0.0,
        placed_yaw: PLACED_YAW,
        grasp_yaw: None,
    };
    let demonstrations = place_demonstrations(&task, DEMONSTRATIONS, 5);
    let model = crate::learn(
        &demonstrations,
        &LearnConfig { seed: 3, ..LearnConfig::default() },
        &NoShapes,
    )
    .expect("learns");
    let report = crate::vocabulary_report(&model);
    assert!(report.contains("Chosen from the demonstrations: position bins, range, rotation bins, threshold (to pin them: `position bins ("), "{report}");
    assert!(report.contains(
        "| group | g | demonstrations | keyframes | scale | centre | extent | tolerance | cell share |"
    ));
    // The gripper's grasp keeps the release tolerance, the resting place on the target the placement one.
    assert!(report.contains(" | 5 mm | "), "{report}");
    assert!(report.contains(" | 2 mm | "), "{report}");
}

/// Demonstrations in which a block stands still on a target from the first step to the last: no keyframe.
fn still_demonstrations() -> Vec<crate::demo::Demonstration> {
    use crate::demo::{Demonstration, Pose, Snapshot};
    (0..10)
        .map(|index| Demonstration {
            id: format!("still-{index}"),
            // The block and the target, without the gripper.
            participants: place_participants()[1..].to_vec(),
            steps: vec![
                Snapshot {
                    poses: vec![Pose::translation(0.0, 0.0, 0.05), Pose::identity()],
                    held: vec![],
                };
                5
            ],
        })
        .collect()
}

#[test]
fn without_keyframe_groups_a_pair_learns_a_region_only_from_a_pinned_threshold() {
    let demonstrations = still_demonstrations();
    let chosen = induce(&demonstrations, &LearnConfig::default(), &NoShapes, cells);
    assert!(
        matches!(chosen, Err(LearnError::NoRegions { .. })),
        "nothing happens, nothing is learned"
    );
    let mut config = LearnConfig::default();
    config.default.threshold = Some(0.5);
    let pairs = induce(&demonstrations, &config, &NoShapes, cells).expect("learns").pairs;
    let target_block = pair(&pairs, "target_block");
    assert_eq!(target_block.regions.len(), 1);
    assert!(contains(target_block, 0, [0.0, 0.0, 0.05]));
    assert_eq!(target_block.settings.position_bins, crate::PairSettings::DEFAULT.position_bins);
}
