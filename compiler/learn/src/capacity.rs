//! Which regions get clear relations on each side of their pair: the settings, and for `auto` a capacity test.
//!
//! `clear_<t1>_<t2>_<k>(x)` ("no t2 in region k of x") is a sound precondition only if region k of one x holds
//! one t2 at a time; `nowhere_<t1>_<t2>_<k>(y)` ("y is in region k of no t1") only if y can be in region k of
//! one t1 at a time.
//! With the side's switch at `auto`, the caller's [`ShapeOracle`] answers whether two bodies fit at once at the
//! region's candidate poses: the corners of the positions the demonstrations show in the region (each of its
//! groups' keyframe boxes, where the settings were chosen from them), else of every voxel, each with the centre
//! rotation of every rotation cell (deduplicated, in index order), as the secondary in the primary's frame for
//! the primary side, and inverted (the primary in the secondary's frame) for the secondary side.
//! A chosen cell is the demonstrated box padded by the tolerance of a membership test: room for noise, not for a
//! second body. A plank on its marker, within 1.5 mm in height, pads to 7.4 mm, which a second 7 mm plank would
//! fit above; the demonstrations never put two there.
//! The candidates are sample-free, so the decision never draws from the learner's generator.
//! Two fit → the side is off for the region; they cannot, or the type's shape is unknown (robot parts) → on.
//! The primary side of a pair whose primary is a robot part stays on without a test: such a region is where the
//! robot part goes, not a container, and "no t2 in region k of this part" is what makes a plan leave one object
//! before it goes to another (without it, the relation to the object left behind would stay true in the model).

use std::collections::BTreeSet;
use std::fmt;

use crate::config::{PairSettings, Switch, TypePair};
use crate::demo::Pose;
use crate::discretise::{Bounds, Grid};
use crate::regions::RegionCells;

/// Geometry the learner does not know: the shapes of the participants' types. Shared by the
/// threads that read one pair's demonstrations two ways (`symmetry auto`).
pub trait ShapeOracle: Sync {
    /// Whether two bodies of the type, at two different poses of `poses` (all in one frame), can stand at once
    /// without overlapping (touching counts as overlapping); `None` when the type has no known shape.
    fn two_fit(&self, type_name: &str, poses: &[Pose]) -> Option<bool>;

    /// The distance (m) between a body of type `primary` at the origin and one of type `secondary` at `relative`
    /// in its frame (0 where they overlap); `None` when either type has no known shape.
    fn gap(&self, primary: &str, secondary: &str, relative: &Pose) -> Option<f64>;

    /// The axis (0, 1, 2: x, y, z of its frame) about which a type's shape is round, so that every turn about it
    /// maps the shape onto itself (a can, a bowl); `None` for any other shape or an unknown one.
    fn round_axis(&self, _type_name: &str) -> Option<usize> {
        None
    }

    /// The smallest and largest coordinates of a type's shape in its own frame; `None` for an unknown shape.
    fn bounding_box(&self, _type_name: &str) -> Option<([f64; 3], [f64; 3])> {
        None
    }
}

impl<O: ShapeOracle + ?Sized> ShapeOracle for &O {
    fn two_fit(&self, type_name: &str, poses: &[Pose]) -> Option<bool> {
        (**self).two_fit(type_name, poses)
    }

    fn gap(&self, primary: &str, secondary: &str, relative: &Pose) -> Option<f64> {
        (**self).gap(primary, secondary, relative)
    }

    fn round_axis(&self, type_name: &str) -> Option<usize> {
        (**self).round_axis(type_name)
    }

    fn bounding_box(&self, type_name: &str) -> Option<([f64; 3], [f64; 3])> {
        (**self).bounding_box(type_name)
    }
}

/// An oracle that knows no shape: every `auto` side is on (the behaviour before the capacity test).
#[derive(Debug, Clone, Copy, Default)]
pub struct NoShapes;

impl ShapeOracle for NoShapes {
    fn two_fit(&self, _: &str, _: &[Pose]) -> Option<bool> {
        None
    }

