//! Structure goals as learned relations: `structure NAME at ANCHOR offset POSE` becomes the
//! relations that hold among the structure's objects, and between each and its marker, once the
//! structure stands at its place.
//!
//! Each structure object is the scene object of the same name (the checker makes sure there is
//! one, of the same type). Its target is the anchor's pose · the offset · its pose in the
//! structure (`SpecWorld::structure_targets`), where `SpecWorld::problem_scene` puts its marker
//! `goal_<object>`. The placed structure is checked first, with the static world as it is and
//! nothing else: no two of its objects touch, and each rests by lamp-world's resting rule. Then
//! the goal state is made by moving every structure object of the problem scene to its target,
//! and abstracted with the learned classifiers as the initial state is; the goal is every region
//! relation (no `_0`, clear or nowhere relation) true there between two structure objects or a
//! structure object and its own target marker. Each object must get one, and each must be added by a
//! learned action, or the solver could never make it true.

use std::collections::BTreeSet;

use lamp_abstraction::GroundAtom;
use lamp_geometry::Pose;
use lamp_geometry::math::relative_pose;
use lamp_learn::{Model, ShapeOracle as _, abstract_state};
use lamp_participants::scene_snapshot;
use lamp_pddl::Atom;
use lamp_spec::Problem;
use lamp_spec::limits::number;
use lamp_world::{Scene, SpecWorld};

use crate::adapter::Adapter;
use crate::error::BuildError;
use crate::goal_warning::GoalWarning;
use crate::initial_scene::{MAX_DISTANCE, objects_at_targets};
use crate::shapes::SpecShapes;
use crate::structure_issue::StructureIssue;

/// Resting pairs named in a warning before the rest are counted.
const LISTED_RESTS: usize = 4;

/// The goal atoms of a problem's structure goal, or why it cannot be written; no atoms and no
/// findings for a problem without one.
pub fn structure_goal_atoms(
    model: &Model,
    world: &SpecWorld,
    adapter: &Adapter,
    problem: &Problem,
) -> Result<StructureGoal, BuildError> {
    let Some(goal) = &problem.goal.structure else { return Ok(StructureGoal::default()) };
    let scene_error = |reason: String| BuildError::Scene { problem: problem.name.clone(), reason };
    let targets =
        world.structure_targets(problem).map_err(|error| scene_error(error.to_string()))?;
    let issue_context = IssueContext { problem: &problem.name, structure: &goal.structure };
    let issues = placed_structure_issues(world, problem)?;
    if !issues.is_empty() {
        return Ok(StructureGoal { issues, ..StructureGoal::default() });
    }
    let mut scene = world.problem_scene(problem).map_err(|error| scene_error(error.to_string()))?;
    for (object, pose) in &targets {
        let body = scene.body_index(object).ok_or_else(|| {
            scene_error(format!("the structure's `{object}` is not in the scene"))
        })?;
        scene.set_body_pose(body, *pose);
    }
    let (participants, snapshot) =
        scene_snapshot(adapter.participants(), &scene).map_err(scene_error)?;
    let state = abstract_state(model, &participants, &snapshot)?;
    let objects: BTreeSet<String> = targets.iter().map(|(object, _)| object.clone()).collect();
    let markers: BTreeSet<String> = match world.goal_marker_type(problem) {
        Some(_) => objects.iter().map(|object| lamp_spec::marker_name(object)).collect(),
        None => BTreeSet::new(),
    };
    let atoms = goal_relations(model, &state, &objects, &markers);
    let found = Found { context: &issue_context, participants: &participants, scene: &scene };
    let mut issues = found.objects_without_atoms(&targets, &atoms, !markers.is_empty());
    issues.extend(found.unlearned(model, &atoms, &objects));
    if !issues.is_empty() {
        return Ok(StructureGoal { issues, ..StructureGoal::default() });
    }
    let warnings = found.unrelated_rests(model, &SpecShapes::new(world), &targets, &atoms);
    let atoms = atoms
        .iter()
        .map(|atom| {
            let names: Vec<&str> = atom.arguments.iter().map(String::as_str).collect();
            Atom::ground(atom.predicate.clone(), &names)
        })
        .collect();
    Ok(StructureGoal { atoms, issues: Vec::new(), warnings })
}

/// A problem's structure goal as written: its atoms, or the findings that refuse it, and the
/// warnings about a goal that is written.
#[derive(Debug, Default)]
pub struct StructureGoal {
    /// The goal atoms; none when there are findings.
    pub atoms: Vec<Atom>,
    /// Why the goal cannot be written.
    pub issues: Vec<StructureIssue>,
    /// What may keep a written goal from being reached.
    pub warnings: Vec<GoalWarning>,
}

