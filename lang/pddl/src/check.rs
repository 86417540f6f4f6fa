//! Semantic checks on a model: names are declared, arities and types agree, nothing is declared
//! twice, variables are bound, the type hierarchy is a tree.
//!
//! The checks work on the model, not on text, so they validate both parsed domains and domains built
//! in memory; spans only sharpen the labels. Every problem is reported, not just the first.

use std::collections::BTreeMap;

use crate::error::{PddlError, label};
use crate::model::{Atom, Condition, Domain, OBJECT_TYPE, Problem, Span, Term, Typed};

/// Every problem in `domain`, in source order of the checks (types, constants, predicates, actions).
#[must_use]
pub fn check_domain(domain: &Domain) -> Vec<PddlError> {
    let mut errors = Vec::new();
    check_domain_names(domain, &mut errors);
    check_types(domain, &mut errors);
    duplicates("constant", domain.constants.iter().map(|c| (&c.name, c.span)), &mut errors);
    for constant in &domain.constants {
        check_type_name(domain, &constant.type_name, constant.span, &mut errors);
    }
    duplicates("predicate", domain.predicates.iter().map(|p| (&p.name, p.span)), &mut errors);
    for predicate in &domain.predicates {
        duplicates(
            "parameter",
            predicate.parameters.iter().map(|p| (&p.name, p.span)),
            &mut errors,
        );
        for parameter in &predicate.parameters {
            check_type_name(domain, &parameter.type_name, parameter.span, &mut errors);
        }
    }
    duplicates("action", domain.actions.iter().map(|a| (&a.name, a.span)), &mut errors);
    let constants = typed_map(&domain.constants);
    for action in &domain.actions {
        duplicates("parameter", action.parameters.iter().map(|p| (&p.name, p.span)), &mut errors);
        for parameter in &action.parameters {
            check_type_name(domain, &parameter.type_name, parameter.span, &mut errors);
        }
        let scope = Scope {
            domain,
            variables: Some((&action.name, typed_map(&action.parameters))),
            objects: &constants,
        };
        for condition in &action.precondition {
            match condition {
                Condition::Atom { atom, .. } => scope.check_atom(atom, &mut errors),
                Condition::Equality { left, right, span, .. } => {
                    scope.term_type(left, *span, &mut errors);
                    scope.term_type(right, *span, &mut errors);
                }
            }
        }
        for atom in action.add.iter().chain(&action.delete) {
            scope.check_atom(atom, &mut errors);
        }
    }
    errors
}

/// Every problem in `problem` read against `domain` (assumed checked).
#[must_use]
pub fn check_problem(domain: &Domain, problem: &Problem) -> Vec<PddlError> {
    let mut errors = Vec::new();
    check_name(&problem.name, problem.span, &mut errors);
    for object in &problem.objects {
        check_name(&object.name, object.span, &mut errors);
    }
    if problem.domain != domain.name {
        errors.push(PddlError::DomainMismatch {
            expected: domain.name.clone(),
            found: problem.domain.clone(),
            span: label(problem.domain_span),
        });
    }
    let names = domain.constants.iter().chain(&problem.objects).map(|o| (&o.name, o.span));
    duplicates("object", names, &mut errors);
    for object in &problem.objects {
        check_type_name(domain, &object.type_name, object.span, &mut errors);
    }
    let mut objects = typed_map(&domain.constants);
    objects.extend(typed_map(&problem.objects));
    let scope = Scope { domain, variables: None, objects: &objects };
    for atom in problem.init.iter().chain(problem.goal.iter().map(|literal| &literal.atom)) {
        scope.check_atom(atom, &mut errors);
    }
    errors
}

/// Names the model declares must read back unchanged: the reader's name syntax, in lower case.
/// (Models parsed from text always pass; models built in memory may not.)
fn check_domain_names(domain: &Domain, errors: &mut Vec<PddlError>) {
    check_name(&domain.name, domain.span, errors);
    for decl in &domain.types {
        check_name(&decl.name, decl.span, errors);
    }
    let typed = domain
        .constants
        .iter()
        .chain(domain.predicates.iter().flat_map(|p| &p.parameters))
        .chain(domain.actions.iter().flat_map(|a| &a.parameters));
    for item in typed {
        check_name(&item.name, item.span, errors);
    }
    for predicate in &domain.predicates {
        check_name(&predicate.name, predicate.span, errors);
    }
    for action in &domain.actions {
        check_name(&action.name, action.span, errors);
    }
}

