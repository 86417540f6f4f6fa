//! The built-in planners as plugins: linked statically and through the C ABI in process, checked
//! with lamp-planner's validator and against known plan lengths.

use lamp_pddl::{parse_domain, parse_problem};
use lamp_planner::validate;
use lamp_planner_builtin::{BuiltinAlgorithm, BuiltinPlanner};
use lamp_plugin_api::{
    MinimalHost, Plan, PlanBudget, PlanRequest, PlanResponse, PlanStatus, Planner, PluginError,
};
use lamp_plugin_host::{LoadError, PluginLibrary};
use lamp_plugin_sdk::{Descriptor, PluginFactory, in_process_planner};

const DOMAIN: &str = "(define (domain blocksworld)
  (:requirements :strips :typing)
  (:types block)
  (:predicates (on ?x - block ?y - block) (ontable ?x - block) (clear ?x - block)
               (handempty) (holding ?x - block))
  (:action pick-up
    :parameters (?x - block)
    :precondition (and (clear ?x) (ontable ?x) (handempty))
    :effect (and (holding ?x) (not (ontable ?x)) (not (clear ?x)) (not (handempty))))
  (:action put-down
    :parameters (?x - block)
    :precondition (holding ?x)
    :effect (and (not (holding ?x)) (clear ?x) (handempty) (ontable ?x)))
  (:action stack
    :parameters (?x - block ?y - block)
    :precondition (and (holding ?x) (clear ?y))
    :effect (and (not (holding ?x)) (not (clear ?y)) (clear ?x) (handempty) (on ?x ?y)))
  (:action unstack
    :parameters (?x - block ?y - block)
    :precondition (and (on ?x ?y) (clear ?x) (handempty))
    :effect (and (holding ?x) (clear ?y) (not (clear ?x)) (not (handempty)) (not (on ?x ?y)))))";

/// The Sussman anomaly; its optimal plan has 6 steps.
const SUSSMAN: &str = "(define (problem sussman) (:domain blocksworld)
  (:objects a b c - block)
  (:init (on c a) (ontable a) (ontable b) (clear c) (clear b) (handempty))
  (:goal (and (on a b) (on b c))))";

/// A goal that can never hold: stacking a block on itself needs it held and clear at once. Relaxed
/// reachability cannot see that, so the search exhausts the reachable states.
const IMPOSSIBLE: &str = "(define (problem impossible) (:domain blocksworld)
  (:objects a - block)
  (:init (ontable a) (clear a) (handempty))
  (:goal (and (on a a))))";

const SUSSMAN_OPTIMAL_LENGTH: usize = 6;

/// Four blocks on the table, one of them to be stacked: many loop-free plans, the shortest of
/// length 2.
const ONE_STACK: &str = "(define (problem one-stack) (:domain blocksworld)
  (:objects a b c d - block)
  (:init (ontable a) (ontable b) (ontable c) (ontable d) (clear a) (clear b) (clear c) (clear d)
         (handempty))
  (:goal (and (on a b))))";

fn assert_valid(plan: &Plan, problem_text: &str) {
    let domain = parse_domain(DOMAIN).expect("the test domain parses");
    let problem = parse_problem(problem_text, &domain).expect("the test problem parses");
    let plan = lamp_planner::Plan {
        steps: plan
            .steps
            .iter()
            .map(|step| lamp_planner::PlanStep {
                action: step.action.clone(),
                arguments: step.arguments.clone(),
            })
            .collect(),
    };
    if let Err(error) = validate(&domain, &problem, &plan) {
        panic!("invalid plan: {error}");
    }
}

fn through_abi(config: &[u8]) -> Box<dyn Planner> {
    let descriptor = Descriptor { name: "lamp-builtin-planner", version: "test", description: "" };
    let library =
        PluginLibrary::from_trusted_entry(in_process_planner::<BuiltinPlanner>(descriptor))
            .expect("the SDK builds a valid entry");
    library.create_planner(config).expect("a known algorithm")
}

fn plan(planner: &mut dyn Planner, request: &PlanRequest) -> PlanResponse {
    planner.plan(request, &MinimalHost).expect("the planner answers")
}

