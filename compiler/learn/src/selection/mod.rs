//! Settings chosen from the demonstrations, for a type pair whose spec leaves them out.
//!
//! The criterion: a region is a place where demonstrations stop or change contact, seen in many of them. So
//! 1. [`keyframes`]: the steps where the pair comes to rest, leaves rest, or an object of it is grasped or let
//!    go of; every pose a carry merely passes through is left out;
//! 2. [`fixed_axes`]: the position axes along which no demonstration moves the pair (a table's height under a
//!    mobile base) are left out of clustering and get one cell;
//! 3. [`clusters`]: keyframes grouped where they stay the same over a fourfold change of scale, per held flag,
//!    by how far the secondary's shape moves between them ([`pose_distance`]), not by position alone; a group
//!    must come from at least the minimum support of demonstrations and from at least
//!    [`MIN_RELATIVE_SUPPORT`] as many as the pair's best-supported group;
//! 4. [`free_turn`]: whether every group shows the secondary at every angle about one axis of its own frame (a
//!    round object set down or grasped at any yaw); rotation cells are then taken from a demonstrated rotation,
//!    with one bin for that turn;
//! 5. [`grid_choice`]: the finest grid that keeps every group in one cell, the rotation bins that keep its
//!    rotations in the cells learning keeps, and the threshold θ = the least share of demonstrations that
//!    visits a group's cell, so that every group's cell is critical.
//!
//! Regions are then made of the groups' cells only: a cell that carries pass through in every demonstration is
//! visited often, yet nothing happens there.
//!
//! What the user pinned is kept, and the rest is chosen around it. The component count is chosen per region by
//! BIC, up to the cap; the cap, the likelihood cover and the clear and nowhere switches come from
//! [`PairSettings::DEFAULT`] when left out. A pair whose keyframes form no group learns no region unless its
//! threshold is pinned.

pub mod clusters;
pub mod fixed_axes;
pub mod free_turn;
pub mod grid_choice;
pub mod keyframes;
pub mod pose_distance;

use std::collections::{BTreeMap, BTreeSet};

use crate::config::{PairSettings, PinnedSettings};
use crate::discretise::{Bounds, FreeTurn, Grid};
pub use clusters::MIN_RELATIVE_SUPPORT;
pub use keyframes::{Stillness, Track, TrackFrame};

/// A cell of the pair's grid with its held flag.
pub type FlaggedCell = (u8, [usize; 3]);

/// Padding around a group's keyframes, as a share of its extent along the axis.
pub const EXTENT_PADDING: f64 = 0.02;
/// The least padding (m) around a group's keyframes where nothing is let go of: the precision to which a robot
/// repeats a placement.
pub const PLACEMENT_TOLERANCE: f64 = 0.002;

/// What was chosen for one pair, and the evidence that chose it.
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    /// Every setting, pinned or chosen.
    pub settings: PairSettings,
    /// Which settings were chosen rather than pinned.
    pub chosen: Chosen,
    /// Keyframes found, over every held flag (after those of two bodies apart are left out).
    pub keyframes: usize,
    /// For a pair of two movable objects with known shapes, the keyframes left out because the two did not
    /// touch ([`Contact`]); `None` for every other pair.
    pub apart: Option<usize>,
    /// How still a step must be to count as rest.
    pub stillness: Stillness,
    /// The groups the settings keep, in order of held flag, then support (most first).
    pub groups: Vec<Group>,
    /// Stable groups left out for too little support.
    pub dropped: usize,
    /// Per axis, the least margin of a group from its cell's edges (share of a cell).
    pub margins: [f64; 3],
    /// Per axis, whether no demonstration moves the pair along it ([`fixed_axes`]): one cell spans it.
    pub fixed_axes: [bool; 3],
    /// The cells, with their held flag, that the groups' keyframes fall in: the only cells regions are made of.
    /// Each is labelled with its place: the first of the groups that share cells with one another, so that
    /// groups in neighbouring cells stay apart (a plank resting by another in 22 ways, some a cell apart).
    pub cells: BTreeMap<FlaggedCell, usize>,
    /// Where no uniform grid keeps the places apart, the box of each place ([`Grid::with_boxes`]); else empty.
    pub boxes: Vec<Bounds>,
}