fn check_name(name: &str, span: Span, errors: &mut Vec<PddlError>) {
    let mut characters = name.chars();
    let valid = characters.next().is_some_and(|first| first.is_ascii_lowercase())
        && characters.all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_' || c == '-');
    if !valid {
        errors.push(PddlError::InvalidName { name: name.to_owned(), span: label(span) });
    }
}

fn typed_map(list: &[Typed]) -> BTreeMap<&str, &str> {
    list.iter().map(|typed| (typed.name.as_str(), typed.type_name.as_str())).collect()
}

fn check_types(domain: &Domain, errors: &mut Vec<PddlError>) {
    duplicates("type", domain.types.iter().map(|t| (&t.name, t.span)), errors);
    for decl in &domain.types {
        check_type_name(domain, &decl.parent, decl.span, errors);
        let mut current = decl.parent.as_str();
        for _ in 0..=domain.types.len() {
            if current == decl.name {
                errors
                    .push(PddlError::TypeCycle { name: decl.name.clone(), span: label(decl.span) });
                break;
            }
            match domain.parent_type(current) {
                Some(parent) => current = parent,
                None => break,
            }
        }
    }
}

fn check_type_name(domain: &Domain, name: &str, span: Span, errors: &mut Vec<PddlError>) {
    if name != OBJECT_TYPE && domain.parent_type(name).is_none() {
        errors.push(PddlError::UnknownType { name: name.to_owned(), span: label(span) });
    }
}

fn duplicates<'a>(
    kind: &'static str,
    names: impl Iterator<Item = (&'a String, Span)>,
    errors: &mut Vec<PddlError>,
) {
    let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
    for (name, span) in names {
        if let Some(first) = seen.get(name.as_str()) {
            errors.push(PddlError::Duplicate {
                kind,
                name: name.clone(),
                span: label(span),
                first: label(*first),
            });
        } else {
            seen.insert(name, span);
        }
    }
}

/// What names mean where an atom is checked: an action's parameters (if inside an action) and the
/// visible constants/objects.
struct Scope<'a> {
    domain: &'a Domain,
    variables: Option<(&'a str, BTreeMap<&'a str, &'a str>)>,
    objects: &'a BTreeMap<&'a str, &'a str>,
}

impl Scope<'_> {
    fn check_atom(&self, atom: &Atom, errors: &mut Vec<PddlError>) {
        let argument_types: Vec<Option<String>> =
            atom.arguments.iter().map(|term| self.term_type(term, atom.span, errors)).collect();
        let Some(predicate) = self.domain.predicate(&atom.predicate) else {
            errors.push(PddlError::UnknownPredicate {
                name: atom.predicate.clone(),
                span: label(atom.span),
            });
            return;
        };
        if predicate.parameters.len() != atom.arguments.len() {
            errors.push(PddlError::Arity {
                predicate: atom.predicate.clone(),
                expected: predicate.parameters.len(),
                found: atom.arguments.len(),
                span: label(atom.span),
            });
            return;
        }
        for ((parameter, found), term) in
            predicate.parameters.iter().zip(&argument_types).zip(&atom.arguments)
        {
            let Some(found) = found else { continue };
            let declared = found == OBJECT_TYPE || self.domain.parent_type(found).is_some();
            if !declared {
                // Already reported as an unknown type where it was declared.
                continue;
            }
            if !self.domain.is_subtype(found, &parameter.type_name) {
                errors.push(PddlError::TypeMismatch {
                    predicate: atom.predicate.clone(),
                    argument: match term {
                        Term::Variable(name) => format!("?{name}"),
                        Term::Constant(name) => name.clone(),
                    },
                    expected: parameter.type_name.clone(),
                    found: found.clone(),
                    span: label(atom.span),
                });
            }
        }
    }

    /// The type of `term`, or `None` (with an error pushed) when it names nothing.
    fn term_type(&self, term: &Term, span: Span, errors: &mut Vec<PddlError>) -> Option<String> {
        match term {
            Term::Variable(name) => match &self.variables {
                Some((action, variables)) => {
                    let found = variables.get(name.as_str()).map(|t| (*t).to_owned());
                    if found.is_none() {
                        errors.push(PddlError::UnboundVariable {
                            name: name.clone(),
                            action: (*action).to_owned(),
                            span: label(span),
                        });
                    }
                    found
                }
                None => {
                    errors.push(PddlError::NonGround {
                        variable: format!("?{name}"),
                        span: label(span),
                    });
                    None
                }
            },
            Term::Constant(name) => {
                let found = self.objects.get(name.as_str()).map(|t| (*t).to_owned());
                if found.is_none() {
                    errors.push(PddlError::UnknownObject { name: name.clone(), span: label(span) });
                }
                found
            }
        }
    }
}
