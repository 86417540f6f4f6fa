//! Clusters of keyframes that stay the same over a range of scales, by the distance of their positions or of
//! their poses ([`super::pose_distance`]).
//!
//! Single-linkage clustering at scales from [`FINEST_SCALE`] up, doubling [`SCALES`] times. A cluster found at
//! one scale is kept when, two doublings coarser (a fourfold scale change), it has gained at most
//! [`STABLE_GROWTH`] more keyframes: it is separated from everything else by a gap four times wider than the
//! links inside it. Scales are tried from fine to coarse and a keyframe joins at most one cluster, so the
//! tightest separated groups are found first. A cluster needs keyframes from at least the minimum support of
//! demonstrations, and keeps the few keyframes it gains up to the coarse scale: they are the sparse edge of the
//! same place. A coarser stable cluster replaces the clusters found inside it when together they are seen in
//! less than [`MIN_RELATIVE_SUPPORT`] of its demonstrations: three demonstrations that happened to stop within a
//! millimetre of each other inside a place that eighty stop in are not a place of their own, but ten tight
//! groups seen in most of the demonstrations of a cloud around them are ten places.
//!
//! Fewer demonstrations spread a group's keyframes further apart, so a second pass over the keyframes left
//! asks for one doubling only, from a group seen in at least [`COMMON_SHARE`] of the demonstrations: common
//! enough not to be chance, though closer to its neighbours.

use std::collections::BTreeSet;

/// The finest scale (m): a millimetre, below what a robot's placements repeat to.
pub const FINEST_SCALE: f64 = 0.001;
/// Scales tried: 1 mm to 128 mm.
pub const SCALES: usize = 8;
/// Scales tried beyond [`SCALES`] when no cluster formed up to them: 256 mm and 512 mm. A table top
/// that forty demonstrations set cans down on anywhere holds them some 12 cm apart, one place only
/// at these; tried first, they joined the can in a box with the table around it (Packing, 100).
pub const WIDE_SCALES: usize = 2;
/// Doublings between a scale and the scale its cluster must survive to.
pub const STABLE_DOUBLINGS: u32 = 2;
/// The share of keyframes a cluster may gain over a fourfold coarsening and still be the same cluster.
pub const STABLE_GROWTH: f64 = 0.1;
/// The share of the demonstrations a group needs to be kept when it is stable over one doubling only.
pub const COMMON_SHARE: f64 = 0.1;
/// A group seen in fewer than this share of the demonstrations of the pair's best-supported group is an
/// incidental rest, not a region.
pub const MIN_RELATIVE_SUPPORT: f64 = 0.2;

/// A cluster: the indices of its points, sorted, and the scale it was found at.
#[derive(Debug, Clone, PartialEq)]
pub struct Cluster {
    /// Indices into the clustered points.
    pub members: Vec<usize>,
    /// The scale (m) at which it separated.
    pub scale: f64,
}

/// The stable clusters of `n` points apart by `distance` (m, a metric); `demonstration[i]` says which of the
/// pair's `demonstrations` point `i` came from.
pub fn stable_clusters(
    n: usize,
    distance: impl Fn(usize, usize) -> f64,
    demonstration: &[usize],
    min_support: usize,
    demonstrations: usize,
) -> Vec<Cluster> {
    if n < min_support.max(2) {
        return Vec::new();
    }
    let tree = minimum_spanning_tree(n, distance);
    let labels: Vec<Vec<usize>> = (0..SCALES + WIDE_SCALES + STABLE_DOUBLINGS as usize)
        .map(|rung| components(n, &tree, scale(rung)))
        .collect();
    let mut taken = vec![false; n];
    let mut found = Vec::new();
    let common = (COMMON_SHARE * demonstrations as f64).ceil() as usize;
    for (doublings, support_needed) in
        [(STABLE_DOUBLINGS as usize, min_support), (1, min_support.max(common))]
    {
        let rungs = 0..SCALES;
        take_stable(
            &labels,
            rungs,
            doublings,
            support_needed,
            demonstration,
            &mut taken,
            &mut found,
        );
    }
    if found.is_empty() {
        let (rungs, doublings) = (SCALES..SCALES + WIDE_SCALES, STABLE_DOUBLINGS as usize);
        take_stable(&labels, rungs, doublings, min_support, demonstration, &mut taken, &mut found);
    }
    found
}

