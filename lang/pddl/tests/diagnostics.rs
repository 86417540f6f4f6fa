//! Snapshots of the diagnostics a user sees for bad PDDL: source and rendered report together.

use lamp_pddl::{PddlError, PddlErrors, parse_domain, parse_problem};
use miette::{GraphicalReportHandler, GraphicalTheme, NamedSource};

const DOMAIN: &str = "\
(define (domain pick)
  (:requirements :strips :typing :equality)
  (:types can gripper - object)
  (:predicates (holding ?g - gripper ?c - can) (free ?g - gripper) (on-table ?c - can))
  (:action pick
    :parameters (?g - gripper ?c - can)
    :precondition (and (free ?g) (on-table ?c))
    :effect (and (holding ?g ?c) (not (free ?g)) (not (on-table ?c)))))
";

fn render(name: &str, source: &str, errors: PddlErrors) -> String {
    let report =
        miette::Report::new(errors).with_source_code(NamedSource::new(name, source.to_owned()));
    let mut out = String::new();
    GraphicalReportHandler::new_themed(GraphicalTheme::unicode_nocolor())
        .with_width(100)
        .render_report(&mut out, report.as_ref())
        .expect("rendering into a String cannot fail");
    format!("----- SOURCE\n{source}\n----- ERROR\n{out}")
}

fn domain_errors(source: &str) -> PddlErrors {
    parse_domain(source).expect_err("the domain is invalid")
}

fn codes(errors: &PddlErrors) -> Vec<String> {
    use miette::Diagnostic as _;
    errors
        .errors
        .iter()
        .map(|error: &PddlError| error.code().expect("every error has a code").to_string())
        .collect()
}

#[test]
fn valid_domain_is_accepted() {
    parse_domain(DOMAIN).expect("the reference domain is valid");
}

#[test]
fn syntax_error_points_at_the_token() {
    let source = DOMAIN.replace("(free ?g) (on-table", "(free ?g)) (on-table");
    let errors = domain_errors(&source);
    assert_eq!(codes(&errors), ["lamp::pddl::syntax"]);
    insta::assert_snapshot!(render("syntax.pddl", &source, errors));
}

#[test]
fn unknown_predicate_and_arity() {
    let source =
        DOMAIN.replace("(and (free ?g) (on-table ?c))", "(and (free ?g ?c) (on-tabel ?c))");
    let errors = domain_errors(&source);
    assert_eq!(codes(&errors), ["lamp::pddl::arity", "lamp::pddl::unknown_predicate"]);
    insta::assert_snapshot!(render("unknown.pddl", &source, errors));
}

#[test]
fn unbound_variable_and_unknown_type() {
    let source = DOMAIN
        .replace("(?g - gripper ?c - can)", "(?g - gripper ?c - cup)")
        .replace("(not (free ?g))", "(not (free ?h))");
    let errors = domain_errors(&source);
    assert_eq!(codes(&errors), ["lamp::pddl::unknown_type", "lamp::pddl::unbound_variable"]);
    insta::assert_snapshot!(render("unbound.pddl", &source, errors));
}

#[test]
fn duplicate_declarations() {
    let source =
        DOMAIN.replace("(free ?g - gripper)", "(free ?g - gripper) (holding ?g - gripper)");
    let errors = domain_errors(&source);
    assert_eq!(codes(&errors), ["lamp::pddl::duplicate"]);
    insta::assert_snapshot!(render("duplicate.pddl", &source, errors));
}

#[test]
fn conditional_effects_are_unsupported_when_used() {
    let source = DOMAIN.replace("(not (on-table ?c))", "(when (on-table ?c) (not (on-table ?c)))");
    let errors = domain_errors(&source);
    assert_eq!(codes(&errors), ["lamp::pddl::unsupported"]);
    insta::assert_snapshot!(render("when.pddl", &source, errors));
}

#[test]
fn numeric_requirement_is_unsupported_when_declared() {
    let source = DOMAIN.replace(":equality)", ":equality :numeric-fluents)");
    let errors = domain_errors(&source);
    assert_eq!(codes(&errors), ["lamp::pddl::unsupported"]);
    insta::assert_snapshot!(render("fluents.pddl", &source, errors));
}

#[test]
fn disjunction_quantifier_and_either_are_each_reported() {
    let source = DOMAIN
        .replace(
            "(and (free ?g) (on-table ?c))",
            "(and (or (free ?g) (on-table ?c)) (exists (?d - can) (on-table ?d)))",
        )
        .replace("can gripper - object", "can gripper - (either object)");
    let errors = domain_errors(&source);
    assert_eq!(
        codes(&errors),
        ["lamp::pddl::unsupported", "lamp::pddl::unsupported", "lamp::pddl::unsupported"]
    );
    let features: Vec<_> = errors
        .errors
        .iter()
        .map(|error| match error {
            PddlError::Unsupported { feature, .. } => feature.clone(),
            other => panic!("unexpected {other:?}"),
        })
        .collect();
    assert_eq!(features, ["either", "or", "exists"]);
}

#[test]
fn keyword_prefixed_predicate_names_are_atoms() {
    let source = DOMAIN.replace("free", "notfree").replace("on-table", "order");
    parse_domain(&source).expect("`notfree` and `order` are ordinary names");
}

#[test]
fn problem_errors_are_checked_against_the_domain() {
    let domain = parse_domain(DOMAIN).expect("valid");
    let source = "\
(define (problem p1) (:domain pick)
  (:objects g1 - gripper c1 c2 - can c1 - can)
  (:init (free g1) (on-table c1) (on-table g1) (on-table c3))
  (:goal (and (holding g1 c1) (not (on-table ?x)))))
";
    let errors = parse_problem(source, &domain).expect_err("the problem is invalid");
    assert_eq!(
        codes(&errors),
        [
            "lamp::pddl::duplicate",
            "lamp::pddl::type_mismatch",
            "lamp::pddl::unknown_object",
            "lamp::pddl::non_ground"
        ]
    );
    insta::assert_snapshot!(render("problem.pddl", source, errors));
}

#[test]
fn problem_for_another_domain_is_rejected() {
    let domain = parse_domain(DOMAIN).expect("valid");
    let source = "(define (problem p) (:domain other) (:objects) (:init) (:goal (and)))";
    let errors = parse_problem(source, &domain).expect_err("wrong domain");
    assert_eq!(codes(&errors), ["lamp::pddl::domain_mismatch"]);
}

#[test]
fn names_and_keywords_are_case_insensitive() {
    let source =
        DOMAIN.replace("(:action pick", "(:ACTION Pick").replace("(and (free", "(AND (Free");
    let domain = parse_domain(&source).expect("keywords are case-insensitive");
    assert!(domain.action("pick").is_some());
}
