//! The planners on known domains: plans validate, lengths respect the known optimum, unsolvable
//! tasks are reported with the right reason, budgets are honoured, top-k gives distinct plans.

mod common;

use common::{assert_valid_loop_free, load};
use lamp_planner::{
    Algorithm, Budget, GroundTask, State, Status, Unsolvable, ground, plan, plan_until,
};

/// (domain, problem, optimal length confirmed with Fast Downward's `astar(blind())`).
const KNOWN: &[(&str, &str, usize)] = &[
    ("blocksworld", "blocksworld-sussman", 6),
    ("blocksworld", "blocksworld-reverse5", 10),
    ("gripper", "gripper-4", 11),
    ("logistics", "logistics-two-cities", 9),
    ("lights", "lights-two", 2),
];

#[test]
fn gbfs_plans_validate_and_are_no_shorter_than_optimal() {
    for &(domain_name, problem_name, optimal) in KNOWN {
        let (domain, problem) = load(domain_name, problem_name);
        let output = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("valid");
        assert_eq!(output.status, Status::Solved, "{problem_name}");
        assert_eq!(output.plans.len(), 1);
        let found = &output.plans[0];
        assert_valid_loop_free(&domain, &problem, found);
        assert!(found.len() >= optimal, "{problem_name}: {} < optimum {optimal}", found.len());
        // Greedy search is not optimal, but on these small tasks it should not wander far.
        assert!(found.len() <= 2 * optimal, "{problem_name}: {} steps\n{found}", found.len());
    }
}

#[test]
fn paper_packing_four_cans_solves() {
    let (domain, problem) = load("packing", "packing-4");
    let output = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("valid");
    assert_eq!(output.status, Status::Solved);
    let found = &output.plans[0];
    assert_valid_loop_free(&domain, &problem, found);
    // Each can needs approach, grasp and place (3 steps), and all but the last a release and a
    // retreat before the next approach (2 more).
    assert!(found.len() >= 18, "{found}");
}

#[test]
fn paper_cafe_eighteen_cans_solves() {
    let (domain, problem) = load("cafe", "cafe-18");
    let output = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("valid");
    assert_eq!(output.status, Status::Solved, "{:?}", output.statistics);
    let found = &output.plans[0];
    assert_valid_loop_free(&domain, &problem, found);
    assert!(found.len() >= 18 * 5, "{} steps", found.len());
}

#[test]
fn relaxed_unreachable_goal_is_unsolvable_without_search() {
    let (domain, problem) = load("logistics", "logistics-no-airport");
    let output = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("valid");
    assert_eq!(
        output.status,
        Status::Unsolvable(Unsolvable::GoalUnreachable { literal: "(at pkg depot2)".into() })
    );
    assert_eq!(output.statistics.expanded, 0);
    assert!(output.plans.is_empty());
}

#[test]
fn static_negative_precondition_makes_goal_unreachable() {
    let (domain, problem) = load("lights", "lights-blown");
    let output = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("valid");
    assert_eq!(
        output.status,
        Status::Unsolvable(Unsolvable::GoalUnreachable { literal: "(on l1)".into() })
    );
}

#[test]
fn mutually_exclusive_goals_are_proved_unsolvable_by_search() {
    let (domain, problem) = load("lights", "lights-paint-and-varnish");
    let output = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("valid");
    assert_eq!(output.status, Status::Unsolvable(Unsolvable::SearchSpaceExhausted));
    // The relaxation ignores the negative preconditions that make painted and varnished
    // exclusive, but nothing undoes either: once the light is painted, varnishing it is lost for
    // good, and the other way round. Of the six states (the light on or off, times unpainted,
    // painted or varnished), the four painted or varnished ones are recognised dead ends.
    assert_eq!(output.statistics.expanded, 6);
    assert_eq!(output.statistics.dead_ends, 4);
}

#[test]
fn budget_exhaustion_is_reported() {
    let (domain, problem) = load("gripper", "gripper-20");
    let output = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::expansions(5)).expect("valid");
    assert_eq!(output.status, Status::BudgetExhausted);
    assert!(output.plans.is_empty());
    assert_eq!(output.statistics.expanded, 5);
    let output = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("valid");
    assert_eq!(output.status, Status::Solved);
    assert_valid_loop_free(&domain, &problem, &output.plans[0]);
}