/// Takes, from fine to coarse, the clusters of keyframes not yet taken that stay the same `doublings` coarser.
fn take_stable(
    labels: &[Vec<usize>],
    rungs: std::ops::Range<usize>,
    doublings: usize,
    min_support: usize,
    demonstration: &[usize],
    taken: &mut [bool],
    found: &mut Vec<Cluster>,
) {
    let n = taken.len();
    for rung in rungs {
        let fine = &labels[rung];
        let coarse = &labels[rung + doublings];
        let roots: BTreeSet<usize> = (0..n).filter(|&i| !taken[i]).map(|i| fine[i]).collect();
        for root in roots {
            let members: Vec<usize> = (0..n).filter(|&i| fine[i] == root).collect();
            let support = support_of(&members, demonstration);
            if support < min_support {
                continue;
            }
            let grown = coarse.iter().filter(|&&label| label == coarse[members[0]]).count();
            if grown as f64 > (1.0 + STABLE_GROWTH) * members.len() as f64 {
                continue;
            }
            if members.iter().any(|&i| taken[i]) {
                // Clusters found inside this one are incidental when it is common enough beside them.
                let Some(inside) = incidental_inside(&members, support, demonstration, found)
                else {
                    continue;
                };
                for index in inside.into_iter().rev() {
                    found.remove(index);
                }
            }
            // The cluster is what stays together up to the coarse scale: the few keyframes it gains there are the
            // sparse edge of the same place (a base stopping a little further aside), not a place of their own.
            let label = coarse[members[0]];
            let mut members = members;
            members.extend((0..n).filter(|&i| coarse[i] == label && fine[i] != root && !taken[i]));
            members.sort_unstable();
            for &i in &members {
                taken[i] = true;
            }
            found.push(Cluster { members, scale: scale(rung) });
        }
    }
}

fn support_of(members: &[usize], demonstration: &[usize]) -> usize {
    members.iter().map(|&i| demonstration[i]).collect::<BTreeSet<_>>().len()
}

/// The indices in `found` of the clusters that `members` (with `support` demonstrations) contains, if every
/// cluster it meets lies wholly inside it and all of them together are seen in less than
/// [`MIN_RELATIVE_SUPPORT`] of its support: a few demonstrations that stopped closer together within a common
/// place do not make a place of their own. Taken together, because many tight groups that between them hold
/// most of a wide cloud (blocks placed across one another, among blocks lying anywhere on a table) are the
/// places, and the cloud around them is the incidental part.
fn incidental_inside(
    members: &[usize],
    support: usize,
    demonstration: &[usize],
    found: &[Cluster],
) -> Option<Vec<usize>> {
    let inside: BTreeSet<usize> = members.iter().copied().collect();
    let mut contained = Vec::new();
    let mut held = Vec::new();
    for (index, cluster) in found.iter().enumerate() {
        let meets = cluster.members.iter().filter(|i| inside.contains(i)).count();
        if meets == 0 {
            continue;
        }
        if meets < cluster.members.len() {
            return None;
        }
        contained.push(index);
        held.extend_from_slice(&cluster.members);
    }
    let incidental =
        (support_of(&held, demonstration) as f64) < MIN_RELATIVE_SUPPORT * support as f64;
    incidental.then_some(contained)
}

fn scale(rung: usize) -> f64 {
    FINEST_SCALE * f64::from(1u32 << rung)
}

