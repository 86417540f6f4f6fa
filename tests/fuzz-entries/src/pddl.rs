//! The PDDL reader: `lamp_pddl::parse_domain` and `parse_problem` on arbitrary text.
//!
//! The input is a domain, optionally followed by a NUL byte and a problem, which is read against
//! the domain when the domain parses. What parses is written back with the learner's writer, and
//! that text must parse again and write the same text (the runtime reads domains the build
//! wrote, and hand-edited ones).

use lamp_pddl::{Domain, PddlErrors, parse_domain, parse_problem, write_domain, write_problem};

use crate::{check_diagnostic, two_texts};

/// Parses the domain and problem of `data` (see the module documentation for the layout).
///
/// # Panics
/// When the reader panics, reports a diagnostic whose label lies outside its text, or accepts a
/// domain or problem whose written form does not read back to the same text.
pub fn pddl(data: &[u8]) {
    let (domain_text, problem_text) = two_texts(data);
    let domain = match parse_domain(&domain_text) {
        Ok(domain) => domain,
        Err(errors) => return check_errors(errors, &domain_text, "the domain"),
    };
    let written = write_domain(&domain);
    let reread = parse_domain(&written).unwrap_or_else(|errors| {
        panic!("the written form of a parsed domain does not parse: {errors:?}\n{written}")
    });
    assert_eq!(write_domain(&reread), written, "writing a domain read back changes it");
    if let Some(problem_text) = problem_text {
        problem(&problem_text, &domain, &reread);
    }
}

fn problem(text: &str, domain: &Domain, reread_domain: &Domain) {
    let problem = match parse_problem(text, domain) {
        Ok(problem) => problem,
        Err(errors) => return check_errors(errors, text, "the problem"),
    };
    let written = write_problem(&problem);
    let reread = parse_problem(&written, reread_domain).unwrap_or_else(|errors| {
        panic!("the written form of a parsed problem does not parse: {errors:?}\n{written}")
    });
    assert_eq!(write_problem(&reread), written, "writing a problem read back changes it");
}

fn check_errors(errors: PddlErrors, text: &str, what: &str) {
    assert!(!errors.errors.is_empty(), "{what} is refused without an error");
    for (index, error) in errors.errors.iter().enumerate() {
        check_diagnostic(error, text, what, index + 1);
    }
    // The whole list, as `lampc` shows it, first.
    let report = miette::Report::new(errors).with_source_code(text.to_string());
    check_diagnostic(report.as_ref(), text, what, 0);
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOMAIN: &str = "(define (domain d) (:requirements :strips :typing)
  (:types can surface)
  (:predicates (on ?c - can ?s - surface) (free ?c - can))
  (:action put :parameters (?c - can ?s - surface)
    :precondition (and (free ?c) (not (on ?c ?s)))
    :effect (and (on ?c ?s) (not (free ?c)))))";

    const PROBLEM: &str = "(define (problem p) (:domain d)
  (:objects c1 - can s1 - surface)
  (:init (free c1))
  (:goal (and (on c1 s1))))";

    #[test]
    fn a_domain_and_problem_read_and_write_back() {
        let domain = parse_domain(DOMAIN).expect("the test domain parses");
        assert_eq!(domain.actions.len(), 1);
        parse_problem(PROBLEM, &domain).expect("the test problem parses");
        pddl(format!("{DOMAIN}\0{PROBLEM}").as_bytes());
    }

    #[test]
    fn broken_texts_are_errors_with_spans_inside_them() {
        pddl(b"(define (domain");
        pddl(format!("{DOMAIN}\0(define (problem p) (:domain d) (:init (on c9 s1)))").as_bytes());
        pddl("(define (domain é) ü".as_bytes());
    }
}
