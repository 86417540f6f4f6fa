//! Plan steps as grounded actions: the lifted action's preconditions and effects with its
//! parameters replaced by the step's objects.

use std::collections::{BTreeMap, BTreeSet};

use lamp_abstraction::GroundAtom;
use lamp_pddl::{Atom, Condition, Domain, Problem, Term};
use lamp_plugin_api::{GroundAtom as WireAtom, GroundedAction, PlanStep};

use crate::error::SolveError;

/// The grounded action of a plan step, whose arguments must be objects of `problem` (or the
/// domain's constants) of the action's parameter types: a planner's plan that names anything else
/// is a bad plan at once, not a plan that no sample can ever refine.
pub fn ground_step(
    domain: &Domain,
    problem: &Problem,
    step: &PlanStep,
) -> Result<GroundedAction, SolveError> {
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
    for (parameter, argument) in action.parameters.iter().zip(&step.arguments) {
        let object = problem
            .objects
            .iter()
            .chain(&domain.constants)
            .find(|object| object.name.eq_ignore_ascii_case(argument));
        let reason = match object {
            None => format!("`{argument}` is no object of problem `{}`", problem.name),
            Some(object) if !is_a(domain, &object.type_name, &parameter.type_name) => format!(
                "`{argument}` is a {}, and the action's `?{}` is a {}",
                object.type_name, parameter.name, parameter.type_name
            ),
            Some(_) => continue,
        };
        return Err(SolveError::BadPlan { step: step_text(step), reason });
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
    let literals = |wanted: bool| {
        action
            .precondition
            .iter()
            .filter_map(|condition| match condition {
                Condition::Atom { atom, positive } if *positive == wanted => Some(ground(atom)),
                _ => None,
            })
            .collect()
    };
    Ok(GroundedAction {
        name: action.name.clone(),
        arguments: step.arguments.clone(),
        preconditions: literals(true),
        negative_preconditions: literals(false),
        add_effects: action.add.iter().map(ground).collect(),
        delete_effects: action.delete.iter().map(ground).collect(),
    })
}

/// Whether type `kind` is `wanted` or one of its descendants (every type is an `object`).
fn is_a(domain: &Domain, kind: &str, wanted: &str) -> bool {
    let mut current = kind;
    // A type chain is no longer than the declarations; a cycle is cut off there.
    for _ in 0..=domain.types.len() {
        if current.eq_ignore_ascii_case(wanted) || wanted.eq_ignore_ascii_case("object") {
            return true;
        }
        match domain.types.iter().find(|declared| declared.name.eq_ignore_ascii_case(current)) {
            Some(declared) => current = &declared.parent,
            None => return false,
        }
    }
    false
}

/// The state after `action` from `before`: deletes removed, then adds added.
pub fn progress(before: &BTreeSet<GroundAtom>, action: &GroundedAction) -> BTreeSet<GroundAtom> {
    let mut after = before.clone();
    apply(&mut after, action);
    after
}

/// [`progress`] in place: a plan's states are checked one after another, and copying a state of
/// thousands of atoms at every step of a long plan was most of the time a 30-block tower took.
fn apply(state: &mut BTreeSet<GroundAtom>, action: &GroundedAction) {
    for atom in &action.delete_effects {
        state.remove(&learned_atom(atom));
    }
    state.extend(action.add_effects.iter().map(learned_atom));
}

/// The effects of an action a state does not show: the adds that are false and the deletes that
/// still hold, each in effect order.
#[derive(Clone, Debug, PartialEq)]
pub struct Unmet {
    pub missing: Vec<GroundAtom>,
    pub unwanted: Vec<GroundAtom>,
}

/// The effects of `action` that `state` does not show, if any.
pub fn unmet_effects(state: &BTreeSet<GroundAtom>, action: &GroundedAction) -> Option<Unmet> {
    let missing = atoms_where(state, &action.add_effects, false);
    let unwanted = atoms_where(state, &action.delete_effects, true);
    (!missing.is_empty() || !unwanted.is_empty()).then_some(Unmet { missing, unwanted })
}

/// Of `atoms`, those whose truth in `state` is `held`, in order.
fn atoms_where(state: &BTreeSet<GroundAtom>, atoms: &[WireAtom], held: bool) -> Vec<GroundAtom> {
    atoms.iter().map(learned_atom).filter(|atom| state.contains(atom) == held).collect()
}

/// Where the rest of a plan breaks when run from `state`: the index in `rest` of the first
/// action whose preconditions do not hold (`rest.len()` for the goal), with the atoms missing
/// and the atoms that hold but must not.
#[derive(Clone, Debug, PartialEq)]
pub struct Broken {
    pub index: usize,
    pub missing: Vec<GroundAtom>,
    pub unwanted: Vec<GroundAtom>,
}

/// Where `rest` breaks when its actions are applied in order from `state` and then `goal` is
/// required; `None` when the rest of the plan still runs from `state` and reaches `goal`.
pub fn first_broken(
    state: &BTreeSet<GroundAtom>,
    rest: &[GroundedAction],
    goal: &BTreeSet<GroundAtom>,
) -> Option<Broken> {
    let mut state = state.clone();
    for (index, action) in rest.iter().enumerate() {
        let missing = atoms_where(&state, &action.preconditions, false);
        let unwanted = atoms_where(&state, &action.negative_preconditions, true);
        if !missing.is_empty() || !unwanted.is_empty() {
            return Some(Broken { index, missing, unwanted });
        }
        apply(&mut state, action);
    }
    let missing: Vec<GroundAtom> = goal.difference(&state).cloned().collect();
    (!missing.is_empty()).then_some(Broken { index: rest.len(), missing, unwanted: Vec::new() })
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
    call_text(&step.action, &step.arguments)
}

/// `(name a b)`.
pub fn call_text(name: &str, arguments: &[String]) -> String {
    let mut text = format!("({name}");
    for argument in arguments {
        text.push(' ');
        text.push_str(argument);
    }
    text.push(')');
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wire(predicate: &str, arguments: &[&str]) -> WireAtom {
        WireAtom {
            predicate: predicate.to_string(),
            arguments: arguments.iter().map(ToString::to_string).collect(),
        }
    }

    fn action(
        name: &str,
        pre: &[&WireAtom],
        add: &[&WireAtom],
        delete: &[&WireAtom],
    ) -> GroundedAction {
        let owned = |atoms: &[&WireAtom]| atoms.iter().map(|atom| (*atom).clone()).collect();
        GroundedAction {
            name: name.to_string(),
            arguments: Vec::new(),
            preconditions: owned(pre),
            negative_preconditions: Vec::new(),
            add_effects: owned(add),
            delete_effects: owned(delete),
        }
    }

    /// A can lifted off table1 by a tuck the plan did not expect: picking it up again from
    /// table1 is broken (and says what it misses); putting it on table2 is not.
    #[test]
    fn the_rest_of_a_plan_breaks_where_a_precondition_is_missing() {
        let on1 = wire("on", &["can1", "table1"]);
        let on2 = wire("on", &["can1", "table2"]);
        let held = wire("held", &["can1"]);
        let reached: BTreeSet<GroundAtom> = [learned_atom(&held)].into_iter().collect();
        let put = action("put", &[&held], &[&on2], &[&held]);
        let goal: BTreeSet<GroundAtom> = [learned_atom(&on2)].into_iter().collect();
        assert_eq!(first_broken(&reached, std::slice::from_ref(&put), &goal), None);

        let pick = action("pick", &[&on1], &[&held], &[&on1]);
        let broken = first_broken(&reached, &[put.clone(), pick], &goal).expect("broken");
        assert_eq!(
            broken,
            Broken { index: 1, missing: vec![learned_atom(&on1)], unwanted: Vec::new() }
        );

        let elsewhere: BTreeSet<GroundAtom> = [learned_atom(&on1)].into_iter().collect();
        let broken = first_broken(&reached, &[put], &elsewhere).expect("the goal fails");
        assert_eq!(
            broken,
            Broken { index: 1, missing: vec![learned_atom(&on1)], unwanted: Vec::new() }
        );
        assert!(unmet_effects(&reached, &action("none", &[], &[&held], &[&on1])).is_none());
        let unmet = unmet_effects(&reached, &action("put", &[], &[&on1], &[&held]))
            .expect("the put's effects do not hold");
        assert_eq!(
            (unmet.missing, unmet.unwanted),
            (vec![learned_atom(&on1)], vec![learned_atom(&held)])
        );
    }

    /// A block placed across two that must each be on some marker ("on no marker" false): the
    /// rest breaks when one of them is on none, and says which atom holds that must not.
    #[test]
    fn a_negative_precondition_that_holds_breaks_the_rest() {
        let on_none = wire("nowhere_loc_block_1", &["b2"]);
        let across = wire("block_block_1", &["b3", "b2"]);
        let mut place = action("place", &[], &[&across], &[]);
        place.negative_preconditions = vec![on_none.clone()];
        let goal: BTreeSet<GroundAtom> = [learned_atom(&across)].into_iter().collect();
        assert_eq!(first_broken(&BTreeSet::new(), std::slice::from_ref(&place), &goal), None);

        let reached: BTreeSet<GroundAtom> = [learned_atom(&on_none)].into_iter().collect();
        let broken = first_broken(&reached, &[place], &goal).expect("broken");
        assert_eq!(
            broken,
            Broken { index: 0, missing: Vec::new(), unwanted: vec![learned_atom(&on_none)] }
        );
    }

    /// A plan step naming an object the problem does not have, or one of another type, is a bad
    /// plan, said at once and naming the argument.
    #[test]
    fn a_step_naming_an_unknown_object_or_one_of_another_type_is_a_bad_plan() {
        let domain = lamp_pddl::parse_domain(
            "(define (domain d) (:requirements :strips :typing) (:types can surface gripper)
               (:predicates (on ?s - surface ?c - can))
               (:action put :parameters (?g - gripper ?c - can ?s - surface)
                 :precondition (and) :effect (on ?s ?c)))",
        )
        .expect("a domain");
        let problem = lamp_pddl::parse_problem(
            "(define (problem p) (:domain d)
               (:objects g1 - gripper can1 - can box1 - surface)
               (:init) (:goal (on box1 can1)))",
            &domain,
        )
        .expect("a problem");
        let step = |arguments: &[&str]| PlanStep {
            action: "put".to_string(),
            arguments: arguments.iter().map(ToString::to_string).collect(),
        };
        let grounded = ground_step(&domain, &problem, &step(&["g1", "can1", "box1"]));
        assert_eq!(grounded.expect("a good step").add_effects, [wire("on", &["box1", "can1"])]);
        let reason = |arguments: &[&str]| match ground_step(&domain, &problem, &step(arguments)) {
            Err(SolveError::BadPlan { reason, .. }) => reason,
            other => panic!("not a bad plan: {other:?}"),
        };
        assert_eq!(reason(&["g1", "can7", "box1"]), "`can7` is no object of problem `p`");
        assert_eq!(
            reason(&["g1", "box1", "can1"]),
            "`box1` is a surface, and the action's `?c` is a can"
        );
    }
}
