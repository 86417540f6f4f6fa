//! Oracle: the plugin runs the real Fast Downward (pip `up-fast-downward`) and K* (pip
//! `kstar-planner`) and agrees with lamp-planner on which tasks are solvable; every plan it returns
//! validates. Skips with a message when a package is missing, fails under `LAMP_REQUIRE_ORACLES=1`.

mod common;

use common::{is_valid, planner_installed, request};
use lamp_pddl::{parse_domain, parse_problem};
use lamp_planner::{Algorithm, Budget, PlannerOutput, Status};
use lamp_planner_external::{Engine, ExternalOptions, ExternalPlanner};
use lamp_plugin_api::{MinimalHost, PlanStatus, Planner};

const SOLVABLE: [(&str, &str); 4] = [
    ("gripper", "gripper-4"),
    ("logistics", "logistics-two-cities"),
    ("packing", "packing-4"),
    ("cafe", "cafe-2"),
];

/// Proved unsolvable by the translator (static facts) and by search (mutually exclusive goals).
const UNSOLVABLE: [(&str, &str); 2] =
    [("logistics", "logistics-no-airport"), ("lights", "lights-paint-and-varnish")];

/// lamp-planner's lazy GBFS on the same task.
fn lamp_planner(domain: &str, problem: &str) -> PlannerOutput {
    let task = request(domain, problem);
    let domain = parse_domain(&task.domain).expect("the domain parses");
    let problem = parse_problem(&task.problem, &domain).expect("the problem parses");
    lamp_planner::plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("plans")
}

#[test]
fn fast_downward_solves_what_lamp_planner_solves_with_valid_plans() {
    if !planner_installed(Engine::FastDownward, "up-fast-downward") {
        return;
    }
    let mut planner = ExternalPlanner::new(ExternalOptions::default());
    for (domain, problem) in SOLVABLE {
        let task = request(domain, problem);
        let response = planner.plan(&task, &MinimalHost).expect("Fast Downward answers");
        assert_eq!(response.status, PlanStatus::Solved, "{problem}");
        assert_eq!(response.plans.len(), 1, "{problem}");
        assert!(is_valid(&task, &response.plans[0]), "{problem}: {:?}", response.plans[0]);
        assert_eq!(lamp_planner(domain, problem).status, Status::Solved, "{problem}: agreed");
    }
}

#[test]
fn fast_downward_and_lamp_planner_agree_on_unsolvable_tasks() {
    if !planner_installed(Engine::FastDownward, "up-fast-downward") {
        return;
    }
    let mut planner = ExternalPlanner::new(ExternalOptions::default());
    for (domain, problem) in UNSOLVABLE {
        let response = planner.plan(&request(domain, problem), &MinimalHost).expect("answers");
        assert!(
            matches!(&response.status, PlanStatus::Unsolvable { reason } if reason.contains("Fast Downward")),
            "{problem}: {:?}",
            response.status
        );
        assert!(response.plans.is_empty());
        assert!(matches!(lamp_planner(domain, problem).status, Status::Unsolvable(_)), "{problem}");
    }
}

#[test]
fn k_star_returns_k_distinct_valid_plans_cheapest_first() {
    if !planner_installed(Engine::KStar, "kstar-planner") {
        return;
    }
    let mut planner = ExternalPlanner::new(ExternalOptions::default());
    let mut task = request("gripper", "gripper-4");
    task.plan_count = 5;
    let response = planner.plan(&task, &MinimalHost).expect("K* answers");
    assert_eq!(response.status, PlanStatus::Solved);
    assert_eq!(response.plans.len(), 5);
    for (index, plan) in response.plans.iter().enumerate() {
        assert!(is_valid(&task, plan), "plan {index}");
        assert!(!response.plans[..index].contains(plan), "plan {index} repeats an earlier one");
    }
    let lengths: Vec<usize> = response.plans.iter().map(|plan| plan.steps.len()).collect();
    assert!(lengths.windows(2).all(|pair| pair[0] <= pair[1]), "cheapest first: {lengths:?}");
    // Gripper with four balls and two hands needs 11 steps at least.
    assert_eq!(lengths[0], 11);
}

#[test]
fn k_star_finds_no_plan_for_an_unsolvable_task() {
    if !planner_installed(Engine::KStar, "kstar-planner") {
        return;
    }
    let mut planner = ExternalPlanner::new(ExternalOptions::default());
    let mut task = request("lights", "lights-paint-and-varnish");
    task.plan_count = 3;
    let response = planner.plan(&task, &MinimalHost).expect("K* answers");
    assert!(matches!(response.status, PlanStatus::Unsolvable { .. }), "{:?}", response.status);
    assert!(response.plans.is_empty());
}
