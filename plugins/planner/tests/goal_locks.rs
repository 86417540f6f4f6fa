//! Grounding drops the operators that would lose a goal for good: those that use up a fact every
//! achiever of a goal needs and uses up, without achieving it.

mod common;

use lamp_pddl::{parse_domain, parse_problem};
use lamp_planner::{Algorithm, Budget, GroundTask, Status, ground, plan};

use common::assert_valid_loop_free;

/// Objects put on markers, each marker taking one object ever; `take` (when `reversible`) lifts
/// an object off its marker again.
fn markers(reversible: bool) -> String {
    let take = if reversible {
        "(:action take :parameters (?o - obj ?m - marker)
           :precondition (and (on ?m ?o))
           :effect (and (clear ?m) (loose ?o) (not (on ?m ?o))))"
    } else {
        ""
    };
    format!(
        "(define (domain markers)
           (:requirements :strips :typing)
           (:types obj marker)
           (:predicates (on ?m - marker ?o - obj) (clear ?m - marker) (loose ?o - obj))
           (:action put :parameters (?o - obj ?m - marker)
             :precondition (and (clear ?m) (loose ?o))
             :effect (and (on ?m ?o) (not (clear ?m)) (not (loose ?o))))
           {take})"
    )
}

fn problem(init: &str, goal: &str) -> String {
    format!(
        "(define (problem three) (:domain markers)
           (:objects o1 o2 o3 - obj m1 m2 m3 - marker)
           (:init {init})
           (:goal (and {goal})))"
    )
}

const LOOSE: &str = "(clear m1) (clear m2) (clear m3) (loose o1) (loose o2) (loose o3)";

fn puts(task: &GroundTask) -> Vec<String> {
    task.operators.iter().filter(|o| o.action == "put").map(ToString::to_string).collect()
}

#[test]
fn putting_an_object_on_another_ones_marker_is_not_grounded() {
    let domain = parse_domain(&markers(false)).expect("valid domain");
    let problem =
        parse_problem(&problem(LOOSE, "(on m1 o1) (on m2 o2)"), &domain).expect("valid problem");
    let task = ground(&domain, &problem, usize::MAX).expect("grounds");
    // o3 and m3 are in no goal: o3 may still go on m3, and nothing else on m1 or m2, and
    // neither o1 nor o2 anywhere but on its own marker.
    assert_eq!(puts(&task), ["(put o1 m1)", "(put o2 m2)", "(put o3 m3)"]);
    let output = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("plans");
    assert_eq!(output.status, Status::Solved);
    assert_valid_loop_free(&domain, &problem, &output.plans[0]);
}

#[test]
fn a_fact_that_some_action_gives_back_locks_nothing() {
    let domain = parse_domain(&markers(true)).expect("valid domain");
    let problem =
        parse_problem(&problem(LOOSE, "(on m1 o1) (on m2 o2)"), &domain).expect("valid problem");
    let task = ground(&domain, &problem, usize::MAX).expect("grounds");
    assert_eq!(puts(&task).len(), 9, "{:?}", puts(&task));
}

#[test]
fn a_goal_true_at_the_start_locks_nothing() {
    let domain = parse_domain(&markers(false)).expect("valid domain");
    // o1 is on m1 already (and m1 is, oddly, still clear): the goal holds without its achiever,
    // so using up m1's clear fact loses nothing.
    let init = format!("{LOOSE} (on m1 o1)");
    let problem = parse_problem(&problem(&init, "(on m1 o1)"), &domain).expect("valid problem");
    let task = ground(&domain, &problem, usize::MAX).expect("grounds");
    assert_eq!(puts(&task).len(), 9, "{:?}", puts(&task));
}

#[test]
fn the_plans_left_are_the_goal_puts_in_every_order() {
    // Every plan of the unpruned task puts each object on its own marker, in some order: top-k on
    // the pruned task finds all six, each valid against the domain itself.
    let domain = parse_domain(&markers(false)).expect("valid domain");
    let problem = parse_problem(&problem(LOOSE, "(on m1 o1) (on m2 o2) (on m3 o3)"), &domain)
        .expect("valid problem");
    let output =
        plan(&domain, &problem, Algorithm::TopK { k: 100 }, &Budget::default()).expect("plans");
    assert_eq!(output.status, Status::Solved);
    // Three puts in any order.
    assert_eq!(output.plans.len(), 6);
    for found in &output.plans {
        assert_valid_loop_free(&domain, &problem, found);
    }
}
