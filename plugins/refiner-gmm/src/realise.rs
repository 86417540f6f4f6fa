//! What an action asks of the robot: which effect relation to realise, which link moves to make
//! it true, and which objects change hands.
//!
//! The driving effect is the first added region relation (`<t1>_<t2>_<k>`, k ≥ 1) whose
//! realisation moves a robot link; failing that, the first added "in no region" relation
//! (`<t1>_<t2>_0`). The link that moves is the primary when the primary is a robot part (the
//! gripper approaches a can, the base drives to a table), the secondary when both are links of
//! one robot (the arm tucks relative to the base), or the gripper holding the secondary when the
//! primary is an object (a held can is carried into the box).
//!
//! Grasp changes follow the held flag of the regions: an added held region (g = 1) whose gripper
//! does not hold its object yet is a grab, done after the motion; a deleted held region whose
//! object the gripper holds, with no held region of the same pair added, is a release, done
//! before the motion.

use lamp_abstraction::{Pose, SamplerArtifact};
use lamp_plugin_api::{GraspChange, GroundAtom};

use crate::world_view::WorldView;

/// What a predicate of the learned vocabulary means.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RelationKind {
    /// Region k (index `region`) of pair `pair`, with held flag `g`.
    Region { pair: usize, region: usize, g: u8 },
    /// In no region of pair `pair`.
    Outside { pair: usize },
}

/// The meaning of `predicate`, or `None` for clear and nowhere relations and unknown names.
pub(crate) fn relation_kind(artifact: &SamplerArtifact, predicate: &str) -> Option<RelationKind> {
    artifact.pairs.iter().enumerate().find_map(|(pair, entry)| {
        if predicate == format!("{}_{}_0", entry.primary, entry.secondary) {
            return Some(RelationKind::Outside { pair });
        }
        entry
            .regions
            .iter()
            .position(|region| region.relation == predicate)
            .map(|region| RelationKind::Region { pair, region, g: entry.regions[region].g })
    })
}

/// How the moving link's target follows from a pose of the secondary in the primary's frame.
#[derive(Clone, Debug)]
pub(crate) enum Anchor {
    /// The primary is the moving link: target = secondary · X⁻¹.
    PrimaryLink { secondary: String },
    /// The secondary is held by the moving link with `grasp`: target = primary · X · grasp⁻¹.
    HeldSecondary { primary: String, grasp: Pose },
    /// The secondary is the moving link, of the same robot as the primary: target = primary · X.
    SecondaryLink { primary: String },
}

/// The motion that realises the driving effect.
#[derive(Clone, Debug)]
pub(crate) struct Mover {
    pub(crate) robot: String,
    pub(crate) link: String,
    pub(crate) anchor: Anchor,
    /// The region to sample, or `None` to move out of every region of the pair.
    pub(crate) region: Option<(usize, usize)>,
}

/// What an action asks of the robot.
#[derive(Clone, Debug, Default)]
pub(crate) struct Realisation {
    /// `None` when only grasp changes (or nothing) are needed.
    pub(crate) mover: Option<Mover>,
    pub(crate) releases: Vec<GraspChange>,
    pub(crate) grabs: Vec<GraspChange>,
}

/// Works out the realisation of an action with `add` and `delete` effects in `view`.
pub(crate) fn realisation(
    artifact: &SamplerArtifact,
    view: &WorldView,
    add: &[GroundAtom],
    delete: &[GroundAtom],
) -> Realisation {
    let held_by = |object: &str| view.current.held.get(object);
    let mut grabs = Vec::new();
    for atom in add {
        if let (Some(RelationKind::Region { g: 1, .. }), [gripper, object]) =
            (relation_kind(artifact, &atom.predicate), atom.arguments.as_slice())
            && let Some(part) = view.parts.get(gripper).filter(|part| part.gripper)
            && held_by(object).is_none()
        {
            grabs.push(GraspChange {
                robot: part.robot.clone(),
                link: part.link.clone(),
                object: object.clone(),
            });
        }
    }
    let mut releases = Vec::new();
    for atom in delete {
        let still_held = add.iter().any(|added| {
            added.arguments == atom.arguments
                && matches!(
                    relation_kind(artifact, &added.predicate),
                    Some(RelationKind::Region { g: 1, .. })
                )
        });
        if let (Some(RelationKind::Region { g: 1, .. }), [gripper, object]) =
            (relation_kind(artifact, &atom.predicate), atom.arguments.as_slice())
            && !still_held
            && let Some(part) = view.parts.get(gripper).filter(|part| part.gripper)
            && held_by(object)
                .is_some_and(|(robot, link, _)| robot == &part.robot && link == &part.link)
        {
            releases.push(GraspChange {
                robot: part.robot.clone(),
                link: part.link.clone(),
                object: object.clone(),
            });
        }
    }
    let released = |object: &str| releases.iter().any(|change| change.object == object);
    let mover_for = |atom: &GroundAtom, region: Option<(usize, usize)>| -> Option<Mover> {
        let [primary, secondary] = atom.arguments.as_slice() else { return None };
        if let (Some(first), Some(second)) = (view.parts.get(primary), view.parts.get(secondary))
            && first.robot == second.robot
        {
            // Two links of one robot (the gripper relative to the base): moving the primary
            // would carry the secondary along, so the secondary moves.
            return Some(Mover {
                robot: second.robot.clone(),
                link: second.link.clone(),
                anchor: Anchor::SecondaryLink { primary: primary.clone() },
                region,
            });
        }
        if let Some(part) = view.parts.get(primary) {
            return Some(Mover {
                robot: part.robot.clone(),
                link: part.link.clone(),
                anchor: Anchor::PrimaryLink { secondary: secondary.clone() },
                region,
            });
        }
        let (robot, link, grasp) = held_by(secondary).filter(|_| !released(secondary))?;
        Some(Mover {
            robot: robot.clone(),
            link: link.clone(),
            anchor: Anchor::HeldSecondary { primary: primary.clone(), grasp: *grasp },
            region,
        })
    };
    let regions = add.iter().filter_map(|atom| match relation_kind(artifact, &atom.predicate) {
        Some(RelationKind::Region { pair, region, .. }) => mover_for(atom, Some((pair, region))),
        _ => None,
    });
    let outside = add.iter().filter_map(|atom| match relation_kind(artifact, &atom.predicate) {
        Some(RelationKind::Outside { .. }) => mover_for(atom, None),
        _ => None,
    });
    let mover = regions.chain(outside).next();
    Realisation { mover, releases, grabs }
}