/// The region relations of `state` between two structure objects, or between a structure object
/// and its own target marker, in the state's (sorted) order.
///
/// A marker is related to its own object only: a marker says where its object goes, and what
/// holds between it and a neighbour of its object (the block below) restates an object–object
/// relation through a stand-in, often one no action makes (the block below never moves while a
/// marker is set on it in a demonstration).
fn goal_relations(
    model: &Model,
    state: &BTreeSet<GroundAtom>,
    objects: &BTreeSet<String>,
    markers: &BTreeSet<String>,
) -> Vec<GroundAtom> {
    let regions: BTreeSet<&str> = model
        .pairs
        .iter()
        .flat_map(|pair| &pair.regions)
        .map(|region| region.relation.as_str())
        .collect();
    let in_goal = |atom: &&GroundAtom| match atom.arguments.as_slice() {
        [first, second] if objects.contains(first) && objects.contains(second) => true,
        [first, second] => [(first, second), (second, first)].iter().any(|(marker, object)| {
            markers.contains(*marker)
                && objects.contains(*object)
                && **marker == lamp_spec::marker_name(object)
        }),
        _ => false,
    };
    state
        .iter()
        .filter(|atom| regions.contains(atom.predicate.as_str()))
        .filter(in_goal)
        .cloned()
        .collect()
}

/// Where the problem and the structure are named in findings.
struct IssueContext<'a> {
    problem: &'a str,
    structure: &'a str,
}

/// The goal state, for the findings about its relations.
struct Found<'a> {
    context: &'a IssueContext<'a>,
    participants: &'a [lamp_abstraction::Participant],
    scene: &'a Scene,
}

impl Found<'_> {
    /// Each structure object that is in none of `atoms`.
    fn objects_without_atoms(
        &self,
        targets: &[(String, Pose)],
        atoms: &[GroundAtom],
        marked: bool,
    ) -> Vec<StructureIssue> {
        targets
            .iter()
            .map(|(object, _)| object)
            .filter(|object| !atoms.iter().any(|atom| atom.arguments.contains(object)))
            .map(|object| {
                let partners = if marked {
                    format!(
                        "its marker `{}` or the other objects of the structure",
                        lamp_spec::marker_name(object)
                    )
                } else {
                    "the other objects of the structure (the spec declares no marker type, so \
                     none marks its place)"
                        .to_string()
                };
                StructureIssue::NoGoalAtom {
                    problem: self.context.problem.to_string(),
                    structure: self.context.structure.to_string(),
                    object: object.clone(),
                    type_name: self.type_of(object),
                    partners,
                }
            })
            .collect()
    }

    /// Each of `atoms` that no learned action adds, with the secondary's pose in the primary's
    /// frame; it is about its structure object (the secondary, or the primary of a marker).
    fn unlearned(
        &self,
        model: &Model,
        atoms: &[GroundAtom],
        objects: &BTreeSet<String>,
    ) -> Vec<StructureIssue> {
        let added: BTreeSet<&str> = model
            .actions
            .iter()
            .flat_map(|action| &action.add)
            .map(|atom| atom.predicate.as_str())
            .collect();
        let pose_of =
            |name: &str| self.scene.body_index(name).map(|body| self.scene.body_pose(body));
        atoms
            .iter()
            .filter(|atom| !added.contains(atom.predicate.as_str()))
            .filter_map(|atom| {
                let [primary, secondary] = atom.arguments.as_slice() else { return None };
                let relative = relative_pose(&pose_of(primary)?, &pose_of(secondary)?);
                let object = if objects.contains(secondary) { secondary } else { primary };
                Some(StructureIssue::Unlearned {
                    problem: self.context.problem.to_string(),
                    structure: self.context.structure.to_string(),
                    object: object.clone(),
                    atom: atom.to_string(),
                    primary_type: self.type_of(primary),
                    secondary_type: self.type_of(secondary),
                    pose: spec_pose(&relative),
                })
            })
            .collect()
    }

    /// The structure objects of a type pair the model relates that touch at their places (one
    /// resting on the other, within the release tolerance) with no goal atom between them, in one
    /// warning. Without the atom the goal does not order the two, and a plan that puts the upper
    /// one first lets go of it above nothing.
    fn unrelated_rests(
        &self,
        model: &Model,
        shapes: &SpecShapes,
        targets: &[(String, Pose)],
        atoms: &[GroundAtom],
    ) -> Vec<GoalWarning> {
        let related: BTreeSet<(&str, &str)> = model
            .pairs
            .iter()
            .map(|learned| &learned.pair.pair)
            .chain(&model.pairs_without_regions)
            .map(|pair| (pair.primary.as_str(), pair.secondary.as_str()))
            .collect();
        let relates = |a: &str, b: &str| {
            atoms.iter().any(|atom| {
                matches!(atom.arguments.as_slice(), [x, y] if (x == a && y == b) || (x == b && y == a))
            })
        };
        // (object above, what it rests on), in the structure's order.
        let mut rests: Vec<(&str, &str)> = Vec::new();
        for (index, (first, first_pose)) in targets.iter().enumerate() {
            for (second, second_pose) in &targets[index + 1..] {
                let (first_type, second_type) = (self.type_of(first), self.type_of(second));
                let pair_related = related.contains(&(first_type.as_str(), second_type.as_str()))
                    || related.contains(&(second_type.as_str(), first_type.as_str()));
                let relative = relative_pose(first_pose, second_pose);
                let touching = shapes
                    .gap(&first_type, &second_type, &relative)
                    .is_some_and(|gap| gap <= lamp_world::MAX_SETTLE_DROP);
                if pair_related && touching && !relates(first, second) {
                    let first_higher = first_pose.translation.z >= second_pose.translation.z;
                    rests.push(if first_higher { (first, second) } else { (second, first) });
                }
            }
        }
        let Some(&(object, _)) = rests.first() else { return Vec::new() };
        let mut listed: Vec<String> = rests
            .iter()
            .take(LISTED_RESTS)
            .map(|(object, support)| format!("`{object}` on `{support}`"))
            .collect();
        if rests.len() > LISTED_RESTS {
            listed.push(format!("{} more", rests.len() - LISTED_RESTS));
        }
        vec![GoalWarning::UnrelatedRest {
            problem: self.context.problem.to_string(),
            structure: self.context.structure.to_string(),
            object: object.to_string(),
            count: rests.len(),
            rests: listed.join(", "),
        }]
    }

    fn type_of(&self, name: &str) -> String {
        self.participants
            .iter()
            .find(|participant| participant.name == name)
            .map(|participant| participant.type_name.clone())
            .unwrap_or_default()
    }
}

