//! The plan validator names the first failing step and condition.

mod common;

use common::load;
use lamp_planner::{Plan, ValidationError, validate};

fn plan(text: &str) -> Plan {
    Plan::parse(text).expect("well-formed plan text")
}

const SUSSMAN_OPTIMAL: &str = "\
; an optimal plan
(unstack c a)
(put-down c)
(pick-up b)
(stack b c)
(pick-up a)
(stack a b)
";

#[test]
fn optimal_sussman_plan_is_valid() {
    let (domain, problem) = load("blocksworld", "blocksworld-sussman");
    let validated = validate(&domain, &problem, &plan(SUSSMAN_OPTIMAL)).expect("valid plan");
    assert!(validated.final_state.contains(&("on".to_owned(), vec!["a".into(), "b".into()])));
}

#[test]
fn first_failing_precondition_is_named() {
    let (domain, problem) = load("blocksworld", "blocksworld-sussman");
    let broken = SUSSMAN_OPTIMAL.replace("(put-down c)\n", "");
    let error =
        validate(&domain, &problem, &plan(&broken)).expect_err("pick-up b needs a free hand");
    assert_eq!(
        error,
        ValidationError::Precondition {
            step: 2,
            action: "(pick-up b)".into(),
            condition: "(handempty)".into()
        }
    );
    assert_eq!(error.to_string(), "step 2 (pick-up b): precondition (handempty) does not hold");
}

#[test]
fn unreached_goal_is_named() {
    let (domain, problem) = load("blocksworld", "blocksworld-sussman");
    let short = "(unstack c a)\n(put-down c)\n(pick-up b)\n(stack b c)\n";
    let error = validate(&domain, &problem, &plan(short)).expect_err("a is not on b");
    assert_eq!(error, ValidationError::Goal { literal: "(on a b)".into() });
}

#[test]
fn negative_preconditions_and_goals_are_checked() {
    let (domain, problem) = load("lights", "lights-two");
    let error = validate(&domain, &problem, &plan("(switch-on l1)\n(switch-on l1)\n"))
        .expect_err("l1 is already on");
    assert_eq!(
        error,
        ValidationError::Precondition {
            step: 2,
            action: "(switch-on l1)".into(),
            condition: "(not (on l1))".into()
        }
    );
    let error = validate(&domain, &problem, &plan("(switch-on l3)\n")).expect_err("l3 is blown");
    assert!(matches!(error, ValidationError::Precondition { step: 1, .. }), "{error}");
}

#[test]
fn inequality_is_checked() {
    let (domain, problem) = load("gripper", "gripper-4");
    let error = validate(&domain, &problem, &plan("(move rooma rooma)\n")).expect_err("same room");
    assert_eq!(
        error,
        ValidationError::Precondition {
            step: 1,
            action: "(move rooma rooma)".into(),
            condition: "(not (= rooma rooma))".into()
        }
    );
}

#[test]
fn bad_steps_are_reported() {
    let (domain, problem) = load("gripper", "gripper-4");
    let cases = [
        ("(fly rooma roomb)", "step 1 (fly rooma roomb): no such action"),
        ("(move rooma)", "step 1 (move rooma): expects 2 argument(s), got 1"),
        (
            "(move rooma kitchen)",
            "step 1 (move rooma kitchen): `kitchen` is not an object of this problem",
        ),
        (
            "(move rooma ball1)",
            "step 1 (move rooma ball1): `ball1` has type `ball`, parameter wants `room`",
        ),
    ];
    for (text, message) in cases {
        let error = validate(&domain, &problem, &plan(text)).expect_err(text);
        assert_eq!(error.to_string(), message);
    }
}

#[test]
fn plan_text_round_trips_and_rejects_garbage() {
    let parsed = plan(SUSSMAN_OPTIMAL);
    assert_eq!(parsed.len(), 6);
    assert_eq!(Plan::parse(&parsed.to_string()).expect("own output parses"), parsed);
    assert_eq!(plan("(UNSTACK C A)\n").steps[0].action, "unstack");
    let error = Plan::parse("(unstack c a)\nunstack c a\n").expect_err("no parentheses");
    assert_eq!(error.line, 2);
}