#[test]
fn gbfs_ff_solves_the_sussman_anomaly_alike_statically_and_through_the_abi() {
    let request = PlanRequest::new(DOMAIN, SUSSMAN);
    let mut direct = BuiltinPlanner::new(BuiltinAlgorithm::GbfsFf);
    let response = plan(&mut direct, &request);
    assert_eq!(response.status, PlanStatus::Solved);
    assert_eq!(response.plans.len(), 1);
    assert_valid(&response.plans[0], SUSSMAN);
    assert!(response.plans[0].steps.len() >= SUSSMAN_OPTIMAL_LENGTH);
    assert_eq!(plan(through_abi(br#"{"algorithm": "gbfs-ff"}"#).as_mut(), &request), response);
    assert_eq!(plan(through_abi(b"").as_mut(), &request), response);
}

#[test]
fn topk_returns_distinct_valid_plans_alike_statically_and_through_the_abi() {
    let mut request = PlanRequest::new(DOMAIN, ONE_STACK);
    request.plan_count = 5;
    let mut direct = BuiltinPlanner::create(br#"{"algorithm": "topk"}"#).unwrap();
    assert_eq!(direct.algorithm(), BuiltinAlgorithm::TopK);
    let response = plan(&mut direct, &request);
    assert_eq!(response.status, PlanStatus::Solved);
    assert_eq!(response.plans.len(), 5);
    for (index, candidate) in response.plans.iter().enumerate() {
        assert_valid(candidate, ONE_STACK);
        assert!(
            !response.plans[..index].contains(candidate),
            "plan {index} repeats an earlier one"
        );
    }
    // The first of the top k is the single GBFS plan, here the shortest one.
    let single = plan(
        &mut BuiltinPlanner::new(BuiltinAlgorithm::GbfsFf),
        &PlanRequest::new(DOMAIN, ONE_STACK),
    );
    assert_eq!(single.plans[0], response.plans[0]);
    assert_eq!(response.plans[0].steps.len(), 2);
    assert_eq!(plan(through_abi(br#"{"algorithm": "topk"}"#).as_mut(), &request), response);
}

#[test]
fn unsolvable_failed_and_budget_statuses_cross_the_abi() {
    let mut planner = through_abi(br#"{"algorithm": "gbfs-ff"}"#);
    let response = plan(planner.as_mut(), &PlanRequest::new(DOMAIN, IMPOSSIBLE));
    assert_eq!(
        response.status,
        PlanStatus::Unsolvable { reason: "the search exhausted every reachable state".into() }
    );
    assert!(response.plans.is_empty());

    let response = plan(planner.as_mut(), &PlanRequest::new(DOMAIN, "(define (problem broken"));
    let PlanStatus::Failed { message } = response.status else { panic!("{:?}", response.status) };
    assert!(message.starts_with("the problem is not valid PDDL"), "{message}");

    let mut request = PlanRequest::new(DOMAIN, SUSSMAN);
    request.budget = PlanBudget { max_expansions: Some(1), time_limit: None };
    assert_eq!(plan(planner.as_mut(), &request).status, PlanStatus::BudgetExhausted);
}

#[test]
fn the_grounding_limit_is_an_option_and_its_failure_names_it() {
    // The Sussman anomaly (three blocks) grounds more than 10 operators and fewer than 100.
    let request = PlanRequest::new(DOMAIN, SUSSMAN);
    for config in [&br#"{"operators": 10}"#[..], br#"{"algorithm": "topk", "operators": 10}"#] {
        let response = plan(through_abi(config).as_mut(), &request);
        let PlanStatus::Failed { message } = response.status else {
            panic!("{:?}", response.status)
        };
        assert!(message.starts_with("grounding exceeds the limit of 10 operators"), "{message}");
        assert!(message.contains("`operators` option"), "{message}");
    }
    let roomy = plan(through_abi(br#"{"operators": 100}"#).as_mut(), &request);
    assert_eq!(roomy.status, PlanStatus::Solved);
    assert!(BuiltinPlanner::create(br#"{"operators": 2.5}"#).is_err());
}

#[test]
fn an_unknown_algorithm_key_or_document_is_refused_at_creation() {
    assert_eq!(
        BuiltinPlanner::create(br#"{"algorithm": "astar"}"#).unwrap_err(),
        PluginError::invalid_request(
            "option `algorithm`: unknown algorithm `astar`; expected `gbfs-ff` or `topk`"
        )
    );
    assert_eq!(
        BuiltinPlanner::create(br#"{"algorithm": "topk", "weight": 2}"#).unwrap_err(),
        PluginError::invalid_request("unknown option `weight`; it reads `algorithm`, `operators`")
    );
    // A bare word is not a JSON document.
    assert!(matches!(
        BuiltinPlanner::create(b"topk"),
        Err(PluginError::InvalidRequest { message }) if message.starts_with("the configuration is not JSON")
    ));
    let descriptor = Descriptor { name: "lamp-builtin-planner", version: "test", description: "" };
    let library =
        PluginLibrary::from_trusted_entry(in_process_planner::<BuiltinPlanner>(descriptor))
            .unwrap();
    assert!(matches!(
        library.create_planner(br#"{"algorithm": "astar"}"#),
        Err(LoadError::Create { .. })
    ));
}