/// Which settings the selection chose.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Chosen {
    /// Bins per axis.
    pub position_bins: bool,
    /// Half-ranges.
    pub half_range: bool,
    /// Rotation bins.
    pub rotation_bins: bool,
    /// Threshold θ.
    pub threshold: bool,
}

/// A stable group of keyframes.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// Its held flag.
    pub g: u8,
    /// Demonstrations with a keyframe in it.
    pub demonstrations: usize,
    /// The scale (m) at which it separated from the rest.
    pub scale: f64,
    /// The mean position (m).
    pub centre: [f64; 3],
    /// The smallest position per axis (m).
    pub low: [f64; 3],
    /// The largest position per axis (m).
    pub high: [f64; 3],
    /// The share of the pair's demonstrations that visit its best cell of the chosen grid.
    pub share: f64,
    /// The least distance (m) its keyframes keep from its cell's edges: the release tolerance where the pair's
    /// own grasp or release happens in it, else the placement tolerance.
    pub tolerance: f64,
    /// Its keyframes' relative poses.
    pub poses: Vec<crate::demo::Pose>,
}

impl Group {
    /// Its keyframes.
    pub fn keyframes(&self) -> usize {
        self.poses.len()
    }
}

impl Selection {
    /// The cells learning counts visits in: the settings' uniform grid, or the boxes of the places.
    pub fn grid(&self) -> Grid {
        if self.boxes.is_empty() {
            Grid::new(&self.settings)
        } else {
            Grid::with_boxes(&self.settings, self.boxes.clone())
        }
    }

    /// Whether the pair may learn regions: it has a group, or its threshold was pinned.
    pub fn learns_regions(&self) -> bool {
        !self.groups.is_empty() || !self.chosen.threshold
    }
}

/// Whether two movable objects touch at a relative pose: within the release tolerance of each other, the farthest
/// an object let go of above its support may be from it.
///
/// Two movable objects are related through contact, one resting on or against the other. One that comes to rest
/// near another without touching it was placed by something else (its marker, the table it stands on), and their
/// relative pose is where those happen to be: Jenga's spare blocks laid out 10 cm apart, or two cans in a box.
pub type Contact<'a> = &'a (dyn Fn(&crate::demo::Pose) -> bool + Sync);

/// What the pair's shapes say where the demonstrations alone cannot.
#[derive(Clone, Copy, Default)]
pub struct ShapeFacts<'a> {
    /// For a pair of two movable objects with known shapes: whether they touch at a relative pose.
    pub contact: Option<Contact<'a>>,
    /// The axis of its own frame about which the secondary's shape is round (a can, a bowl).
    pub round: Option<usize>,
    /// The points of the secondary that tell its keyframe poses apart ([`pose_distance`]); `None`: its position
    /// alone.
    pub probes: Option<&'a pose_distance::Probes>,
}

