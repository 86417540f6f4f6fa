//! The deterministic PDDL writer.
//!
//! Layout is fixed (two-space indentation, one declaration or atom per line) and every list is
//! emitted in model order, so the same model always gives the same bytes. Requirements are computed
//! from what the model uses, never copied from a declaration. Every action carries a
//! `:precondition`, `(and)` when empty, because some validators (VAL) reject actions without one.

use std::fmt::Write as _;

use crate::model::{Action, Atom, Condition, Domain, Literal, Problem, Requirement, Term, Typed};

// A model prints as its PDDL text; the impls live with the writer, so that the model does not
// name it back.
impl std::fmt::Display for Domain {
    /// The PDDL text of [`write_domain`].
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&write_domain(self))
    }
}

impl std::fmt::Display for Problem {
    /// The PDDL text of [`write_problem`].
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&write_problem(self))
    }
}

/// Writes `domain` as PDDL text.
#[must_use]
pub fn write_domain(domain: &Domain) -> String {
    let requirements = domain.used_requirements();
    let typing = requirements.contains(&Requirement::Typing);
    let mut out = String::new();
    line(&mut out, 0, &format!("(define (domain {})", domain.name));
    line(&mut out, 1, &format!("(:requirements {})", keywords(&requirements)));
    if typing && !domain.types.is_empty() {
        line(&mut out, 1, "(:types");
        for decl in &domain.types {
            line(&mut out, 2, &format!("{} - {}", decl.name, decl.parent));
        }
        line(&mut out, 1, ")");
    }
    if !domain.constants.is_empty() {
        line(&mut out, 1, "(:constants");
        for constant in &domain.constants {
            line(&mut out, 2, &typed_name(constant, "", typing));
        }
        line(&mut out, 1, ")");
    }
    line(&mut out, 1, "(:predicates");
    for predicate in &domain.predicates {
        let mut text = format!("({}", predicate.name);
        for parameter in &predicate.parameters {
            text.push(' ');
            text.push_str(&typed_name(parameter, "?", typing));
        }
        text.push(')');
        line(&mut out, 2, &text);
    }
    line(&mut out, 1, ")");
    for action in &domain.actions {
        write_action(&mut out, action, typing);
    }
    out.push_str(")\n");
    out
}

/// Writes `problem` as PDDL text. A problem with negative goal literals declares
/// `:negative-preconditions` itself, because the domain's requirements do not know its goal.
#[must_use]
pub fn write_problem(problem: &Problem) -> String {
    let mut out = String::new();
    line(&mut out, 0, &format!("(define (problem {})", problem.name));
    line(&mut out, 1, &format!("(:domain {})", problem.domain));
    if problem.uses_negative_goals() {
        line(
            &mut out,
            1,
            &format!("(:requirements {})", keywords(&[Requirement::NegativePreconditions])),
        );
    }
    let typing = problem.objects.iter().any(|object| object.type_name != crate::OBJECT_TYPE);
    line(&mut out, 1, "(:objects");
    for object in &problem.objects {
        line(&mut out, 2, &typed_name(object, "", typing));
    }
    line(&mut out, 1, ")");
    line(&mut out, 1, "(:init");
    for atom in &problem.init {
        line(&mut out, 2, &atom_text(atom));
    }
    line(&mut out, 1, ")");
    line(&mut out, 1, "(:goal (and");
    for literal in &problem.goal {
        line(&mut out, 2, &literal_text(literal));
    }
    line(&mut out, 1, "))");
    out.push_str(")\n");
    out
}

fn write_action(out: &mut String, action: &Action, typing: bool) {
    line(out, 1, &format!("(:action {}", action.name));
    let parameters: Vec<String> =
        action.parameters.iter().map(|parameter| typed_name(parameter, "?", typing)).collect();
    line(out, 2, &format!(":parameters ({})", parameters.join(" ")));
    if action.precondition.is_empty() {
        line(out, 2, ":precondition (and)");
    } else {
        line(out, 2, ":precondition (and");
        for condition in &action.precondition {
            line(out, 3, &condition_text(condition));
        }
        line(out, 2, ")");
    }
    if action.add.is_empty() && action.delete.is_empty() {
        line(out, 2, ":effect (and)");
    } else {
        line(out, 2, ":effect (and");
        for atom in &action.add {
            line(out, 3, &atom_text(atom));
        }
        for atom in &action.delete {
            line(out, 3, &format!("(not {})", atom_text(atom)));
        }
        line(out, 2, ")");
    }
    line(out, 1, ")");
}

fn line(out: &mut String, depth: usize, text: &str) {
    for _ in 0..depth {
        out.push_str("  ");
    }
    out.push_str(text);
    out.push('\n');
}

fn keywords(requirements: &[Requirement]) -> String {
    requirements.iter().map(|requirement| requirement.keyword()).collect::<Vec<_>>().join(" ")
}

fn typed_name(typed: &Typed, prefix: &str, typing: bool) -> String {
    if typing {
        format!("{prefix}{} - {}", typed.name, typed.type_name)
    } else {
        format!("{prefix}{}", typed.name)
    }
}

fn term_text(term: &Term) -> String {
    match term {
        Term::Variable(name) => format!("?{name}"),
        Term::Constant(name) => name.clone(),
    }
}

/// `(p a ?b)`.
#[must_use]
pub fn atom_text(atom: &Atom) -> String {
    let mut text = format!("({}", atom.predicate);
    for argument in &atom.arguments {
        // Writing to a String cannot fail.
        let _ = write!(text, " {}", term_text(argument));
    }
    text.push(')');
    text
}

fn condition_text(condition: &Condition) -> String {
    match condition {
        Condition::Atom { atom, positive: true } => atom_text(atom),
        Condition::Atom { atom, positive: false } => format!("(not {})", atom_text(atom)),
        Condition::Equality { left, right, positive, .. } => {
            let equality = format!("(= {} {})", term_text(left), term_text(right));
            if *positive { equality } else { format!("(not {equality})") }
        }
    }
}

fn literal_text(literal: &Literal) -> String {
    if literal.positive {
        atom_text(&literal.atom)
    } else {
        format!("(not {})", atom_text(&literal.atom))
    }
}
