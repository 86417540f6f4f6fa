//! AtGoal goals as learned relations: `at OBJECT POSE within D A` becomes the atom of the learned
//! relation that puts an object of the object's type onto a marker, with the marker that
//! `SpecWorld::problem_scene` places at the target.
//!
//! The relation is found by example, the way aliases are (`resolve_alias`): among the learned
//! regions of the (marker type, object type) pair, the one that contains the identity (the
//! object exactly on its marker), largest margin first. A region reaches farther than its
//! centre; when samples of it stray from the target by more than the stated tolerance, the build
//! warns: the solver then needs more samples to land within it, and the final replay refuses a
//! solution that does not.

use lamp_abstraction::{Pose, RegionClassifier};
use lamp_learn::Model;
use lamp_pddl::Atom;
use lamp_spec::{AtGoal, Problem, RelationAlias};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::aliases::resolve_alias;
use crate::error::BuildError;
use crate::goal_warning::GoalWarning;

/// Samples drawn from a region to measure how far it strays from its target.
const SPREAD_SAMPLES: usize = 400;
/// The share of samples a tolerance must cover for the build not to warn.
const SPREAD_QUANTILE: f64 = 0.95;

/// The goal atoms of a problem's AtGoals, and warnings about them.
pub fn at_goal_atoms(
    model: &Model,
    problem: &Problem,
) -> Result<(Vec<Atom>, Vec<GoalWarning>), BuildError> {
    let mut atoms = Vec::new();
    let mut warnings = Vec::new();
    for goal in &problem.goal.at {
        let Some(object) = problem.scene.objects.iter().find(|object| object.name == goal.object)
        else {
            return Err(BuildError::Scene {
                problem: problem.name.clone(),
                reason: format!("the `at` goal names `{}`, which is not in the scene", goal.object),
            });
        };
        let on_marker = RelationAlias {
            name: format!("at {}", goal.object),
            parameters: [goal.marker_type.clone(), object.type_name.clone()],
            primary: goal.marker_type.clone(),
            secondary: object.type_name.clone(),
            example: Pose::identity(),
        };
        // Without the shapes' turns: an AtGoal's target is the object's own pose, turn and all.
        let relation = resolve_alias(model, &on_marker, &lamp_learn::LearnConfig::default())
            .map_err(|error| BuildError::AtGoal {
                problem: problem.name.clone(),
                object: goal.object.clone(),
                marker_type: goal.marker_type.clone(),
                object_type: object.type_name.clone(),
                reason: match error {
                    BuildError::AliasPair { .. } => "the demonstrations never put one onto a \
                                                     marker often enough to learn a region"
                        .to_string(),
                    BuildError::AliasRegion { regions, .. } => format!(
                        "no learned region contains the object exactly on its marker ({regions})"
                    ),
                    other => other.to_string(),
                },
            })?
            .relation;
        let marker = goal.marker_name();
        atoms.push(Atom::ground(relation.clone(), &[marker.as_str(), goal.object.as_str()]));
        if let Some(warning) = spread_warning(model, problem, goal, &relation) {
            warnings.push(warning);
        }
    }
    Ok((atoms, warnings))
}