/// Chooses every setting `pinned` leaves out from the pair's tracks over `demonstrations` demonstrations;
/// the keyframes of a group where the pair's own grasp or release happens stay at least `release_tolerance` (m)
/// inside its cell ([`LearnConfig`]), those of every other group [`PLACEMENT_TOLERANCE`].
///
/// [`LearnConfig`]: crate::config::LearnConfig
///
/// With `shape.contact`, only keyframes at which the two touch count; with `shape.round`, the rotation bins keep
/// every angle of the secondary's turn where a group shows it turned more than half the way round
/// ([`grid_choice::choose_rotation_bins`]).
pub fn select(
    pinned: &PinnedSettings,
    tracks: &[Track],
    demonstrations: usize,
    min_support: usize,
    rotation_share: f64,
    release_tolerance: f64,
    shape: ShapeFacts<'_>,
) -> Selection {
    let chosen = Chosen {
        position_bins: pinned.position_bins.is_none(),
        half_range: pinned.half_range.is_none(),
        rotation_bins: pinned.rotation_bins.is_none(),
        threshold: pinned.threshold.is_none(),
    };
    let stillness = keyframes::stillness(tracks);
    let (keyframes, apart) = match shape.contact {
        Some(touching) => {
            let mut every = keyframes::keyframes_with_every_partner(tracks, stillness);
            let before = every.len();
            every.retain(|keyframe| touching(&keyframe.pose));
            let apart = before - every.len();
            (every, Some(apart))
        }
        None => (keyframes::keyframes(tracks, stillness), None),
    };
    let fixed_axes = fixed_axes::fixed_axes(tracks, stillness);
    let (found, dropped) =
        keyframe_groups(&keyframes, fixed_axes, shape.probes, min_support, demonstrations);

    let fallback = pinned.resolve(&PairSettings::DEFAULT);
    if found.is_empty() {
        return Selection {
            settings: fallback,
            chosen,
            keyframes: keyframes.len(),
            apart,
            stillness,
            groups: Vec::new(),
            dropped,
            margins: [0.0; 3],
            fixed_axes,
            cells: BTreeMap::new(),
            boxes: Vec::new(),
        };
    }
    let extents: Vec<([f64; 3], [f64; 3])> =
        found.iter().map(|(_, members, _)| bounds(members)).collect();
    // An object let go of settles by up to the release tolerance, and the relation it had to what let it go
    // must still hold once it is at rest.
    let floors: Vec<f64> =
        found
            .iter()
            .map(|(_, members, _)| {
                if members.iter().any(|k| k.grip) { release_tolerance } else { PLACEMENT_TOLERANCE }
            })
            .collect();
    let (half_range, position_bins, mut margins) =
        position_grid(pinned, &extents, &floors, fixed_axes);
    let (rotation_bins, free_turn) = match pinned.rotation_bins {
        Some(bins) => (bins, None),
        None => rotation_choice(&found, rotation_share, shape.round),
    };
    let mut settings =
        PairSettings { position_bins, half_range, rotation_bins, free_turn, ..fallback };
    let mut grid = Grid::new(&settings);
    let (mut shares, mut cells) = best_cell_shares(&grid, &found, tracks, demonstrations);
    // Each axis's bins must keep every group whole, so groups far apart on one axis can still share a cell
    // when their intervals chain along the others: then each place gets a box of its own.
    let places = place_count(&cells);
    if places < found.len() && chosen.position_bins && chosen.half_range {
        let boxes = place_boxes(&extents, &floors, fixed_axes);
        let boxed = Grid::with_boxes(&settings, boxes.clone());
        let (boxed_shares, boxed_cells) = best_cell_shares(&boxed, &found, tracks, demonstrations);
        if place_count(&boxed_cells) > places {
            margins = box_margins(&boxes, &extents);
            (grid, shares, cells) = (boxed, boxed_shares, boxed_cells);
        }
    }
    if chosen.threshold {
        let least = shares.iter().copied().fold(1.0, f64::min);
        settings.threshold = least.clamp(f64::MIN_POSITIVE, 1.0);
    }
    let groups = found
        .iter()
        .zip(&extents)
        .zip(&shares)
        .zip(&floors)
        .map(|((((g, members, scale), (low, high)), share), tolerance)| Group {
            g: *g,
            demonstrations: support(members),
            scale: *scale,
            centre: centre(members),
            low: *low,
            high: *high,
            share: *share,
            tolerance: *tolerance,
            poses: members.iter().map(|k| k.pose).collect(),
        })
        .collect();
    Selection {
        settings,
        chosen,
        keyframes: keyframes.len(),
        apart,
        stillness,
        groups,
        dropped,
        margins,
        fixed_axes,
        cells,
        boxes: grid.boxes().to_vec(),
    }
}

