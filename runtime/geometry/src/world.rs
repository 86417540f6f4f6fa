//! A set of placed bodies with a broad phase: the scene side of every collision query.
//!
//! Bodies keep their world bounding box; a query first compares boxes and runs the exact test
//! only on overlapping ones. Scenes here hold tens of bodies, where a linear pass over cached
//! boxes beats maintaining a tree (it is a few dozen comparisons of six numbers). Many shapes
//! that stand together (a robot's links) pass over the world once, for the bodies near all of
//! them ([`CollisionWorld::bodies_near`]), and each then looks only among those.

use crate::collision::{Aabb, CollisionShape, penetration_depth, within_margin};
use crate::math::{Point3, Pose, Real};
use crate::support::{ContactPoint, contact_points, drop_distance};

/// A body's index in its [`CollisionWorld`], in insertion order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct BodyId(pub usize);

#[derive(Clone, Debug)]
struct Entry {
    /// `None` for a marker: a named pose that takes part in no query.
    shape: Option<CollisionShape>,
    pose: Pose,
    aabb: Aabb,
    enabled: bool,
}

/// Placed bodies that can be moved, disabled (a held object) and queried.
#[derive(Clone, Debug, Default)]
pub struct CollisionWorld {
    entries: Vec<Entry>,
}

impl CollisionWorld {
    /// An empty world.
    pub fn new() -> CollisionWorld {
        CollisionWorld::default()
    }

    /// Adds a body at `pose`.
    pub fn insert(&mut self, shape: CollisionShape, pose: Pose) -> BodyId {
        let aabb = shape.aabb(&pose);
        self.entries.push(Entry { shape: Some(shape), pose, aabb, enabled: true });
        BodyId(self.entries.len() - 1)
    }

    /// Adds a marker at `pose`: it keeps an id and a pose, so that ids stay the scene's body
    /// indices, but no query ever meets it.
    pub fn insert_marker(&mut self, pose: Pose) -> BodyId {
        let aabb = point_box(&pose);
        self.entries.push(Entry { shape: None, pose, aabb, enabled: true });
        BodyId(self.entries.len() - 1)
    }

    /// How many bodies there are (enabled or not).
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether there are no bodies.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Moves a body.
    pub fn set_pose(&mut self, id: BodyId, pose: Pose) {
        if let Some(entry) = self.entries.get_mut(id.0) {
            entry.aabb = match &entry.shape {
                Some(shape) => shape.aabb(&pose),
                None => point_box(&pose),
            };
            entry.pose = pose;
        }
    }

    /// The pose of a body.
    pub fn pose(&self, id: BodyId) -> Option<&Pose> {
        self.entries.get(id.0).map(|entry| &entry.pose)
    }

    /// The shape of a body (`None` for a marker).
    pub fn shape(&self, id: BodyId) -> Option<&CollisionShape> {
        self.entries.get(id.0).and_then(|entry| entry.shape.as_ref())
    }

    /// Includes or excludes a body from queries (a held object is checked as part of the robot).
    pub fn set_enabled(&mut self, id: BodyId, enabled: bool) {
        if let Some(entry) = self.entries.get_mut(id.0) {
            entry.enabled = enabled;
        }
    }

    /// The first enabled body (in id order) closer than `margin` to `shape` at `pose`, skipping
    /// those `skip` says to.
    pub fn first_contact(
        &self,
        shape: &CollisionShape,
        pose: &Pose,
        margin: Real,
        skip: impl Fn(BodyId) -> bool,
    ) -> Option<BodyId> {
        let aabb = shape.aabb(pose);
        self.first_contact_in_box(shape, pose, &aabb, margin, skip)
    }

    /// [`CollisionWorld::first_contact`] with the query's bounding box already computed (any
    /// box that contains the shape at `pose`).
    pub fn first_contact_in_box(
        &self,
        shape: &CollisionShape,
        pose: &Pose,
        aabb: &Aabb,
        margin: Real,
        skip: impl Fn(BodyId) -> bool,
    ) -> Option<BodyId> {
        self.first_within_margin(0..self.entries.len(), shape, pose, aabb, margin, skip)
    }

    /// The enabled bodies, in id order, whose boxes overlap `aabb` within `grow`: where a
    /// query about anything inside `aabb` need look ([`CollisionWorld::first_contact_among`]).
    /// Checking many shapes that stand together (a robot's links) against these few, rather
    /// than each against every body, gives the same answers for a pass over the world.
    pub fn bodies_near(&self, aabb: &Aabb, grow: Real) -> Vec<BodyId> {
        (self.entries.iter().enumerate())
            .filter(|(_, entry)| entry.enabled && entry.shape.is_some())
            .filter(|(_, entry)| entry.aabb.overlaps(aabb, grow))
            .map(|(index, _)| BodyId(index))
            .collect()
    }

    /// [`CollisionWorld::first_contact_in_box`] among `bodies` only (in the order given), which
    /// must include every body that query could meet: [`CollisionWorld::bodies_near`] of a box
    /// containing `aabb`, grown by at least `margin`.
    pub fn first_contact_among(
        &self,
        bodies: &[BodyId],
        shape: &CollisionShape,
        pose: &Pose,
        aabb: &Aabb,
        margin: Real,
        skip: impl Fn(BodyId) -> bool,
    ) -> Option<BodyId> {
        let ids = bodies.iter().map(|id| id.0);
        self.first_within_margin(ids, shape, pose, aabb, margin, skip)
    }