#[test]
fn time_limit_is_honoured() {
    let (domain, problem) = load("gripper", "gripper-20");
    let budget = Budget { time_limit: Some(std::time::Duration::ZERO), ..Budget::default() };
    let output = plan(&domain, &problem, Algorithm::GbfsFf, &budget).expect("valid");
    assert_eq!(output.status, Status::BudgetExhausted);
    assert_eq!(output.statistics.expanded, 0);
}

#[test]
fn a_stop_request_ends_grounding_and_search() {
    let (domain, problem) = load("cafe", "cafe-18");
    let budget = Budget::default();
    // Asked to stop at once: grounding gives up at its first check.
    let error = plan_until(&domain, &problem, Algorithm::GbfsFf, &budget, &|| true)
        .expect_err("stopped while grounding");
    assert!(matches!(error, lamp_planner::PlannerError::Stopped), "{error:?}");
    // Asked to stop once grounding is done: the search ends as out of budget at its first check.
    let task = ground(&domain, &problem, budget.max_operators).expect("grounds");
    let output = lamp_planner::top_k_until(&task, 1, &budget, &|| true);
    assert_eq!(output.status, Status::BudgetExhausted);
    assert!(output.plans.is_empty());
    // Never asked to stop: the same as without the request.
    let free = plan_until(&domain, &problem, Algorithm::GbfsFf, &budget, &|| false).expect("plans");
    assert_eq!(free, plan(&domain, &problem, Algorithm::GbfsFf, &budget).expect("plans"));
}

#[test]
fn too_many_operators_is_an_error() {
    let (domain, problem) = load("gripper", "gripper-20");
    let budget = Budget { max_operators: 10, ..Budget::default() };
    let error = plan(&domain, &problem, Algorithm::GbfsFf, &budget).expect_err("limit");
    assert!(matches!(error, lamp_planner::PlannerError::TooManyOperators { limit: 10 }));
}

#[test]
fn top_k_gives_distinct_valid_loop_free_plans() {
    for (domain_name, problem_name) in
        [("gripper", "gripper-4"), ("logistics", "logistics-two-cities")]
    {
        let (domain, problem) = load(domain_name, problem_name);
        let output =
            plan(&domain, &problem, Algorithm::TopK { k: 10 }, &Budget::default()).expect("valid");
        assert_eq!(output.status, Status::Solved, "{problem_name}");
        assert_eq!(output.plans.len(), 10, "{problem_name}");
        for found in &output.plans {
            assert_valid_loop_free(&domain, &problem, found);
        }
        let mut distinct = output.plans.clone();
        distinct.sort();
        distinct.dedup();
        assert_eq!(distinct.len(), 10, "{problem_name}: plans repeat");
        // The first plan is the plain GBFS plan.
        let single = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("valid");
        assert_eq!(single.plans[0], output.plans[0]);
    }
}

#[test]
fn top_k_stops_when_every_loop_free_plan_is_found() {
    let (domain, problem) = load("lights", "lights-two");
    let output =
        plan(&domain, &problem, Algorithm::TopK { k: 5 }, &Budget::default()).expect("valid");
    assert_eq!(output.status, Status::Solved);
    let texts: Vec<String> = output.plans.iter().map(ToString::to_string).collect();
    assert_eq!(texts.len(), 2, "{texts:?}");
    assert!(texts.contains(&"(switch-on l1)\n(switch-on l2)\n".to_owned()), "{texts:?}");
    assert!(texts.contains(&"(switch-on l2)\n(switch-on l1)\n".to_owned()), "{texts:?}");
}

/// Counts the loop-free plans (paths from the initial state that never repeat a state and end in a
/// goal state) by exhaustive depth-first enumeration.
fn count_loop_free_plans(task: &GroundTask, state: &State, path: &mut Vec<State>) -> usize {
    let mut total = usize::from(state.satisfies_goal(task));
    for operator in &task.operators {
        if state.applicable(operator) {
            let next = state.apply(operator);
            if !path.contains(&next) {
                path.push(next.clone());
                total += count_loop_free_plans(task, &next, path);
                path.pop();
            }
        }
    }
    total
}