/// The keyframe groups of each held flag (flag, members, scale), every group that too few
/// demonstrations show dropped (how many is the second value), sorted by flag and then by support,
/// most first.
fn keyframe_groups(
    keyframes: &[keyframes::Keyframe],
    fixed_axes: [bool; 3],
    probes: Option<&pose_distance::Probes>,
    min_support: usize,
    demonstrations: usize,
) -> (Vec<FoundGroup>, usize) {
    let mut found: Vec<FoundGroup> = Vec::new();
    // Rests are told apart by pose: the secondary's shape turned another way is another rest.
    let origin = pose_distance::Probes::origin();
    let probes = probes.unwrap_or(&origin);
    for g in [0u8, 1] {
        let slice: Vec<keyframes::Keyframe> =
            keyframes.iter().filter(|k| k.g == g).copied().collect();
        let placed: Vec<pose_distance::Placed> =
            slice.iter().map(|k| probes.placed(&k.pose, fixed_axes)).collect();
        let distance = |i: usize, j: usize| pose_distance::distance(&placed[i], &placed[j]);
        let sources: Vec<usize> = slice.iter().map(|k| k.demonstration).collect();
        for cluster in
            clusters::stable_clusters(slice.len(), distance, &sources, min_support, demonstrations)
        {
            let members = cluster.members.iter().map(|&i| slice[i]).collect();
            found.push((g, members, cluster.scale));
        }
    }
    let best = found.iter().map(|(_, members, _)| support(members)).max().unwrap_or(0);
    let before = found.len();
    found.retain(|(_, members, _)| support(members) as f64 >= MIN_RELATIVE_SUPPORT * best as f64);
    let dropped = before - found.len();
    found.sort_by_key(|(g, members, _)| (*g, std::cmp::Reverse(support(members))));
    (found, dropped)
}

/// A keyframe group: its held flag, its members and its scale.
type FoundGroup = (u8, Vec<keyframes::Keyframe>, f64);

/// How many demonstrations show a group's keyframes.
fn support(members: &[keyframes::Keyframe]) -> usize {
    members.iter().map(|k| k.demonstration).collect::<BTreeSet<_>>().len()
}

/// The position grid (half range, bins and margin per axis) that keeps every group's padded
/// interval whole, or what `pinned` says.
fn position_grid(
    pinned: &PinnedSettings,
    extents: &[([f64; 3], [f64; 3])],
    floors: &[f64],
    fixed_axes: [bool; 3],
) -> ([f64; 3], [usize; 3], [f64; 3]) {
    let mut half_range = [0.0; 3];
    let mut position_bins = [1; 3];
    let mut margins = [0.0; 3];
    for axis in 0..3 {
        let (intervals, bins): (Vec<(f64, f64)>, Option<usize>) = if fixed_axes[axis] {
            // One cell across every value the demonstrations show.
            (
                vec![padded_span(extents, floors, axis)],
                Some(pinned.position_bins.map_or(1, |bins| bins[axis])),
            )
        } else {
            let intervals = extents
                .iter()
                .zip(floors)
                .map(|((low, high), floor)| padded(low[axis], high[axis], *floor))
                .collect();
            (intervals, pinned.position_bins.map(|bins| bins[axis]))
        };
        let choice = grid_choice::choose_axis(
            &intervals,
            pinned.half_range.map(|range| range[axis]),
            bins,
            PLACEMENT_TOLERANCE,
        );
        half_range[axis] = choice.half_range;
        position_bins[axis] = choice.bins;
        margins[axis] = choice.margin;
    }
    (half_range, position_bins, margins)
}

/// The rotation bins, and the free turn where plain cells tell no rotation apart.
fn rotation_choice(
    found: &[FoundGroup],
    rotation_share: f64,
    round: Option<usize>,
) -> (usize, Option<FreeTurn>) {
    let rotations: Vec<Vec<(usize, crate::demo::Pose)>> = found
        .iter()
        .map(|(_, members, _)| members.iter().map(|k| (k.demonstration, k.pose)).collect())
        .collect();
    let most = PairSettings::DEFAULT.rotation_bins;
    let plain = grid_choice::choose_rotation_bins(&rotations, rotation_share, most, None, round);
    // A free turn only where plain cells tell no rotation apart: one bin per component
    // admits an object held on its side as well as upright. Where plain cells keep some
    // rotation (a can on a table at any yaw is a turn about one fixed axis, which a few
    // bins of one component hold), they stay: the region's mixture then splits a wide top
    // along the turn, which it cannot once the turn is taken out.
    let turn = if plain == 1 { free_turn_of(found) } else { None };
    match turn {
        Some(turn) => (
            grid_choice::choose_rotation_bins(&rotations, rotation_share, most, Some(turn), None),
            Some(turn),
        ),
        None => (plain, None),
    }
}