    fn gap(&self, _: &str, _: &str, _: &Pose) -> Option<f64> {
        None
    }
}

/// Why a side is on or off for a region.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SideReason {
    /// The pair's setting is `on` or `off`.
    Setting,
    /// `auto`, and two bodies fit in the region at once.
    TwoFit,
    /// `auto`, and no two bodies fit in the region at once.
    OneAtATime,
    /// `auto`, and the type whose capacity matters has no known shape.
    UnknownShape,
    /// `auto` on the primary side, and the primary is a robot part: it goes to one object at a time.
    RobotPart,
}

/// One side's decision for one region.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Side {
    /// Whether the relation exists.
    pub on: bool,
    /// Why.
    pub reason: SideReason,
}

/// Both sides' decisions for one region.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RegionSides {
    /// `clear_<t1>_<t2>_<k>(x)`: no t2 in region k of x.
    pub clear: Side,
    /// `nowhere_<t1>_<t2>_<k>(y)`: y in region k of no t1.
    pub nowhere: Side,
}

impl Default for RegionSides {
    /// Both sides on, as the settings' `on` gives.
    fn default() -> Self {
        let on = Side { on: true, reason: SideReason::Setting };
        RegionSides { clear: on, nowhere: on }
    }
}

impl fmt::Display for Side {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let text = match (self.on, self.reason) {
            (true, SideReason::Setting) => "on by setting",
            (false, SideReason::Setting) => "off by setting",
            (_, SideReason::TwoFit) => "two fit at once",
            (_, SideReason::OneAtATime) => "one at a time",
            (_, SideReason::UnknownShape) => "shape unknown",
            (_, SideReason::RobotPart) => "robot part",
        };
        f.write_str(text)
    }
}

/// The decision for both sides of one region of a pair; `primary_moves` tells that the primary is a robot part.
pub fn decide(
    pair: &TypePair,
    primary_moves: bool,
    settings: &PairSettings,
    grid: &Grid,
    cells: &RegionCells,
    demonstrated: &[Bounds],
    oracle: &dyn ShapeOracle,
) -> RegionSides {
    let mut candidates: Option<Vec<Pose>> = None;
    let mut side = |switch: Switch, type_name: &str, invert: bool| match switch {
        Switch::On => Side { on: true, reason: SideReason::Setting },
        Switch::Off => Side { on: false, reason: SideReason::Setting },
        Switch::Auto => {
            let poses =
                candidates.get_or_insert_with(|| candidate_poses(grid, cells, demonstrated));
            let answer = if invert {
                let inverted: Vec<Pose> = poses.iter().map(Pose::inverse).collect();
                oracle.two_fit(type_name, &inverted)
            } else {
                oracle.two_fit(type_name, poses)
            };
            match answer {
                Some(true) => Side { on: false, reason: SideReason::TwoFit },
                Some(false) => Side { on: true, reason: SideReason::OneAtATime },
                None => Side { on: true, reason: SideReason::UnknownShape },
            }
        }
    };
    let clear = if primary_moves && settings.clear == Switch::Auto {
        Side { on: true, reason: SideReason::RobotPart }
    } else {
        side(settings.clear, &pair.secondary, false)
    };
    let nowhere = side(settings.nowhere, &pair.primary, true);
    RegionSides { clear, nowhere }
}

/// The region's candidate poses of the secondary in the primary's frame: every corner of the `demonstrated` boxes,
/// or with none every voxel corner (deduplicated), with the centre rotation of every rotation cell of the region
/// (deduplicated), corners and cells in index order.
pub fn candidate_poses(grid: &Grid, cells: &RegionCells, demonstrated: &[Bounds]) -> Vec<Pose> {
    let rotations: BTreeSet<[usize; 3]> = cells.voxels.values().flatten().copied().collect();
    let rotations: Vec<nalgebra::UnitQuaternion<f64>> =
        rotations.into_iter().map(|cell| grid.rotation_cell_centre(cell)).collect();
    let positions = if !demonstrated.is_empty() {
        demonstrated.iter().copied().flat_map(corners).collect()
    } else if grid.boxes().is_empty() {
        grid_corners(grid, cells)
    } else {
        cells.voxels.keys().flat_map(|voxel| corners(grid.voxel_bounds(*voxel))).collect()
    };
    let mut poses = Vec::with_capacity(positions.len() * rotations.len());
    for position in positions {
        for rotation in &rotations {
            poses.push(Pose::from_parts(position.into(), *rotation));
        }
    }
    poses
}

