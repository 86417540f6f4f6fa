//! The PDDL subset lamp speaks: STRIPS with `:typing`, `:equality` and `:negative-preconditions`.
//!
//! - [`model`]: domains and problems as plain values;
//! - [`write_domain`] / [`write_problem`]: the deterministic writer the learner emits with;
//! - [`parse_domain`] / [`parse_problem`]: the reader (pest stays inside this crate), with spans;
//! - [`check_domain`] / [`check_problem`]: the semantic checks both paths share;
//! - [`PddlError`]: typed diagnostics with stable `lamp::pddl::*` codes.

mod check;
mod error;
pub mod model;
mod parse;
mod write;

pub use check::{check_domain, check_problem};
pub use error::{PddlError, PddlErrors, SUPPORTED_SUBSET};
pub use model::{
    Action, Atom, Condition, Domain, Literal, OBJECT_TYPE, Predicate, Problem, Requirement, Span,
    Term, TypeDecl, Typed,
};
pub use parse::{parse_domain, parse_problem};
pub use write::{atom_text, write_domain, write_problem};