#[test]
fn top_k_enumerates_exactly_the_loop_free_plans() {
    let cases = [
        ("blocksworld", "blocksworld-sussman", 1),
        ("blocksworld", "blocksworld-tower3", 1),
        ("lights", "lights-two", 2),
        ("lights", "lights-three", 18),
    ];
    for (domain_name, problem_name, expected) in cases {
        let (domain, problem) = load(domain_name, problem_name);
        let task = ground(&domain, &problem, usize::MAX).expect("valid");
        let initial = State::from_facts(task.fact_count(), &task.initial);
        let brute_force = count_loop_free_plans(&task, &initial, &mut vec![initial.clone()]);
        assert_eq!(brute_force, expected, "{problem_name}: enumeration");
        let output = lamp_planner::top_k(&task, expected + 10, &Budget::default());
        assert_eq!(output.status, Status::Solved, "{problem_name}");
        assert_eq!(output.plans.len(), expected, "{problem_name}");
        let mut distinct = output.plans.clone();
        distinct.sort();
        distinct.dedup();
        assert_eq!(distinct.len(), expected, "{problem_name}: plans repeat");
    }
}

#[test]
fn top_k_many_plans_stay_distinct() {
    // Gripper with two balls has 848 loop-free plans; ask for 200.
    let (domain, problem) = load("gripper", "gripper-2");
    let output =
        plan(&domain, &problem, Algorithm::TopK { k: 200 }, &Budget::default()).expect("valid");
    assert_eq!(output.status, Status::Solved);
    let mut distinct = output.plans.clone();
    distinct.sort();
    distinct.dedup();
    assert_eq!(distinct.len(), 200);
    for found in &output.plans {
        assert_valid_loop_free(&domain, &problem, found);
    }
}

#[test]
fn top_k_on_an_unsolvable_task_is_unsolvable() {
    let (domain, problem) = load("lights", "lights-paint-and-varnish");
    let output =
        plan(&domain, &problem, Algorithm::TopK { k: 3 }, &Budget::default()).expect("valid");
    assert_eq!(output.status, Status::Unsolvable(Unsolvable::SearchSpaceExhausted));
}

#[test]
fn planning_is_deterministic() {
    let (domain, problem) = load("cafe", "cafe-2");
    let first =
        plan(&domain, &problem, Algorithm::TopK { k: 4 }, &Budget::default()).expect("valid");
    let second =
        plan(&domain, &problem, Algorithm::TopK { k: 4 }, &Budget::default()).expect("valid");
    assert_eq!(first, second);
    assert_eq!(first.plans.len(), 4);
    for found in &first.plans {
        assert_valid_loop_free(&domain, &problem, found);
    }
}

#[test]
fn grounding_compiles_statics_and_equality_away() {
    let (domain, problem) = load("logistics", "logistics-two-cities");
    let task = ground(&domain, &problem, usize::MAX).expect("valid");
    assert!(task.facts.iter().all(|fact| fact.predicate != "in-city"), "in-city is static");
    let drives: Vec<String> =
        task.operators.iter().filter(|o| o.action == "drive").map(ToString::to_string).collect();
    assert_eq!(
        drives,
        [
            "(drive t1 depot1 port1 c1)",
            "(drive t1 port1 depot1 c1)",
            "(drive t2 depot2 port2 c2)",
            "(drive t2 port2 depot2 c2)",
        ]
    );
    let flights: Vec<String> =
        task.operators.iter().filter(|o| o.action == "fly").map(ToString::to_string).collect();
    assert_eq!(flights, ["(fly plane port1 port2)", "(fly plane port2 port1)"]);
    // Facts are sorted by predicate, then arguments.
    let mut sorted = task.facts.clone();
    sorted.sort();
    assert_eq!(sorted, task.facts);
}

#[test]
fn invalid_models_are_rejected_before_grounding() {
    let (domain, mut problem) = load("gripper", "gripper-4");
    problem.init.push(lamp_pddl::Atom::ground("at", &["ball1", "nowhere"]));
    let error =
        plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect_err("invalid");
    assert!(matches!(error, lamp_planner::PlannerError::InvalidInput(_)));
}
