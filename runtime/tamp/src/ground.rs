//! Plan steps as grounded actions: the lifted action's preconditions and effects with its
//! parameters replaced by the step's objects.

use std::collections::{BTreeMap, BTreeSet};

use lamp_learn::GroundAtom;
use lamp_pddl::{Atom, Condition, Domain, Term};
use lamp_plugin_api::{GroundAtom as WireAtom, GroundedAction, PlanStep};

use crate::error::SolveError;

/// The grounded action of a plan step.
pub fn ground_step(domain: &Domain, step: &PlanStep) -> Result<GroundedAction, SolveError> {
    let action = domain
        .actions
        .iter()
        .find(|action| action.name.eq_ignore_ascii_case(&step.action))
        .ok_or_else(|| SolveError::BadPlan {
            step: step_text(step),
            reason: "the domain has no such action".to_string(),
        })?;
    if action.parameters.len() != step.arguments.len() {
        return Err(SolveError::BadPlan {
            step: step_text(step),
            reason: format!("the action takes {} arguments", action.parameters.len()),
        });
    }
    let binding: BTreeMap<&str, &str> = action
        .parameters
        .iter()
        .zip(&step.arguments)
        .map(|(parameter, argument)| (parameter.name.as_str(), argument.as_str()))
        .collect();
    let ground = |atom: &Atom| WireAtom {
        predicate: atom.predicate.clone(),
        arguments: atom
            .arguments
            .iter()
            .map(|term| match term {
                Term::Variable(name) => {
                    binding.get(name.as_str()).map_or_else(|| name.clone(), |o| (*o).to_string())
                }
                Term::Constant(name) => name.clone(),
            })
            .collect(),
    };
    let preconditions = action
        .precondition
        .iter()
        .filter_map(|condition| match condition {
            Condition::Atom { atom, positive: true } => Some(ground(atom)),
            _ => None,
        })
        .collect();
    Ok(GroundedAction {
        name: action.name.clone(),
        arguments: step.arguments.clone(),
        preconditions,
        add_effects: action.add.iter().map(ground).collect(),
        delete_effects: action.delete.iter().map(ground).collect(),
    })
}

/// The state after `action` from `before`: deletes removed, then adds added.
pub fn progress(before: &BTreeSet<GroundAtom>, action: &GroundedAction) -> BTreeSet<GroundAtom> {
    let mut after = before.clone();
    for atom in &action.delete_effects {
        after.remove(&learned_atom(atom));
    }
    after.extend(action.add_effects.iter().map(learned_atom));
    after
}

/// Whether `action`'s effects hold in `state`: every add is true and every delete false.
pub fn effects_hold(state: &BTreeSet<GroundAtom>, action: &GroundedAction) -> bool {
    action.add_effects.iter().all(|atom| state.contains(&learned_atom(atom)))
        && !action.delete_effects.iter().any(|atom| state.contains(&learned_atom(atom)))
}

/// The first of `rest` (by index) whose preconditions do not hold when the actions are applied
/// in order from `state`, or `rest.len()` if none and the goal then fails; `None` when the rest
/// of the plan still runs from `state` and reaches `goal`.
pub fn first_broken(
    state: &BTreeSet<GroundAtom>,
    rest: &[GroundedAction],
    goal: &BTreeSet<GroundAtom>,
) -> Option<usize> {
    let mut state = state.clone();
    for (index, action) in rest.iter().enumerate() {
        if !action.preconditions.iter().all(|atom| state.contains(&learned_atom(atom))) {
            return Some(index);
        }
        state = progress(&state, action);
    }
    (!goal.is_subset(&state)).then_some(rest.len())
}

/// A ground atom of the plugin contract as the learner's.
pub fn learned_atom(atom: &WireAtom) -> GroundAtom {
    GroundAtom { predicate: atom.predicate.clone(), arguments: atom.arguments.clone() }
}

/// A ground PDDL atom as the learner's.
pub fn pddl_atom(atom: &Atom) -> GroundAtom {
    GroundAtom {
        predicate: atom.predicate.clone(),
        arguments: atom.arguments.iter().map(|term| term.name().to_string()).collect(),
    }
}

/// `(action a b)`.
pub fn step_text(step: &PlanStep) -> String {
    let mut text = format!("({}", step.action);
    for argument in &step.arguments {
        text.push(' ');
        text.push_str(argument);
    }
    text.push(')');
    text
}