/// A group's interval `(low, high)` along an axis, padded by [`EXTENT_PADDING`] of its extent and at least
/// `floor`.
fn padded(low: f64, high: f64, floor: f64) -> (f64, f64) {
    let pad = (EXTENT_PADDING * (high - low)).max(floor);
    (low - pad, high + pad)
}

/// Every group's values along `axis` as one interval, padded by the largest of their floors: the one cell of
/// a fixed axis.
fn padded_span(extents: &[([f64; 3], [f64; 3])], floors: &[f64], axis: usize) -> (f64, f64) {
    let low = extents.iter().map(|(low, _)| low[axis]).fold(f64::INFINITY, f64::min);
    let high = extents.iter().map(|(_, high)| high[axis]).fold(f64::NEG_INFINITY, f64::max);
    let floor = floors.iter().copied().fold(PLACEMENT_TOLERANCE, f64::max);
    padded(low, high, floor)
}

/// One box per place: each group's keyframe extent, padded as for the grid, with boxes that overlap joined (they
/// are one place), in order of their lower corner. Along a fixed axis every box spans every group.
fn place_boxes(extents: &[([f64; 3], [f64; 3])], floors: &[f64], fixed: [bool; 3]) -> Vec<Bounds> {
    let span = [0, 1, 2].map(|axis| padded_span(extents, floors, axis));
    let mut boxes: Vec<Bounds> = extents
        .iter()
        .zip(floors)
        .map(|((low, high), floor)| {
            [0, 1, 2].map(|axis| {
                if fixed[axis] { span[axis] } else { padded(low[axis], high[axis], *floor) }
            })
        })
        .collect();
    let overlap = |a: &Bounds, b: &Bounds| {
        (0..3).all(|axis| a[axis].0 <= b[axis].1 && b[axis].0 <= a[axis].1)
    };
    loop {
        let pair = (0..boxes.len())
            .flat_map(|i| (i + 1..boxes.len()).map(move |j| (i, j)))
            .find(|&(i, j)| overlap(&boxes[i], &boxes[j]));
        let Some((i, j)) = pair else { break };
        let joined = boxes.remove(j);
        for axis in 0..3 {
            boxes[i][axis] =
                (boxes[i][axis].0.min(joined[axis].0), boxes[i][axis].1.max(joined[axis].1));
        }
    }
    boxes.sort_by(|a, b| {
        let corner = |bounds: &Bounds| bounds.map(|(low, _)| low);
        corner(a).partial_cmp(&corner(b)).unwrap_or(std::cmp::Ordering::Equal)
    });
    boxes
}

/// Per axis, the least margin of a group from its box's edges, as a share of the box.
fn box_margins(boxes: &[Bounds], extents: &[([f64; 3], [f64; 3])]) -> [f64; 3] {
    let mut margins = [f64::INFINITY; 3];
    for (low, high) in extents {
        let inside = boxes.iter().find(|bounds| {
            (0..3).all(|axis| bounds[axis].0 <= low[axis] && high[axis] <= bounds[axis].1)
        });
        let Some(bounds) = inside else { continue };
        for axis in 0..3 {
            let width = (bounds[axis].1 - bounds[axis].0).max(f64::MIN_POSITIVE);
            let margin = (low[axis] - bounds[axis].0).min(bounds[axis].1 - high[axis]) / width;
            margins[axis] = margins[axis].min(margin);
        }
    }
    margins.map(|margin| if margin.is_finite() { margin } else { 0.0 })
}

/// The turn the groups leave free, if any, measured from the first keyframe of the
/// best-supported group (ties: the earlier group).
fn free_turn_of(found: &[FoundGroup]) -> Option<FreeTurn> {
    let best = (0..found.len()).max_by_key(|&i| (support(&found[i].1), std::cmp::Reverse(i)));
    let order = best.into_iter().chain((0..found.len()).filter(|i| Some(*i) != best));
    let groups: Vec<free_turn::GroupRotations> = order
        .map(|i| free_turn::GroupRotations {
            rotations: found[i].1.iter().map(|k| k.pose.rotation).collect(),
            draws: support(&found[i].1),
        })
        .collect();
    free_turn::free_turn(&groups)
}