/// The edges `(a, b, length)` of a minimum spanning tree of `n` points under `distance`, by Prim's algorithm
/// (quadratic, no index).
fn minimum_spanning_tree(
    n: usize,
    distance: impl Fn(usize, usize) -> f64,
) -> Vec<(usize, usize, f64)> {
    let mut in_tree = vec![false; n];
    let mut best = vec![(f64::INFINITY, 0usize); n];
    let mut edges = Vec::with_capacity(n.saturating_sub(1));
    let mut current = 0;
    in_tree[0] = true;
    for _ in 1..n {
        let mut next = None;
        for i in 0..n {
            if in_tree[i] {
                continue;
            }
            let d = distance(current, i);
            if d < best[i].0 {
                best[i] = (d, current);
            }
            if next.is_none_or(|j: usize| best[i].0 < best[j].0) {
                next = Some(i);
            }
        }
        let Some(chosen) = next else { break };
        in_tree[chosen] = true;
        edges.push((best[chosen].1, chosen, best[chosen].0));
        current = chosen;
    }
    edges
}

/// Component labels (the smallest member index) of the tree's edges no longer than `scale`.
fn components(n: usize, tree: &[(usize, usize, f64)], scale: f64) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for &(a, b, length) in tree {
        if length <= scale {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            let (low, high) = (ra.min(rb), ra.max(rb));
            parent[high] = low;
        }
    }
    (0..n).map(|i| root(&mut parent, i)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn euclidean(points: &[[f64; 3]]) -> impl Fn(usize, usize) -> f64 + '_ {
        |i, j| (0..3).map(|axis| (points[i][axis] - points[j][axis]).powi(2)).sum::<f64>().sqrt()
    }

    /// The stable clusters of `points` by the distance of their positions.
    fn clusters_of(
        points: &[[f64; 3]],
        demonstration: &[usize],
        min_support: usize,
        demonstrations: usize,
    ) -> Vec<Cluster> {
        stable_clusters(points.len(), euclidean(points), demonstration, min_support, demonstrations)
    }

    #[test]
    fn cans_set_down_anywhere_on_a_table_top_by_few_demonstrations_are_one_place() {
        // Forty demonstrations set a can down somewhere on a 0.7 m square top: some 12 cm apart,
        // so no cluster forms up to 128 mm, and only a quarter metre or more links them.
        let mut points = Vec::new();
        for d in 0..36 {
            let (row, column) = ((d / 6) as f64, (d % 6) as f64);
            let jitter = 0.01 * ((d * 7 % 5) as f64 - 2.0);
            points.push([-0.35 + 0.13 * column + jitter, -0.35 + 0.12 * row - jitter, 0.001]);
        }
        let demos: Vec<usize> = (0..36).collect();
        let found = clusters_of(&points, &demos, 3, 40);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].members.len(), 36);
        assert!(found[0].scale > 0.128, "{}", found[0].scale);
        // With a tight group among them, the wide scales are not tried: the group is the place.
        let mut with_group = points.clone();
        let mut group_demos = demos.clone();
        for d in 0..10 {
            with_group.push([0.5 + 1e-4 * d as f64, 0.5, 0.001]);
            group_demos.push(d);
        }
        let found = clusters_of(&with_group, &group_demos, 3, 40);
        assert!(found.iter().all(|cluster| cluster.scale <= 0.128), "{found:?}");
    }

    #[test]
    fn two_tight_groups_far_apart_are_two_clusters() {
        let mut points = Vec::new();
        let mut demos = Vec::new();
        for d in 0..10 {
            let jitter = d as f64 * 1e-4;
            points.push([jitter, 0.0, 0.0]);
            points.push([0.3 + jitter, 0.0, 0.0]);
            demos.extend([d, d]);
        }
        let found = clusters_of(&points, &demos, 3, 100);
        assert_eq!(found.len(), 2);
        assert_eq!(found[0].members, (0..20).step_by(2).collect::<Vec<_>>());
        assert_eq!(found[0].scale, FINEST_SCALE);
    }

    #[test]
    fn a_group_is_kept_only_at_a_scale_where_it_stops_growing() {
        // Ten keyframes within half a millimetre and a trail of four at 2.5 mm spacing beside them: at 1 and
        // 2 mm the group would still gain the trail four times coarser, so it is taken at 4 mm, trail and all.
        let mut points: Vec<[f64; 3]> = (0..10).map(|i| [i as f64 * 5e-5, 0.0, 0.0]).collect();
        points.extend((1..=4).map(|i| [i as f64 * 0.0025, 0.0, 0.0]));
        let demos: Vec<usize> = (0..14).collect();
        let found = clusters_of(&points, &demos, 3, 100);
        assert_eq!(found.len(), 1);
        assert_eq!((found[0].members.len(), found[0].scale), (14, 0.004));
    }

    #[test]
    fn a_few_close_keyframes_inside_a_common_place_do_not_hide_it() {
        // Forty keyframes 3 cm apart along a line (a base stopping anywhere along a table's edge), and three
        // within 0.1 mm of one another 2 cm beyond its end: a cluster at 1 mm that stays the same at 4 mm.
        let mut points: Vec<[f64; 3]> = (0..40).map(|i| [i as f64 * 0.03, 0.0, 0.0]).collect();
        points.extend((0..3).map(|i| [-0.02 + i as f64 * 5e-5, 0.0, 0.0]));
        let demos: Vec<usize> = (0..43).collect();
        let found = clusters_of(&points, &demos, 3, 43);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!((found[0].members.len(), found[0].scale), (43, 0.032));
    }

    #[test]
    fn tight_groups_that_hold_much_of_a_wide_cloud_are_places_and_the_cloud_is_not() {
        // Sixty rests 10 cm apart on a plane (blocks lying anywhere on a table, one per demonstration), and four
        // groups of eight within half a millimetre, each at the middle of a square of the cloud: each group is
        // seen in 8 of the cloud's 60 demonstrations, under a fifth, but together in 32 of them.
        let mut points: Vec<[f64; 3]> =
            (0..60).map(|i| [(i % 6) as f64 * 0.1, (i / 6) as f64 * 0.1, 0.0]).collect();
        let mut demos: Vec<usize> = (0..60).collect();
        for group in 0..4 {
            let centre = [0.05 + group as f64 * 0.1, 0.05, 0.0];
            for k in 0..8 {
                points.push([centre[0] + k as f64 * 5e-5, centre[1], centre[2]]);
                demos.push(group * 8 + k);
            }
        }
        let found = clusters_of(&points, &demos, 3, 60);
        let groups: Vec<(usize, f64)> = found.iter().map(|c| (c.members.len(), c.scale)).collect();
        assert_eq!(groups, [(8, FINEST_SCALE); 4]);
        assert!(found.iter().all(|c| c.members.iter().all(|&i| i >= 60)), "{found:?}");
    }

    #[test]
    fn a_cluster_keeps_the_sparse_edge_it_gains_up_to_the_coarse_scale() {
        // Forty stops 2 cm apart, then two stragglers 5 cm apart beyond the last: at 32 mm the forty are one
        // cluster, and at 128 mm it has gained only the two, which are the edge of the same place.
        let mut points: Vec<[f64; 3]> = (0..40).map(|i| [i as f64 * 0.02, 0.0, 0.0]).collect();
        points.extend([[0.83, 0.0, 0.0], [0.88, 0.0, 0.0]]);
        let demos: Vec<usize> = (0..42).collect();
        let found = clusters_of(&points, &demos, 3, 42);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!((found[0].members.len(), found[0].scale), (42, 0.032));
    }

    #[test]
    fn a_group_from_too_few_demonstrations_is_no_cluster() {
        let points = vec![[0.0; 3], [0.0001, 0.0, 0.0], [0.0002, 0.0, 0.0]];
        assert!(clusters_of(&points, &[0, 0, 1], 3, 3).is_empty());
        assert_eq!(clusters_of(&points, &[0, 1, 2], 3, 3).len(), 1);
    }

    #[test]
    fn the_tree_joins_every_point_with_the_shortest_links() {
        let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [1.0, 0.5, 0.0]];
        let tree = minimum_spanning_tree(points.len(), euclidean(&points));
        let total: f64 = tree.iter().map(|e| e.2).sum();
        assert!((total - (1.0 + 0.5 + (1.0f64 + 1.5 * 1.5).sqrt())).abs() < 1e-12, "{tree:?}");
        assert_eq!(components(4, &tree, 0.6), [0, 1, 2, 1]);
    }
}
