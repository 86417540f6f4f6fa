//! Shared helpers: the planner fixtures of lamp-planner, requests, and plan checks.

#![allow(dead_code)]

use lamp_pddl::{parse_domain, parse_problem};
use lamp_planner_external::{Engine, ExternalOptions, ExternalPlanner};
use lamp_plugin_api::{Plan, PlanRequest};

/// The text of a fixture of lamp-planner's tests.
pub fn fixture(name: &str) -> String {
    let path = format!("{}/../planner/tests/fixtures/{name}.pddl", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|error| panic!("reading {path}: {error}"))
}

/// A one-plan request for `<domain>-domain.pddl` and `<problem>.pddl`.
pub fn request(domain: &str, problem: &str) -> PlanRequest {
    PlanRequest::new(fixture(&format!("{domain}-domain")), fixture(problem))
}

/// Whether `plan` solves `request` by lamp-planner's validator.
pub fn is_valid(request: &PlanRequest, plan: &Plan) -> bool {
    let domain = parse_domain(&request.domain).expect("the domain parses");
    let problem = parse_problem(&request.problem, &domain).expect("the problem parses");
    let steps = plan
        .steps
        .iter()
        .map(|step| lamp_planner::PlanStep {
            action: step.action.clone(),
            arguments: step.arguments.clone(),
        })
        .collect();
    lamp_planner::validate(&domain, &problem, &lamp_planner::Plan { steps }).is_ok()
}

/// Whether the plugin finds `engine` by itself (the pip package `package`, or a driver on
/// `PATH`). Missing: the test is skipped with a message, or fails when oracles are required.
///
/// The plugin's own search is the test, not `import`: `up_fast_downward` cannot be imported
/// without `unified-planning`, which its driver does not need.
#[allow(clippy::print_stdout, reason = "the skip notice is the test's output")]
pub fn planner_installed(engine: Engine, package: &str) -> bool {
    let found = ExternalPlanner::new(ExternalOptions::default()).command(engine).is_ok();
    if !found {
        assert!(
            !lamp_test_support::oracles_required(),
            "{} (pip {package}) is required",
            engine.name()
        );
        println!("skipped: {} is not installed (pip install {package})", engine.name());
    }
    found
}
