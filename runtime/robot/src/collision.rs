//! Self-collision pairs: which link pairs the world must check against each other.
//!
//! Links joined by fixed joints move as one rigid body, so they are collapsed into one "rigid group"
//! first; two links are adjacent when they are in the same rigid group or their rigid groups are
//! joined by a single moving joint. Adjacent links touch by construction and are never checked.

use crate::robot::{LinkId, Motion, Robot};

/// The rigid group of each link: the id of the topmost link reached through fixed joints only.
pub(crate) fn rigid_groups(robot: &Robot) -> Vec<LinkId> {
    let mut group: Vec<LinkId> = (0..robot.links.len()).collect();
    // Parents precede children, so one forward pass suffices.
    for id in 0..robot.links.len() {
        let link = &robot.links[id];
        if let (Some(parent), Some(joint)) = (link.parent, &link.joint)
            && joint.motion == Motion::Fixed
        {
            group[id] = group[parent];
        }
    }
    group
}

/// Whether two links never need a collision check because they are rigidly or directly joined.
pub(crate) fn adjacent(robot: &Robot, groups: &[LinkId], a: LinkId, b: LinkId) -> bool {
    let (group_a, group_b) = (groups[a], groups[b]);
    if group_a == group_b {
        return true;
    }
    let parent_group = |group: LinkId| robot.links[group].parent.map(|parent| groups[parent]);
    parent_group(group_a) == Some(group_b) || parent_group(group_b) == Some(group_a)
}

/// All pairs of links with geometry that are not adjacent, lower id first, sorted.
pub(crate) fn compute_self_collision_pairs(robot: &Robot) -> Vec<(LinkId, LinkId)> {
    let groups = rigid_groups(robot);
    let mut with_geometry: Vec<LinkId> =
        robot.geometry.iter().map(|geometry| geometry.link).collect();
    with_geometry.sort_unstable();
    with_geometry.dedup();
    let mut pairs = Vec::new();
    for (index, &a) in with_geometry.iter().enumerate() {
        for &b in &with_geometry[index + 1..] {
            if !adjacent(robot, &groups, a, b) {
                pairs.push((a, b));
            }
        }
    }
    pairs
}