/// The corners of a uniform grid's voxels, each once, in index order.
fn grid_corners(grid: &Grid, cells: &RegionCells) -> Vec<nalgebra::Vector3<f64>> {
    let corners: BTreeSet<[usize; 3]> = cells
        .voxels
        .keys()
        .flat_map(|voxel| {
            (0..8).map(move |corner: usize| {
                [0, 1, 2].map(|axis| voxel[axis] + ((corner >> axis) & 1))
            })
        })
        .collect();
    let low = grid.voxel_bounds([0; 3]);
    let width: Vec<f64> = (0..3).map(|axis| low[axis].1 - low[axis].0).collect();
    corners
        .into_iter()
        .map(|corner| {
            nalgebra::Vector3::from_fn(|axis, _| low[axis].0 + corner[axis] as f64 * width[axis])
        })
        .collect()
}

/// The eight corners of a box.
fn corners(bounds: Bounds) -> impl Iterator<Item = nalgebra::Vector3<f64>> {
    (0..8).map(move |corner: usize| {
        nalgebra::Vector3::from_fn(|axis, _| {
            if (corner >> axis) & 1 == 0 { bounds[axis].0 } else { bounds[axis].1 }
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;
    use std::f64::consts::PI;
    use std::sync::Mutex;

    /// Answers from a table by type, and remembers the poses it was asked about.
    struct Table {
        answers: BTreeMap<&'static str, bool>,
        asked: Mutex<Vec<(String, Vec<Pose>)>>,
    }

    impl ShapeOracle for Table {
        fn two_fit(&self, type_name: &str, poses: &[Pose]) -> Option<bool> {
            self.asked.lock().expect("not poisoned").push((type_name.to_string(), poses.to_vec()));
            self.answers.get(type_name).copied()
        }

        fn gap(&self, _: &str, _: &str, _: &Pose) -> Option<f64> {
            None
        }
    }

    fn grid() -> Grid {
        Grid::new(&PairSettings {
            position_bins: [4, 4, 2],
            half_range: [0.2, 0.2, 0.1],
            rotation_bins: 4,
            ..PairSettings::default()
        })
    }

    /// Two voxels sharing a face, one with two rotation cells.
    fn cells() -> RegionCells {
        RegionCells {
            g: 0,
            voxels: BTreeMap::from([
                ([1, 1, 0], BTreeSet::from([[2, 2, 2]])),
                ([2, 1, 0], BTreeSet::from([[2, 2, 2], [2, 2, 3]])),
            ]),
        }
    }

    #[test]
    fn candidates_are_the_deduplicated_corners_times_the_cell_centres() {
        let poses = candidate_poses(&grid(), &cells(), &[]);
        // Two voxels sharing a face have 12 distinct corners; two distinct rotation cells.
        assert_eq!(poses.len(), 24);
        let first = poses[0];
        assert!(
            (first.translation.vector - nalgebra::Vector3::new(-0.1, -0.1, -0.1)).norm() < 1e-12
        );
        // Cell 2 of 4 over [-π, π] has its centre at π/4; cell 3 at 3π/4.
        assert!((first.rotation.scaled_axis() - nalgebra::Vector3::repeat(PI / 4.0)).norm() < 1e-9);
        let last = poses[23];
        assert!((last.translation.vector - nalgebra::Vector3::new(0.1, 0.0, 0.0)).norm() < 1e-12);
        let expected = nalgebra::Vector3::new(PI / 4.0, PI / 4.0, 3.0 * PI / 4.0);
        let turned = nalgebra::UnitQuaternion::from_scaled_axis(expected);
        assert!(last.rotation.angle_to(&turned) < 1e-9);
    }

    #[test]
    fn demonstrated_boxes_replace_the_cells_as_the_room_a_region_offers() {
        // A plank's marker region: demonstrated within 1.5 mm in height, in a cell 20 cm tall.
        let demonstrated = [[(-0.0016, 0.0016), (-0.0014, 0.0014), (0.0, 0.0015)]];
        let poses = candidate_poses(&grid(), &cells(), &demonstrated);
        // Eight corners of the one box, each with the region's two rotation cells.
        assert_eq!(poses.len(), 16);
        for pose in &poses {
            let at = pose.translation.vector;
            assert!((0..3).all(|axis| {
                demonstrated[0][axis].0 <= at[axis] && at[axis] <= demonstrated[0][axis].1
            }));
        }
        let highest = poses.iter().map(|pose| pose.translation.z).fold(f64::MIN, f64::max);
        assert_eq!(highest, 0.0015);
        // Two boxes (two groups in one region) give the corners of both.
        let two = [demonstrated[0], [(0.05, 0.06), (0.0, 0.0), (0.0, 0.0)]];
        assert_eq!(candidate_poses(&grid(), &cells(), &two).len(), 32);
    }

    #[test]
    fn two_fit_turns_a_side_off_and_unknown_shapes_leave_it_on() {
        let pair = TypePair::new("surface", "can");
        let oracle = Table {
            answers: BTreeMap::from([("can", true), ("surface", false)]),
            asked: Mutex::new(Vec::new()),
        };
        let settings = PairSettings::default();
        let sides = decide(&pair, false, &settings, &grid(), &cells(), &[], &oracle);
        assert_eq!(sides.clear, Side { on: false, reason: SideReason::TwoFit });
        assert_eq!(sides.nowhere, Side { on: true, reason: SideReason::OneAtATime });
        let asked = oracle.asked.lock().expect("not poisoned");
        // The secondary side asks about the primary's poses in the secondary's frame: the inverses.
        assert_eq!((asked[0].0.as_str(), asked[1].0.as_str()), ("can", "surface"));
        assert_eq!(asked[1].1[5], asked[0].1[5].inverse());
        drop(asked);
        // Two cans fit in the gripper's region, but the gripper goes to one can at a time.
        let gripper = TypePair::new("gripper", "can");
        let sides = decide(&gripper, true, &settings, &grid(), &cells(), &[], &oracle);
        assert_eq!(sides.clear, Side { on: true, reason: SideReason::RobotPart });
        assert_eq!(sides.nowhere, Side { on: true, reason: SideReason::UnknownShape });
        assert_eq!(
            decide(&pair, false, &settings, &grid(), &cells(), &[], &NoShapes),
            RegionSides {
                clear: Side { on: true, reason: SideReason::UnknownShape },
                nowhere: Side { on: true, reason: SideReason::UnknownShape },
            }
        );
        let off = PairSettings { clear: Switch::Off, ..PairSettings::default() };
        let sides = decide(&gripper, true, &off, &grid(), &cells(), &[], &oracle);
        assert_eq!(sides.clear, Side { on: false, reason: SideReason::Setting });
    }

    #[test]
    fn settings_on_and_off_never_ask_the_oracle() {
        let oracle =
            Table { answers: BTreeMap::from([("can", true)]), asked: Mutex::new(Vec::new()) };
        let settings =
            PairSettings { clear: Switch::On, nowhere: Switch::Off, ..PairSettings::default() };
        let pair = TypePair::new("surface", "can");
        let sides = decide(&pair, false, &settings, &grid(), &cells(), &[], &oracle);
        assert_eq!(sides.clear, Side { on: true, reason: SideReason::Setting });
        assert_eq!(sides.nowhere, Side { on: false, reason: SideReason::Setting });
        assert!(oracle.asked.lock().expect("not poisoned").is_empty());
    }
}