    /// The first body of `ids` closer than `margin` to `shape` at `pose` (inside `aabb`): the
    /// contact queries above over all bodies or some.
    fn first_within_margin(
        &self,
        ids: impl IntoIterator<Item = usize>,
        shape: &CollisionShape,
        pose: &Pose,
        aabb: &Aabb,
        margin: Real,
        skip: impl Fn(BodyId) -> bool,
    ) -> Option<BodyId> {
        self.first_body(ids, aabb, margin.max(0.0), skip, |other, other_pose| {
            within_margin(shape, pose, other, other_pose, margin)
        })
    }

    /// The first enabled body (in id order) that `shape` at `pose` overlaps deeper than `depth`
    /// ([`penetration_depth`]), skipping those `skip` says to.
    pub fn first_overlap_deeper_than(
        &self,
        shape: &CollisionShape,
        pose: &Pose,
        depth: Real,
        skip: impl Fn(BodyId) -> bool,
    ) -> Option<BodyId> {
        let all = 0..self.entries.len();
        self.first_body(all, &shape.aabb(pose), 0.0, skip, |other, other_pose| {
            penetration_depth(shape, pose, other, other_pose) > depth
        })
    }

    /// The first enabled body of `ids` (in their order) whose box overlaps `aabb` within
    /// `grow`, that `skip` keeps, and that `hits` (given its shape and pose): the broad phase
    /// every query shares.
    fn first_body(
        &self,
        ids: impl IntoIterator<Item = usize>,
        aabb: &Aabb,
        grow: Real,
        skip: impl Fn(BodyId) -> bool,
        hits: impl Fn(&CollisionShape, &Pose) -> bool,
    ) -> Option<BodyId> {
        ids.into_iter().find_map(|index| {
            let entry = self.entries.get(index)?;
            let other = entry.shape.as_ref().filter(|_| entry.enabled)?;
            let hit =
                entry.aabb.overlaps(aabb, grow) && !skip(BodyId(index)) && hits(other, &entry.pose);
            hit.then_some(BodyId(index))
        })
    }

    /// The enabled body `shape` at `pose` would first touch if it moved straight down, and how
    /// far it can move before it does (0 when it touches one already), looking no further than
    /// `max`; ties go to the lower id. Bodies `skip` names are ignored.
    pub fn first_below(
        &self,
        shape: &CollisionShape,
        pose: &Pose,
        max: Real,
        skip: impl Fn(BodyId) -> bool,
    ) -> Option<(BodyId, Real)> {
        let mut swept = shape.aabb(pose);
        swept.mins.z -= max;
        let mut nearest: Option<(BodyId, Real)> = None;
        for (index, entry) in self.entries.iter().enumerate() {
            let Some(other) = entry.shape.as_ref().filter(|_| entry.enabled) else { continue };
            if !entry.aabb.overlaps(&swept, 0.0) || skip(BodyId(index)) {
                continue;
            }
            let limit = nearest.map_or(max, |(_, drop)| drop);
            if let Some(drop) = drop_distance(shape, pose, other, &entry.pose, limit)
                && nearest.is_none_or(|(_, best)| drop < best)
            {
                nearest = Some((BodyId(index), drop));
            }
        }
        nearest
    }

    /// Every contact point between `shape` at `pose` and the enabled bodies closer than
    /// `prediction`, with the body it touches, in id order. Bodies `skip` names are ignored.
    pub fn contact_points(
        &self,
        shape: &CollisionShape,
        pose: &Pose,
        prediction: Real,
        skip: impl Fn(BodyId) -> bool,
    ) -> Vec<(BodyId, ContactPoint)> {
        let aabb = shape.aabb(pose);
        let mut points = Vec::new();
        for (index, entry) in self.entries.iter().enumerate() {
            let Some(other) = entry.shape.as_ref().filter(|_| entry.enabled) else { continue };
            if !entry.aabb.overlaps(&aabb, prediction) || skip(BodyId(index)) {
                continue;
            }
            let found = contact_points(shape, pose, other, &entry.pose, prediction);
            points.extend(found.into_iter().map(|point| (BodyId(index), point)));
        }
        points
    }

    /// Every pair of enabled bodies closer than `margin`, sorted (for checking a scene itself).
    pub fn contacts_between_bodies(&self, margin: Real) -> Vec<(BodyId, BodyId)> {
        let mut pairs = Vec::new();
        for (i, a) in self.entries.iter().enumerate() {
            for (j, b) in self.entries.iter().enumerate().skip(i + 1) {
                let (Some(a_shape), Some(b_shape)) = (&a.shape, &b.shape) else { continue };
                if a.enabled
                    && b.enabled
                    && a.aabb.overlaps(&b.aabb, margin.max(0.0))
                    && within_margin(a_shape, &a.pose, b_shape, &b.pose, margin)
                {
                    pairs.push((BodyId(i), BodyId(j)));
                }
            }
        }
        pairs
    }
}

/// The degenerate box at a marker's origin.
fn point_box(pose: &Pose) -> Aabb {
    let point = Point3::from(pose.translation.vector);
    Aabb { mins: point, maxs: point }
}