fn bounds(members: &[keyframes::Keyframe]) -> ([f64; 3], [f64; 3]) {
    let mut low = [f64::INFINITY; 3];
    let mut high = [f64::NEG_INFINITY; 3];
    for k in members {
        for axis in 0..3 {
            low[axis] = low[axis].min(k.pose.translation.vector[axis]);
            high[axis] = high[axis].max(k.pose.translation.vector[axis]);
        }
    }
    (low, high)
}

fn centre(members: &[keyframes::Keyframe]) -> [f64; 3] {
    let mut sum = [0.0; 3];
    for k in members {
        for (axis, total) in sum.iter_mut().enumerate() {
            *total += k.pose.translation.vector[axis];
        }
    }
    sum.map(|total| total / members.len().max(1) as f64)
}

/// Per group: the largest share of the demonstrations that visit, at any step, one of the cells its keyframes
/// fall in (in its held flag); and all those cells.
fn best_cell_shares(
    grid: &Grid,
    groups: &[(u8, Vec<keyframes::Keyframe>, f64)],
    tracks: &[Track],
    demonstrations: usize,
) -> (Vec<f64>, BTreeMap<FlaggedCell, usize>) {
    let group_cells: Vec<BTreeSet<(u8, [usize; 3])>> = groups
        .iter()
        .map(|(g, members, _)| {
            members.iter().filter_map(|k| grid.voxel(&k.pose).map(|voxel| (*g, voxel))).collect()
        })
        .collect();
    let wanted = places(&group_cells);
    let mut visitors: BTreeMap<(u8, [usize; 3]), BTreeSet<usize>> = BTreeMap::new();
    for track in tracks {
        for frame in &track.frames {
            if let Some(voxel) = grid.voxel(&frame.pose)
                && wanted.contains_key(&(frame.g, voxel))
            {
                visitors.entry((frame.g, voxel)).or_default().insert(track.demonstration);
            }
        }
    }
    let total = demonstrations.max(1) as f64;
    let shares = group_cells
        .iter()
        .map(|cells| {
            cells.iter().map(|cell| visitors.get(cell).map_or(0, BTreeSet::len)).max().unwrap_or(0)
                as f64
                / total
        })
        .collect();
    (shares, wanted)
}

/// How many places the labelled cells make.
fn place_count(cells: &BTreeMap<FlaggedCell, usize>) -> usize {
    cells.values().collect::<BTreeSet<_>>().len()
}

