//! What an action asks of the robot: which effect relation to realise, which link moves to make
//! it true, and which objects change hands.
//!
//! The driving effect is the first added region relation (`<t1>_<t2>_<k>`, k ≥ 1) whose
//! realisation moves a robot link; failing that, the first added "in no region" relation
//! (`<t1>_<t2>_0`). The link that moves is the primary when the primary is a robot part (the
//! gripper approaches a can, the base drives to a table), the secondary when both are links of
//! one robot (the arm tucks relative to the base), or the gripper holding the secondary when the
//! primary is an object (a held can is carried into the box), or the gripper holding the primary
//! when the secondary is an object (a held block is put on one below it, in a pair whose primary
//! is the block above). Of several added regions, one relative to a frame no robot carries is
//! sampled first, then the narrowest.
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
    /// The primary is held by the moving link with `grasp` (a held block placed relative to one
    /// below it, in a pair whose primary is the upper): target = secondary · X⁻¹ · grasp⁻¹.
    HeldPrimary { secondary: String, grasp: Pose },
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
        if let Some((robot, link, grasp)) = held_by(secondary).filter(|_| !released(secondary)) {
            return Some(Mover {
                robot: robot.clone(),
                link: link.clone(),
                anchor: Anchor::HeldSecondary { primary: primary.clone(), grasp: *grasp },
                region,
            });
        }
        if view.parts.contains_key(secondary) {
            // A robot part is always the primary of its pairs; a held primary with a part as
            // secondary does not occur.
            return None;
        }
        let (robot, link, grasp) = held_by(primary).filter(|_| !released(primary))?;
        Some(Mover {
            robot: robot.clone(),
            link: link.clone(),
            anchor: Anchor::HeldPrimary { secondary: secondary.clone(), grasp: *grasp },
            region,
        })
    };
    // Of the regions the action adds, one is sampled and the others are tested (the stream keeps
    // a candidate only when every effect holds). A region of an object robots carry is placed
    // wherever that object came to rest, off its own target by up to its region's width, so
    // sampling it builds each placement on the error of the one before, and up a stack the
    // errors add until no sample meets the fixed frames: a frame nothing carries (a marker, a
    // table) comes first. Then an intersection is sampled best from its narrowest member. Ties
    // keep the effects' order.
    let carried = carried_types(artifact);
    let order = |(pair, region): (usize, usize)| {
        let drifts = carried.contains(artifact.pairs[pair].primary.as_str());
        (drifts, artifact.pairs[pair].regions[region].model.position_spread())
    };
    let mut regions: Vec<((bool, f64), Mover)> = add
        .iter()
        .filter_map(|atom| match relation_kind(artifact, &atom.predicate) {
            Some(RelationKind::Region { pair, region, .. }) => {
                mover_for(atom, Some((pair, region))).map(|mover| (order((pair, region)), mover))
            }
            _ => None,
        })
        .collect();
    regions.sort_by(|a, b| a.0.0.cmp(&b.0.0).then(a.0.1.total_cmp(&b.0.1)));
    let regions = regions.into_iter().map(|(_, mover)| mover);
    let outside = add.iter().filter_map(|atom| match relation_kind(artifact, &atom.predicate) {
        Some(RelationKind::Outside { .. }) => mover_for(atom, None),
        _ => None,
    });
    let mover = regions.chain(outside).next();
    Realisation { mover, releases, grabs }
}

/// The types robots carry: the secondaries of held regions (g = 1).
fn carried_types(artifact: &SamplerArtifact) -> std::collections::BTreeSet<&str> {
    artifact
        .pairs
        .iter()
        .filter(|pair| pair.regions.iter().any(|region| region.g == 1))
        .map(|pair| pair.secondary.as_str())
        .collect()
}

#[cfg(test)]
mod tests {
    use lamp_plugin_api::{
        HeldObject, IDENTITY_POSE, ObjectState, RobotPart, RobotState, WorldState,
    };

    use super::*;

