//! PDDL out: the learned domain and abstract states as lamp-pddl values, written by its deterministic writer.
//!
//! Types are the participant types (children of `object`), predicates follow declaration order, actions keep
//! their numbering, parameters keep their sorted order, and every pair of same-typed parameters gets
//! `(not (= ?a ?b))`. The writer then sorts conditions and effects canonically.

use std::collections::BTreeSet;

use lamp_pddl::model::{Atom, Condition, Domain, Predicate, Span, Term, TypeDecl, Typed};

use crate::abstraction::GroundAtom;
use crate::actions::{Action, LiftedAtom};
use crate::error::LearnError;
use crate::model::Model;

/// The learned domain as a lamp-pddl model, checked.
pub fn domain(model: &Model, name: &str) -> Result<Domain, LearnError> {
    let mut domain = Domain::new(name);
    domain.types = model
        .types
        .iter()
        .map(|(type_name, _)| TypeDecl {
            name: type_name.clone(),
            parent: lamp_pddl::OBJECT_TYPE.to_string(),
            span: Span::default(),
        })
        .collect();
    domain.predicates = model
        .predicates()
        .into_iter()
        .map(|signature| Predicate {
            name: signature.name,
            parameters: signature
                .argument_types
                .iter()
                .enumerate()
                .map(|(position, type_name)| {
                    Typed::new(["x", "y"][position.min(1)], type_name.clone())
                })
                .collect(),
            span: Span::default(),
        })
        .collect();
    domain.actions = model.actions.iter().map(action).collect();
    domain.sort_canonical();
    let problems = lamp_pddl::check_domain(&domain);
    if let Some(problem) = problems.first() {
        return Err(LearnError::Emit { reason: problem.to_string() });
    }
    Ok(domain)
}

/// The learned domain as PDDL text.
pub fn domain_text(model: &Model, name: &str) -> Result<String, LearnError> {
    Ok(lamp_pddl::write_domain(&domain(model, name)?))
}

/// Ground atoms as PDDL atoms (for a problem's `:init` or a goal), in atom order.
pub fn ground_atoms(atoms: &BTreeSet<GroundAtom>) -> Vec<Atom> {
    atoms
        .iter()
        .map(|atom| {
            Atom::new(
                atom.predicate.clone(),
                atom.arguments.iter().cloned().map(Term::Constant).collect(),
            )
        })
        .collect()
}

fn variable(name: &str) -> Term {
    Term::Variable(name.trim_start_matches('?').to_string())
}

fn lifted(atom: &LiftedAtom) -> Atom {
    Atom::new(
        atom.predicate.clone(),
        atom.arguments.iter().map(|argument| variable(argument)).collect(),
    )
}

fn action(learned: &Action) -> lamp_pddl::Action {
    let parameters = learned
        .parameters
        .iter()
        .map(|parameter| {
            Typed::new(parameter.name.trim_start_matches('?'), parameter.type_name.clone())
        })
        .collect();
    let mut pddl = lamp_pddl::Action::new(learned.name.clone(), parameters);
    pddl.precondition = learned
        .distinct_parameter_pairs()
        .into_iter()
        .map(|(left, right)| Condition::distinct(variable(&left), variable(&right)))
        .chain(learned.preconditions.iter().map(|atom| Condition::atom(lifted(atom))))
        .chain(learned.negative_preconditions.iter().map(|atom| Condition::not_atom(lifted(atom))))
        .collect();
    pddl.add = learned.add.iter().map(lifted).collect();
    pddl.delete = learned.delete.iter().map(lifted).collect();
    pddl
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::actions::Parameter;

    fn atom(predicate: &str, arguments: &[&str]) -> LiftedAtom {
        LiftedAtom {
            predicate: predicate.into(),
            arguments: arguments.iter().map(|a| a.to_string()).collect(),
        }
    }

    #[test]
    fn same_typed_parameters_must_differ_and_variables_lose_their_mark() {
        let learned = Action {
            name: "a1".into(),
            parameters: vec![
                Parameter { name: "?can_p1".into(), type_name: "can".into() },
                Parameter { name: "?can_p2".into(), type_name: "can".into() },
                Parameter { name: "?gripper_p1".into(), type_name: "gripper".into() },
            ],
            preconditions: vec![atom("gripper_can_2", &["?gripper_p1", "?can_p1"])],
            negative_preconditions: vec![],
            add: vec![atom("can_can_1", &["?can_p2", "?can_p1"])],
            delete: vec![atom("can_can_0", &["?can_p2", "?can_p1"])],
            transitions: vec![],
            distinct_transitions: 0,
        };
        let pddl = action(&learned);
        assert_eq!(
            pddl.precondition[0],
            Condition::distinct(variable("?can_p1"), variable("?can_p2"))
        );
        assert_eq!(pddl.precondition.len(), 2);
        assert_eq!(pddl.parameters[0].name, "can_p1");
        assert_eq!(lamp_pddl::atom_text(&pddl.add[0]), "(can_can_1 ?can_p2 ?can_p1)");
    }

    #[test]
    fn ground_atoms_keep_atom_order() {
        let atoms = BTreeSet::from([
            GroundAtom { predicate: "b".into(), arguments: vec!["x".into()] },
            GroundAtom { predicate: "a".into(), arguments: vec!["y".into(), "x".into()] },
        ]);
        let texts: Vec<String> = ground_atoms(&atoms).iter().map(lamp_pddl::atom_text).collect();
        assert_eq!(texts, ["(a y x)", "(b x)"]);
    }
}