/// Every group's cells, labelled with their place: groups that share a cell are one place, named by the
/// first of them.
fn places(group_cells: &[BTreeSet<FlaggedCell>]) -> BTreeMap<FlaggedCell, usize> {
    let mut place: Vec<usize> = (0..group_cells.len()).collect();
    fn root(place: &mut [usize], mut group: usize) -> usize {
        while place[group] != group {
            place[group] = place[place[group]];
            group = place[group];
        }
        group
    }
    let mut owner: BTreeMap<FlaggedCell, usize> = BTreeMap::new();
    for (group, cells) in group_cells.iter().enumerate() {
        for cell in cells {
            if let Some(&other) = owner.get(cell) {
                let (a, b) = (root(&mut place, other), root(&mut place, group));
                place[a.max(b)] = a.min(b);
            } else {
                owner.insert(*cell, group);
            }
        }
    }
    owner.into_iter().map(|(cell, group)| (cell, root(&mut place, group))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::Pose;

    #[test]
    fn a_base_standing_at_tables_of_two_heights_stands_at_one_place() {
        // A surface's top, seen from a base that drives up to it and stops 0.9 m ahead of it: at a table
        // (0.73 m) in two demonstrations of three, at a counter (0.90 m) in the third.
        let tracks: Vec<Track> = (0..30)
            .map(|demonstration| {
                let height = if demonstration % 3 == 2 { 0.90 } else { 0.73 };
                let side = 0.0001 * (demonstration % 7) as f64;
                let mut frames: Vec<TrackFrame> = (0..20)
                    .map(|step| 3.0 - 0.1 * step as f64)
                    .chain(std::iter::repeat_n(0.9, 10))
                    .map(|x| TrackFrame {
                        g: 0,
                        pose: Pose::translation(x, side, height),
                        contact: false,
                        paused: false,
                    })
                    .collect();
                frames.extend((1..=10).map(|step| TrackFrame {
                    g: 0,
                    pose: Pose::translation(0.9, side + 0.1 * step as f64, height),
                    contact: false,
                    paused: false,
                }));
                Track { demonstration, primary: 0, secondary: 1, frames }
            })
            .collect();
        let selection =
            select(&PinnedSettings::default(), &tracks, 30, 3, 0.1, 0.005, ShapeFacts::default());
        assert_eq!(selection.fixed_axes, [false, false, true]);
        assert_eq!(selection.groups.len(), 1, "{:?}", selection.groups);
        assert_eq!(selection.groups[0].demonstrations, 30);
        assert_eq!(selection.settings.position_bins[2], 1);
        let grid = Grid::new(&selection.settings);
        let at = |height: f64| grid.voxel(&Pose::translation(0.9, 0.0003, height));
        assert!(at(0.73).is_some() && at(0.73) == at(0.90), "{:?}", selection.settings);
    }

    #[test]
    fn places_that_no_uniform_grid_keeps_apart_get_boxes_of_their_own() {
        // A plank comes to rest 8 mm above (A) or below (B) another's middle, or anywhere within 5 mm of its
        // height 5 cm along it (C). C's heights overlap both A's and B's, so every uniform grid that keeps C
        // whole puts A and B in one cell.
        let rest = |demonstration: usize| match demonstration % 3 {
            0 => (0.0, 0.008),
            1 => (0.0, -0.008),
            _ => (0.05, -0.005 + 0.001 * (demonstration / 3) as f64),
        };
        let tracks: Vec<Track> = (0..33)
            .map(|demonstration| {
                let (x, z) = rest(demonstration);
                let frames = (0..20)
                    .map(|step| 0.2 - 0.01 * step as f64)
                    .chain(std::iter::repeat_n(0.0, 10))
                    .map(|above| TrackFrame {
                        g: 0,
                        pose: Pose::translation(x + above, above, z + above),
                        contact: false,
                        paused: false,
                    })
                    .collect();
                Track { demonstration, primary: 0, secondary: 1, frames }
            })
            .collect();
        let selection =
            select(&PinnedSettings::default(), &tracks, 33, 3, 0.1, 0.005, ShapeFacts::default());
        assert_eq!(selection.groups.len(), 3, "{:?}", selection.groups);
        assert_eq!(selection.boxes.len(), 3, "{:?}", selection.boxes);
        let places: BTreeSet<usize> = selection.cells.values().copied().collect();
        assert_eq!(places.len(), 3, "{:?}", selection.cells);
        // Each rest falls in its own box, and a pose between A and B in none.
        let grid = selection.grid();
        let voxel = |x: f64, z: f64| grid.voxel(&Pose::translation(x, 0.0, z));
        let (a, b, c) = (voxel(0.0, 0.008), voxel(0.0, -0.008), voxel(0.05, 0.0));
        assert!(a.is_some() && b.is_some() && c.is_some());
        assert!(a != b && b != c && a != c);
        assert_eq!(voxel(0.0, 0.0), None);
        // Pinned bins keep the uniform grid.
        let pinned = PinnedSettings {
            position_bins: Some([5, 5, 5]),
            half_range: Some([0.1, 0.1, 0.1]),
            ..PinnedSettings::default()
        };
        assert!(
            select(&pinned, &tracks, 33, 3, 0.1, 0.005, ShapeFacts::default()).boxes.is_empty()
        );
    }

    #[test]
    fn two_movable_objects_relate_only_where_they_touch() {
        // A block comes down onto another (3 cm above its centre) in half the demonstrations, and is set down
        // 10 cm beside it, not touching, in the other half.
        let tracks: Vec<Track> = (0..30)
            .map(|demonstration| {
                let side = 0.0001 * (demonstration % 7) as f64;
                let (x, z) = if demonstration % 2 == 0 { (side, 0.03) } else { (0.10 + side, 0.0) };
                let frames = (0..20)
                    .map(|step| z + 0.2 - 0.01 * step as f64)
                    .chain(std::iter::repeat_n(z, 10))
                    .map(|height| TrackFrame {
                        g: 0,
                        pose: Pose::translation(x, 0.0, height.max(z)),
                        contact: false,
                        paused: false,
                    })
                    .collect();
                Track { demonstration, primary: 0, secondary: 1, frames }
            })
            .collect();
        let anywhere =
            select(&PinnedSettings::default(), &tracks, 30, 3, 0.1, 0.005, ShapeFacts::default());
        assert_eq!(anywhere.groups.len(), 2, "{:?}", anywhere.groups);
        assert_eq!(anywhere.apart, None);
        // Blocks 5 cm wide touch when their centres are less than a width apart sideways.
        let touching = |pose: &Pose| pose.translation.vector.x.abs() < 0.05;
        let by_contact = select(
            &PinnedSettings::default(),
            &tracks,
            30,
            3,
            0.1,
            0.005,
            ShapeFacts { contact: Some(&touching), round: None, probes: None },
        );
        assert_eq!(by_contact.groups.len(), 1, "{:?}", by_contact.groups);
        assert!(by_contact.groups[0].centre[2] > 0.02, "{:?}", by_contact.groups);
        assert!(by_contact.apart.is_some_and(|apart| apart > 0));
        assert_eq!(by_contact.keyframes + by_contact.apart.unwrap_or(0), anywhere.keyframes);
    }

    #[test]
    fn rests_turned_apart_are_two_groups_though_their_positions_are_close() {
        // A plank comes to rest standing on its end by another, its face one way in half the demonstrations and
        // the other way in the rest, its origin 2 mm along from where it is in the other rest.
        let half_pi = std::f64::consts::FRAC_PI_2;
        let tracks: Vec<Track> = (0..30)
            .map(|demonstration| {
                let jitter = 0.0001 * (demonstration % 5) as f64;
                let (x, pitch) =
                    if demonstration % 2 == 0 { (0.060, half_pi) } else { (0.062, -half_pi) };
                let rest = Pose::from_parts(
                    nalgebra::Translation3::new(x + jitter, 0.0, -0.035),
                    nalgebra::UnitQuaternion::from_euler_angles(0.0, pitch, 0.0),
                );
                let frames = (0..20)
                    .map(|step| 0.2 - 0.01 * step as f64)
                    .chain(std::iter::repeat_n(0.0, 10))
                    .map(|above| {
                        let mut pose = rest;
                        pose.translation.vector.z += above;
                        TrackFrame { g: 0, pose, contact: false, paused: false }
                    })
                    .collect();
                Track { demonstration, primary: 0, secondary: 1, frames }
            })
            .collect();
        let by_position =
            select(&PinnedSettings::default(), &tracks, 30, 3, 0.1, 0.005, ShapeFacts::default());
        assert_eq!(by_position.groups.len(), 1, "{:?}", by_position.groups);
        let plank = pose_distance::Probes::of_box(
            [-0.0585, -0.0115, 0.0],
            [0.0585, 0.0115, 0.007],
            None,
            &[],
        );
        let shape = ShapeFacts { probes: Some(&plank), ..ShapeFacts::default() };
        let by_pose = select(&PinnedSettings::default(), &tracks, 30, 3, 0.1, 0.005, shape);
        assert_eq!(by_pose.groups.len(), 2, "{:?}", by_pose.groups);
        assert!(
            by_pose.groups.iter().all(|group| group.demonstrations == 15),
            "{:?}",
            by_pose.groups
        );
        let sides: Vec<f64> = by_pose.groups.iter().map(|group| group.centre[0]).collect();
        assert!((sides[0] - sides[1]).abs() > 0.0015, "{sides:?}");
    }
}
