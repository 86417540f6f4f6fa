//! Typed PDDL diagnostics, each with a stable code, a labelled span and help where the fix is known.
//!
//! Errors hold spans, never the source text; the caller attaches the source when rendering.

use miette::{Diagnostic, SourceSpan};
use thiserror::Error;

use crate::model::Span;

/// What the parser and the checks accept, quoted in "unsupported" help texts.
pub const SUPPORTED_SUBSET: &str = "lamp supports STRIPS with :typing, :equality and \
:negative-preconditions: conjunctions of atoms, negated atoms and (= ?a ?b) in preconditions, \
add and delete effects, and conjunctions of ground literals as goals.";

/// One problem found in a PDDL text or model.
#[derive(Debug, Clone, PartialEq, Eq, Error, Diagnostic)]
pub enum PddlError {
    #[error("syntax error: {message}")]
    #[diagnostic(code(lamp::pddl::syntax))]
    Syntax {
        message: String,
        #[label("{label}")]
        span: SourceSpan,
        label: String,
    },

    #[error("unsupported PDDL feature `{feature}`")]
    #[diagnostic(code(lamp::pddl::unsupported), help("{}", SUPPORTED_SUBSET))]
    Unsupported {
        feature: String,
        #[label("not supported")]
        span: Option<SourceSpan>,
    },

    #[error("unknown predicate `{name}`")]
    #[diagnostic(
        code(lamp::pddl::unknown_predicate),
        help("Declare it in the domain's (:predicates ...) section, or check the spelling.")
    )]
    UnknownPredicate {
        name: String,
        #[label("not declared")]
        span: Option<SourceSpan>,
    },

    #[error("unknown type `{name}`")]
    #[diagnostic(
        code(lamp::pddl::unknown_type),
        help(
            "Declare it in the domain's (:types ...) section; `object` is the only implicit type."
        )
    )]
    UnknownType {
        name: String,
        #[label("not declared")]
        span: Option<SourceSpan>,
    },

    #[error("unknown object or constant `{name}`")]
    #[diagnostic(
        code(lamp::pddl::unknown_object),
        help("Declare it in the problem's (:objects ...) or the domain's (:constants ...).")
    )]
    UnknownObject {
        name: String,
        #[label("not declared")]
        span: Option<SourceSpan>,
    },

    #[error("variable `?{name}` is not a parameter of action `{action}`")]
    #[diagnostic(
        code(lamp::pddl::unbound_variable),
        help("Add it to the action's :parameters, or use one of the declared parameters.")
    )]
    UnboundVariable {
        name: String,
        action: String,
        #[label("unbound")]
        span: Option<SourceSpan>,
    },

    #[error("`{predicate}` takes {expected} argument(s) but {found} were given")]
    #[diagnostic(code(lamp::pddl::arity))]
    Arity {
        predicate: String,
        expected: usize,
        found: usize,
        #[label("{found} argument(s)")]
        span: Option<SourceSpan>,
    },

    #[error("argument `{argument}` of `{predicate}` has type `{found}`, expected `{expected}`")]
    #[diagnostic(
        code(lamp::pddl::type_mismatch),
        help("Each argument's type must be the declared type or one of its subtypes.")
    )]
    TypeMismatch {
        predicate: String,
        argument: String,
        expected: String,
        found: String,
        #[label("wrong type")]
        span: Option<SourceSpan>,
    },

    #[error("{kind} `{name}` is declared twice")]
    #[diagnostic(code(lamp::pddl::duplicate), help("Remove or rename one of the declarations."))]
    Duplicate {
        kind: &'static str,
        name: String,
        #[label("second declaration")]
        span: Option<SourceSpan>,
        #[label("first declared here")]
        first: Option<SourceSpan>,
    },

    #[error("`{name}` is not a valid PDDL name")]
    #[diagnostic(
        code(lamp::pddl::invalid_name),
        help(
            "PDDL names start with a letter and contain only letters, digits, `_` and `-`; \
             lamp stores them in lower case so that written text reads back the same."
        )
    )]
    InvalidName {
        name: String,
        #[label("invalid name")]
        span: Option<SourceSpan>,
    },

    #[error("type `{name}` is its own ancestor")]
    #[diagnostic(code(lamp::pddl::type_cycle), help("Types must form a tree rooted at `object`."))]
    TypeCycle {
        name: String,
        #[label("part of a cycle")]
        span: Option<SourceSpan>,
    },

    #[error("problem is for domain `{found}`, but the domain is `{expected}`")]
    #[diagnostic(code(lamp::pddl::domain_mismatch))]
    DomainMismatch {
        expected: String,
        found: String,
        #[label("expected `{expected}`")]
        span: Option<SourceSpan>,
    },

    #[error("variable `{variable}` appears outside an action")]
    #[diagnostic(
        code(lamp::pddl::non_ground),
        help("Initial states and goals name objects; variables appear only inside actions.")
    )]
    NonGround {
        variable: String,
        #[label("contains a variable")]
        span: Option<SourceSpan>,
    },
}

/// Every problem found in one PDDL text or model; never empty when returned as an error.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{} PDDL error(s)", errors.len())]
pub struct PddlErrors {
    pub errors: Vec<PddlError>,
}

impl Diagnostic for PddlErrors {
    fn code<'a>(&'a self) -> Option<Box<dyn std::fmt::Display + 'a>> {
        Some(Box::new("lamp::pddl::errors"))
    }

    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn Diagnostic> + 'a>> {
        Some(Box::new(self.errors.iter().map(|error| error as &dyn Diagnostic)))
    }
}

/// Converts a model span into a label location; a default (synthetic) span has no location.
pub(crate) fn label(span: Span) -> Option<SourceSpan> {
    if span.start == 0 && span.end == 0 { None } else { Some(span.into()) }
}
