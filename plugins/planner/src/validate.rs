//! The plan validator: simulates a plan on the lifted domain from the initial state, checking every
//! step's arguments and precondition and finally the goal.
//!
//! It works on the PDDL model directly, not on the grounded task, so it also checks the grounder and
//! plans from other planners.

use std::collections::{BTreeMap, BTreeSet};

use lamp_pddl::{Atom, Condition, Domain, Problem, Term};
use miette::Diagnostic;
use thiserror::Error;

use crate::plan::{Plan, PlanStep};

/// Why a plan is not valid. Steps are numbered from 1.
#[derive(Clone, Debug, PartialEq, Eq, Error, Diagnostic)]
pub enum ValidationError {
    #[error("step {step} {action}: no such action")]
    #[diagnostic(code(lamp::plan::unknown_action))]
    UnknownAction { step: usize, action: String },

    #[error("step {step} {action}: expects {expected} argument(s), got {found}")]
    #[diagnostic(code(lamp::plan::arity))]
    Arity { step: usize, action: String, expected: usize, found: usize },

    #[error("step {step} {action}: `{object}` is not an object of this problem")]
    #[diagnostic(code(lamp::plan::unknown_object))]
    UnknownObject { step: usize, action: String, object: String },

    #[error("step {step} {action}: `{object}` has type `{found}`, parameter wants `{expected}`")]
    #[diagnostic(code(lamp::plan::type_mismatch))]
    TypeMismatch { step: usize, action: String, object: String, expected: String, found: String },

    #[error("step {step} {action}: precondition {condition} does not hold")]
    #[diagnostic(code(lamp::plan::precondition))]
    Precondition { step: usize, action: String, condition: String },

    #[error("after the last step, goal {literal} does not hold")]
    #[diagnostic(code(lamp::plan::goal))]
    Goal { literal: String },
}

type GroundKey = (String, Vec<String>);

/// The final state of a valid plan, as sorted ground atoms `(predicate, arguments)`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Validated {
    pub final_state: BTreeSet<GroundKey>,
}

/// Checks `plan` for `problem` over `domain` (both assumed to pass `lamp_pddl`'s checks).
///
/// # Errors
/// The first failing step and condition, or the first goal literal that does not hold.
pub fn validate(
    domain: &Domain,
    problem: &Problem,
    plan: &Plan,
) -> Result<Validated, ValidationError> {
    let types: BTreeMap<&str, &str> = domain
        .constants
        .iter()
        .chain(&problem.objects)
        .map(|o| (o.name.as_str(), o.type_name.as_str()))
        .collect();
    let mut state: BTreeSet<GroundKey> =
        problem.init.iter().map(|atom| ground(atom, &[])).collect();
    for (index, step) in plan.steps.iter().enumerate() {
        let number = index + 1;
        apply_step(domain, &types, &mut state, step, number)?;
    }
    for literal in &problem.goal {
        if state.contains(&ground(&literal.atom, &[])) != literal.positive {
            let atom = lamp_pddl::atom_text(&literal.atom);
            let literal = if literal.positive { atom } else { format!("(not {atom})") };
            return Err(ValidationError::Goal { literal });
        }
    }
    Ok(Validated { final_state: state })
}

fn apply_step(
    domain: &Domain,
    types: &BTreeMap<&str, &str>,
    state: &mut BTreeSet<GroundKey>,
    step: &PlanStep,
    number: usize,
) -> Result<(), ValidationError> {
    let name = step.to_string();
    let Some(action) = domain.action(&step.action) else {
        return Err(ValidationError::UnknownAction { step: number, action: name });
    };
    if action.parameters.len() != step.arguments.len() {
        return Err(ValidationError::Arity {
            step: number,
            action: name,
            expected: action.parameters.len(),
            found: step.arguments.len(),
        });
    }
    let mut binding = Vec::with_capacity(step.arguments.len());
    for (parameter, object) in action.parameters.iter().zip(&step.arguments) {
        let Some(found) = types.get(object.as_str()) else {
            return Err(ValidationError::UnknownObject {
                step: number,
                action: name,
                object: object.clone(),
            });
        };
        if !domain.is_subtype(found, &parameter.type_name) {
            return Err(ValidationError::TypeMismatch {
                step: number,
                action: name,
                object: object.clone(),
                expected: parameter.type_name.clone(),
                found: (*found).to_owned(),
            });
        }
        binding.push((parameter.name.as_str(), object.as_str()));
    }
    for condition in &action.precondition {
        let holds = match condition {
            Condition::Atom { atom, positive } => {
                state.contains(&ground(atom, &binding)) == *positive
            }
            Condition::Equality { left, right, positive, .. } => {
                (value(left, &binding) == value(right, &binding)) == *positive
            }
        };
        if !holds {
            return Err(ValidationError::Precondition {
                step: number,
                action: name,
                condition: condition_text(condition, &binding),
            });
        }
    }
    for atom in &action.delete {
        state.remove(&ground(atom, &binding));
    }
    for atom in &action.add {
        state.insert(ground(atom, &binding));
    }
    Ok(())
}

fn value<'a>(term: &'a Term, binding: &[(&str, &'a str)]) -> &'a str {
    match term {
        Term::Variable(name) => binding
            .iter()
            .find(|(parameter, _)| parameter == name)
            .map_or(name.as_str(), |(_, object)| object),
        Term::Constant(name) => name,
    }
}

fn ground(atom: &Atom, binding: &[(&str, &str)]) -> GroundKey {
    (
        atom.predicate.clone(),
        atom.arguments.iter().map(|term| value(term, binding).to_owned()).collect(),
    )
}

fn condition_text(condition: &Condition, binding: &[(&str, &str)]) -> String {
    match condition {
        Condition::Atom { atom, positive } => {
            let (predicate, arguments) = ground(atom, binding);
            let text = format!(
                "({predicate}{})",
                arguments.iter().map(|a| format!(" {a}")).collect::<String>()
            );
            if *positive { text } else { format!("(not {text})") }
        }
        Condition::Equality { left, right, positive, .. } => {
            let text = format!("(= {} {})", value(left, binding), value(right, binding));
            if *positive { text } else { format!("(not {text})") }
        }
    }
}
