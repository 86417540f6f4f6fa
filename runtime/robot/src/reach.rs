//! A ball that holds every position a link can reach when only one joint group moves: the cheap
//! test that spares inverse kinematics its restarts on targets no configuration can reach.
//!
//! Along the chain from the root to the link, every joint above the first one the group moves
//! keeps its pose, so the origin of that joint's frame stays where it is. Below it, a revolute
//! joint turns its child about an axis through its own origin and changes no distance from it; a
//! prismatic joint moves its child by at most its largest travel; a fixed offset adds its length.
//! The link's origin is therefore never farther from that origin than the sum of the offsets and
//! the travels below it (the triangle inequality, link by link).

use lamp_geometry::Vec3;

use crate::kinematics::joint_motion;
use crate::mount::Mount;
use crate::robot::{JointGroup, LinkId, Motion, Robot};

impl Robot {
    /// The centre and radius of a ball holding every position of `link`'s origin over all
    /// configurations that differ from `q` only in `group`'s coordinates; `None` when the group
    /// moves the mount or a planar or floating joint on the chain (the reach is unbounded).
    pub fn reach_ball(&self, group: &JointGroup, link: LinkId, q: &[f64]) -> Option<(Vec3, f64)> {
        self.reach_ball_of_chain(group, &self.chain(link), q)
    }

    /// [`Robot::reach_ball`] of the last link of `chain`, the links from the root to it as
    /// [`Robot::chain`] lists them.
    pub(crate) fn reach_ball_of_chain(
        &self,
        group: &JointGroup,
        chain: &[LinkId],
        q: &[f64],
    ) -> Option<(Vec3, f64)> {
        let moves = |first: usize, count: usize| {
            (first..first + count).any(|index| group.coordinates.binary_search(&index).is_ok())
        };
        if !matches!(self.mount, Mount::Fixed(_)) && moves(0, self.mount.coordinate_count()) {
            return None;
        }
        let first_moving = chain.iter().position(|&id| {
            self.links[id]
                .joint
                .as_ref()
                .is_some_and(|joint| moves(joint.first_coordinate, joint.coordinate_count()))
        })?;
        let first_link = chain[first_moving];
        let parent = self.links[first_link].parent?;
        let joint = self.links[first_link].joint.as_ref()?;
        let centre = (self.link_pose(q, parent) * joint.origin).translation.vector;
        let mut radius = 0.0;
        for &id in &chain[first_moving..] {
            let Some(joint) = &self.links[id].joint else { continue };
            if id != first_link {
                radius += joint.origin.translation.vector.norm();
            }
            let in_group = moves(joint.first_coordinate, joint.coordinate_count());
            radius += match (&joint.motion, in_group) {
                (Motion::Fixed | Motion::Revolute { .. }, _) => 0.0,
                (Motion::Prismatic { .. }, true) => {
                    let coordinate = &self.coordinates[joint.first_coordinate];
                    coordinate.lower.abs().max(coordinate.upper.abs())
                }
                (Motion::Planar { .. } | Motion::Floating, true) => return None,
                (_, false) => joint_motion(&joint.motion, &q[joint.first_coordinate..])
                    .translation
                    .vector
                    .norm(),
            };
        }
        radius.is_finite().then_some((centre, radius))
    }
}