/// Refuses an AtGoal that a relation goal contradicts: one of `problem`'s relation goals, with
/// `resolved` the learned atoms they stand for in the same order, relates the AtGoal's object to
/// a marker (a scene object of the marker type, or another goal's marker) whose region does not
/// reach the target. The region does not reach it when the target, in the marker's frame, is
/// outside the region's membership test, and none of the region's samples (drawn as for the
/// tolerance warning) lands within the goal's position tolerance of it. Without this the build
/// wrote both goals, and the solver failed to place the object, suggesting a looser tolerance.
///
/// # Errors
/// [`BuildError::AtGoalContradiction`] naming the first AtGoal and relation goal that contradict.
pub fn contradicting_goals(
    model: &Model,
    problem: &Problem,
    resolved: &[Atom],
) -> Result<(), BuildError> {
    let Some(marker_type) = problem.goal.at.first().map(|goal| goal.marker_type.as_str()) else {
        return Ok(());
    };
    // Where each marker of the problem is: scene markers as placed, the AtGoals' at their
    // targets and where their objects start.
    let mut markers: Vec<(String, Pose)> = problem
        .scene
        .objects
        .iter()
        .filter(|object| object.type_name == marker_type)
        .map(|object| (object.name.clone(), object.pose))
        .collect();
    for goal in &problem.goal.at {
        markers.push((goal.marker_name(), goal.pose));
        if let Some(object) = problem.scene.objects.iter().find(|o| o.name == goal.object) {
            markers.push((goal.start_marker_name(), object.pose));
        }
    }
    for goal in &problem.goal.at {
        let own_marker = goal.marker_name();
        for (written, atom) in problem.goal.atoms.iter().zip(resolved) {
            let names: Vec<&str> = atom.arguments.iter().map(lamp_pddl::Term::name).collect();
            let [primary, secondary] = names.as_slice() else { continue };
            let (marker, object_is_secondary) = if *secondary == goal.object {
                (*primary, true)
            } else if *primary == goal.object {
                (*secondary, false)
            } else {
                continue;
            };
            if marker == own_marker {
                continue;
            }
            let Some((_, marker_pose)) = markers.iter().find(|(name, _)| name == marker) else {
                continue;
            };
            let Some(region) = model.region(&atom.predicate) else { continue };
            // The relation's secondary in its primary's frame, with the object at its target.
            let relative = if object_is_secondary {
                marker_pose.inverse() * goal.pose
            } else {
                goal.pose.inverse() * marker_pose
            };
            if region.model.margin(&relative) >= 0.0 || reaches(model, region, &relative, goal) {
                continue;
            }
            let distance = (marker_pose.translation.vector - goal.pose.translation.vector).norm();
            return Err(BuildError::AtGoalContradiction {
                problem: problem.name.clone(),
                object: goal.object.clone(),
                relation_goal: format!("{}({})", written.relation, written.arguments.join(", ")),
                reason: format!(
                    "the `at` goal puts `{}` within {:.1} mm of its target, which lies {:.1} mm from `{marker}`, outside the region `{}` that the other goal puts it in",
                    goal.object,
                    goal.position_tolerance * 1000.0,
                    distance * 1000.0,
                    atom.predicate
                ),
            });
        }
    }
    Ok(())
}

/// Whether a sample of `region` lands within `goal`'s position tolerance of `relative`.
fn reaches(model: &Model, region: &lamp_learn::Region, relative: &Pose, goal: &AtGoal) -> bool {
    region_samples(model, region).any(|sample| {
        (sample.translation.vector - relative.translation.vector).norm() <= goal.position_tolerance
    })
}

/// The samples of a region both goal checks measure: drawn with the model's seed, so that the
/// same model always warns and refuses the same way.
fn region_samples<'a>(
    model: &Model,
    region: &'a lamp_learn::Region,
) -> impl Iterator<Item = Pose> + 'a {
    let mut rng = ChaCha8Rng::seed_from_u64(model.seed);
    (0..SPREAD_SAMPLES).map(move |_| region.model.sample(&mut rng))
}

/// A warning when the region strays from the target by more than the goal allows, measured on
/// samples drawn with the model's seed (so the same model always warns the same way).
fn spread_warning(
    model: &Model,
    problem: &Problem,
    goal: &AtGoal,
    relation: &str,
) -> Option<GoalWarning> {
    let region = model.region(relation)?;
    let mut distances = Vec::with_capacity(SPREAD_SAMPLES);
    let mut angles = Vec::with_capacity(SPREAD_SAMPLES);
    // A sample is the object in the marker's frame, or the marker in the object's: the distance
    // and the angle from the identity are the same either way.
    for sample in region_samples(model, region) {
        distances.push(sample.translation.vector.norm());
        angles.push(sample.rotation.angle());
    }
    let position = quantile(&mut distances, SPREAD_QUANTILE);
    let angle = quantile(&mut angles, SPREAD_QUANTILE);
    if position <= goal.position_tolerance && angle <= goal.angle_tolerance {
        return None;
    }
    Some(GoalWarning::LooserRegion {
        problem: problem.name.clone(),
        object: goal.object.clone(),
        relation: relation.to_string(),
        share: format!("{:.0} %", SPREAD_QUANTILE * 100.0),
        position: format!("{:.1} mm", position * 1000.0),
        angle: format!("{:.1}°", angle.to_degrees()),
        tolerance: format!(
            "{:.1} mm and {:.1}°",
            goal.position_tolerance * 1000.0,
            goal.angle_tolerance.to_degrees()
        ),
    })
}

/// The `q` quantile of `values` (nearest rank).
fn quantile(values: &mut [f64], q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    let rank = ((values.len() as f64) * q).ceil() as usize;
    values.get(rank.saturating_sub(1)).copied().unwrap_or(0.0)
}