    /// A region of `relation` whose mixture is one Gaussian at `centre` with standard deviation
    /// `sigma` in every feature.
    fn region(relation: &str, g: u8, centre: [f64; 3], sigma: f64) -> String {
        let mean = [centre[0], centre[1], centre[2], 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let covariance: Vec<f64> =
            (0..81).map(|index| if index % 10 == 0 { sigma * sigma } else { 0.0 }).collect();
        format!(
            r#"{{"relation": "{relation}", "g": {g}, "clear": true, "nowhere": true, "model": {{"g": {g}, "mixture": {{"dimension": 9, "weights": [1.0], "means": [{mean:?}], "covariances": [{covariance:?}]}}, "threshold": -100.0, "extent": [[-1.0, 1.0], [-1.0, 1.0], [-1.0, 1.0]]}}}}"#
        )
    }

    /// Blocks above blocks (a wide and a narrow region), blocks on markers, and a grasp.
    fn artifact() -> SamplerArtifact {
        artifact_with_marker_spread(0.001)
    }

    /// [`artifact`] with the marker region's standard deviation `sigma`.
    fn artifact_with_marker_spread(sigma: f64) -> SamplerArtifact {
        let pair = |primary: &str, secondary: &str, regions: Vec<String>| {
            format!(
                r#"{{"primary": "{primary}", "secondary": "{secondary}", "regions": [{}]}}"#,
                regions.join(", ")
            )
        };
        let json = format!(
            r#"{{"version": {}, "seed": 1, "pairs": [{}, {}, {}]}}"#,
            lamp_abstraction::SAMPLER_ARTIFACT_VERSION,
            pair(
                "block",
                "block",
                vec![
                    region("block_block_1", 0, [0.0, 0.0, 0.03], 0.03),
                    region("block_block_2", 0, [0.0, 0.05, 0.03], 0.002),
                ]
            ),
            pair("gripper", "block", vec![region("gripper_block_1", 1, [0.0, 0.0, 0.1], 0.002)]),
            pair("loc", "block", vec![region("loc_block_1", 0, [0.0, 0.0, 0.0], sigma)]),
        );
        let artifact: SamplerArtifact = serde_json::from_str(&json).unwrap();
        artifact.validate().unwrap();
        artifact
    }

    /// A gripper holding `b2` above `b1`, with marker `m2`.
    fn view() -> WorldView {
        let object = |name: &str, object_type: &str| ObjectState {
            name: name.into(),
            object_type: object_type.into(),
            pose: IDENTITY_POSE,
        };
        let world = WorldState {
            robots: vec![RobotState {
                name: "arm".into(),
                configuration: vec![0.0; 3],
                held: vec![HeldObject {
                    object: "b2".into(),
                    link: "hand".into(),
                    grasp: IDENTITY_POSE,
                }],
                parts: vec![RobotPart {
                    object: "arm_gripper".into(),
                    object_type: "gripper".into(),
                    link: "hand".into(),
                    gripper: true,
                }],
            }],
            objects: vec![object("b1", "block"), object("b2", "block"), object("m2", "loc")],
        };
        WorldView::new(&world).unwrap()
    }

    fn atom(predicate: &str, arguments: &[&str]) -> GroundAtom {
        GroundAtom {
            predicate: predicate.into(),
            arguments: arguments.iter().map(|argument| (*argument).to_string()).collect(),
        }
    }

    /// The mover of a carry that adds `add` (letting go is an action of its own).
    fn placement(add: &[GroundAtom]) -> Mover {
        let realisation = realisation(&artifact(), &view(), add, &[]);
        assert!(realisation.releases.is_empty() && realisation.grabs.is_empty());
        realisation.mover.unwrap()
    }

    #[test]
    fn of_the_regions_a_placement_adds_the_narrowest_is_sampled() {
        let wide = atom("block_block_1", &["b1", "b2"]);
        let on_marker = atom("loc_block_1", &["m2", "b2"]);
        let narrow = atom("block_block_2", &["b1", "b2"]);
        let mover = placement(&[wide.clone(), narrow.clone(), on_marker.clone()]);
        assert_eq!(mover.region, Some((2, 0)), "the marker's region is fixed and the narrowest");
        assert!(matches!(&mover.anchor, Anchor::HeldSecondary { primary, .. } if primary == "m2"));
        let mover = placement(&[wide, narrow]);
        assert_eq!(mover.region, Some((0, 1)));
    }

    #[test]
    fn a_region_of_a_frame_no_robot_carries_is_sampled_before_a_narrower_one_of_a_carried_object() {
        // The marker's region is five times wider than the narrow block region; blocks are carried
        // (the gripper's held region), markers are not.
        let artifact = artifact_with_marker_spread(0.01);
        let add = [atom("block_block_2", &["b1", "b2"]), atom("loc_block_1", &["m2", "b2"])];
        let mover = realisation(&artifact, &view(), &add, &[]).mover.unwrap();
        assert_eq!(mover.region, Some((2, 0)));
        assert!(matches!(&mover.anchor, Anchor::HeldSecondary { primary, .. } if primary == "m2"));
    }

    #[test]
    fn a_held_block_that_is_the_primary_is_placed_relative_to_the_secondary() {
        let mover = placement(&[atom("block_block_2", &["b2", "b1"])]);
        assert_eq!(mover.region, Some((0, 1)));
        match &mover.anchor {
            Anchor::HeldPrimary { secondary, .. } => assert_eq!(secondary, "b1"),
            other => panic!("expected the held primary to move, got {other:?}"),
        }
    }
}
