//! PDDL problems from spec problems: objects and initial state from the problem's scene, goal from
//! its learned-relation and alias atoms, its AtGoals and its structure goal.
//!
//! Objects are the scene's robot parts (`<robot>_<part type>`) and its bodies that are not the static
//! world. The initial state is the learned abstraction of the scene: body poses as placed, part
//! poses by forward kinematics of the robot's initial configuration; the markers of AtGoal and
//! structure targets are objects like the others. The goal: the learned-relation and alias atoms,
//! each AtGoal as its object on its marker (`at_goals`), the relations of the transcribed
//! structure (`structure_goals`), and the grippers empty as they start.

use std::collections::{BTreeMap, BTreeSet};

use lamp_abstraction::{GroundAtom, Participant, Role, Snapshot};
use lamp_learn::{Model, abstract_state, ground_atoms};
use lamp_participants::scene_snapshot;
use lamp_pddl::{Atom, Literal, Typed};
use lamp_spec::Problem;
use lamp_world::SpecWorld;

use crate::adapter::Adapter;
use crate::aliases::ResolvedAlias;
use crate::at_goals::{at_goal_atoms, contradicting_goals};
use crate::error::BuildError;
use crate::goal_warning::GoalWarning;
use crate::structure_goals::structure_goal_atoms;
use crate::structure_issue::StructureIssue;

/// What became of one spec problem.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ProblemOutcome {
    /// Written; `warnings` say what may make it hard.
    Written { name: String, text: String, warnings: Vec<GoalWarning> },
    /// Not written, and why.
    Skipped { name: String, reason: String },
    /// Its structure goal cannot be transcribed: every finding.
    Refused { name: String, issues: Vec<StructureIssue> },
}

/// Everything a problem is written against.
pub struct ProblemContext<'a> {
    pub model: &'a Model,
    pub domain: &'a lamp_pddl::Domain,
    pub world: &'a SpecWorld,
    pub adapter: &'a Adapter,
    pub aliases: &'a BTreeMap<String, ResolvedAlias>,
    /// Comment lines (without `;`) written at the top of the file.
    pub header: &'a [String],
}

/// The PDDL problem of a spec problem, or why it is skipped.
pub fn problem_pddl(
    context: &ProblemContext<'_>,
    problem: &Problem,
) -> Result<ProblemOutcome, BuildError> {
    let name = problem.name.clone();
    let goal = &problem.goal;
    if goal.atoms.is_empty() && goal.at.is_empty() && goal.structure.is_none() {
        let reason = "its goal is empty".to_string();
        return Ok(ProblemOutcome::Skipped { name, reason });
    }
    let mut goal_atoms = goal_atoms(context, problem)?;
    contradicting_goals(context.model, problem, &goal_atoms)?;
    let (at_atoms, warnings) = at_goal_atoms(context.model, problem)?;
    goal_atoms.extend(at_atoms);
    let (participants, snapshot) = initial_snapshot(context, problem)?;
    let declared: BTreeMap<&str, Role> =
        context.model.types.iter().map(|(name, role)| (name.as_str(), *role)).collect();
    if let Some(missing) = participants
        .iter()
        .find(|participant| !declared.contains_key(participant.type_name.as_str()))
    {
        let reason = format!(
            "object `{}` has type `{}`, which appears in no demonstration, so the learned domain does not declare it",
            missing.name, missing.type_name
        );
        return Ok(ProblemOutcome::Skipped { name, reason });
    }
    let structure = structure_goal_atoms(context.model, context.world, context.adapter, problem)?;
    if !structure.issues.is_empty() {
        return Ok(ProblemOutcome::Refused { name, issues: structure.issues });
    }
    goal_atoms.extend(structure.atoms);
    let mut warnings = warnings;
    warnings.extend(structure.warnings);
    let init = abstract_state(context.model, &participants, &snapshot)?;
    let mut pddl = lamp_pddl::Problem::new(problem.name.clone(), context.domain.name.clone());
    pddl.objects = participants
        .iter()
        .map(|participant| Typed::new(participant.name.clone(), participant.type_name.clone()))
        .collect();
    pddl.init = ground_atoms(&init);
    let mut goal = goal_atoms;
    goal.extend(ground_atoms(&hands_free(context.model, &init)));
    pddl.goal = goal.into_iter().map(Literal::positive).collect();
    pddl.sort_canonical();
    if let Some(problem_error) = lamp_pddl::check_problem(context.domain, &pddl).first() {
        return Err(BuildError::Emit {
            what: format!("problem `{}`", problem.name),
            reason: problem_error.to_string(),
        });
    }
    let mut text = String::new();
    for line in context.header {
        text.push_str(&format!("; {line}\n"));
    }
    text.push_str(&lamp_pddl::write_problem(&pddl));
    Ok(ProblemOutcome::Written { name, text, warnings })
}

/// The clear relations of held regions (g = 1) true in `init`: grippers that start empty must end
/// empty, so that a plan puts down what it carries instead of stopping with the last object in
/// hand. A held region without a clear relation (two objects fit in it) says the same with its
/// nowhere relations: what is held by no gripper at the start is held by none at the end. Where
/// the clear relation exists, its nowhere atoms would add nothing, so they are left out.
fn hands_free(model: &Model, init: &BTreeSet<GroundAtom>) -> BTreeSet<GroundAtom> {
    let held: BTreeSet<String> = model
        .pairs
        .iter()
        .flat_map(|pair| &pair.regions)
        .filter(|region| region.summary.g == 1)
        .filter_map(|region| {
            let sides = &region.summary.sides;
            if sides.clear.on {
                Some(format!("clear_{}", region.relation))
            } else if sides.nowhere.on {
                Some(format!("nowhere_{}", region.relation))
            } else {
                None
            }
        })
        .collect();
    init.iter().filter(|atom| held.contains(&atom.predicate)).cloned().collect()
}

fn goal_atoms(context: &ProblemContext<'_>, problem: &Problem) -> Result<Vec<Atom>, BuildError> {
    let predicates: Vec<String> =
        context.model.predicates().into_iter().map(|signature| signature.name).collect();
    problem
        .goal
        .atoms
        .iter()
        .map(|atom| {
            if let Some(alias) = context.aliases.get(&atom.relation) {
                let arguments = alias.arguments(&atom.arguments);
                let names: Vec<&str> = arguments.iter().map(String::as_str).collect();
                return Ok(Atom::ground(alias.relation.clone(), &names));
            }
            if !predicates.contains(&atom.relation) {
                return Err(BuildError::GoalRelation {
                    problem: problem.name.clone(),
                    relation: atom.relation.clone(),
                });
            }
            let names: Vec<&str> = atom.arguments.iter().map(String::as_str).collect();
            Ok(Atom::ground(atom.relation.clone(), &names))
        })
        .collect()
}

/// The participants of a problem's initial scene and their snapshot.
fn initial_snapshot(
    context: &ProblemContext<'_>,
    problem: &Problem,
) -> Result<(Vec<Participant>, Snapshot), BuildError> {
    let scene_error = |reason: String| BuildError::Scene { problem: problem.name.clone(), reason };
    let scene =
        context.world.problem_scene(problem).map_err(|error| scene_error(error.to_string()))?;
    scene_snapshot(context.adapter.participants(), &scene).map_err(scene_error)
}