/// The findings of a problem's structure standing alone at its anchor on the problem's static
/// bodies: objects that touch one another or a static body, then objects that do not rest by the
/// resting rule (an object already reported as touching is not judged again: the rule would only
/// say it touches). Empty without a structure goal.
pub fn placed_structure_issues(
    world: &SpecWorld,
    problem: &Problem,
) -> Result<Vec<StructureIssue>, BuildError> {
    let Some(goal) = &problem.goal.structure else { return Ok(Vec::new()) };
    let scene_error = |error: lamp_world::WorldError| BuildError::Scene {
        problem: problem.name.clone(),
        reason: error.to_string(),
    };
    let targets = world.structure_targets(problem).map_err(scene_error)?;
    let context = IssueContext { problem: &problem.name, structure: &goal.structure };
    // A target beyond the scenes' range is reported as such: collision queries there are not
    // exact, and found every such structure intersecting itself.
    let far: Vec<StructureIssue> = targets
        .iter()
        .filter_map(|(object, pose)| {
            let position = pose.translation.vector;
            // Compared per coordinate first: the norm of (1e308, 1e308, 0) overflows.
            let far = !position.iter().all(|coordinate| coordinate.is_finite())
                || position.amax() > MAX_DISTANCE
                || position.norm() > MAX_DISTANCE;
            far.then(|| StructureIssue::OutOfRange {
                problem: problem.name.clone(),
                structure: goal.structure.clone(),
                object: object.clone(),
                position: format!(
                    "({}, {}, {})",
                    number(position.x),
                    number(position.y),
                    number(position.z)
                ),
            })
        })
        .collect();
    if !far.is_empty() {
        return Ok(far);
    }
    let scene = objects_at_targets(world, problem, &targets).map_err(scene_error)?;
    Ok(structure_scene_issues(&scene, &targets, &context))
}

fn structure_scene_issues(
    scene: &Scene,
    targets: &[(String, Pose)],
    context: &IssueContext<'_>,
) -> Vec<StructureIssue> {
    let structure: BTreeSet<&str> = targets.iter().map(|(object, _)| object.as_str()).collect();
    let mut issues = Vec::new();
    let mut touching = BTreeSet::new();
    for (first, second) in scene.body_contacts() {
        let (object, other) =
            if structure.contains(first.as_str()) { (first, second) } else { (second, first) };
        touching.insert(object.clone());
        touching.insert(other.clone());
        issues.push(StructureIssue::Contact {
            problem: context.problem.to_string(),
            structure: context.structure.to_string(),
            object,
            other,
        });
    }
    for (object, _) in targets {
        if touching.contains(object) {
            continue;
        }
        let Some(body) = scene.body_index(object) else { continue };
        if let Err(reason) = scene.resting_pose(body) {
            issues.push(StructureIssue::Unsupported {
                problem: context.problem.to_string(),
                structure: context.structure.to_string(),
                object: object.clone(),
                reason: reason.to_string(),
            });
        }
    }
    issues
}

/// A pose as a spec writes one: `(x, y, z) m rpy (r, p, y) deg`, millimetres and tenths of a
/// degree.
fn spec_pose(pose: &Pose) -> String {
    let position = pose.translation.vector;
    let (roll, pitch, yaw) = pose.rotation.euler_angles();
    let degrees = |angle: f64| {
        let value = (angle.to_degrees() * 10.0).round() / 10.0;
        if value == 0.0 { 0.0 } else { value }
    };
    let metres = |value: f64| {
        let value = (value * 1000.0).round() / 1000.0;
        if value == 0.0 { 0.0 } else { value }
    };
    format!(
        "({}, {}, {}) m rpy ({}, {}, {}) deg",
        metres(position.x),
        metres(position.y),
        metres(position.z),
        degrees(roll),
        degrees(pitch),
        degrees(yaw)
    )
}
