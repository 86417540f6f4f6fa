//! Shared helpers: loading fixtures and checking plans.

#![allow(dead_code)]

use lamp_pddl::{Domain, Problem, parse_domain, parse_problem};
use lamp_planner::{Plan, validate};

pub fn fixture_path(name: &str) -> String {
    format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"))
}

pub fn read(name: &str) -> String {
    let path = fixture_path(name);
    std::fs::read_to_string(&path).unwrap_or_else(|error| panic!("reading {path}: {error}"))
}

/// Parses `<domain>-domain.pddl` and `<problem>.pddl`.
pub fn load(domain: &str, problem: &str) -> (Domain, Problem) {
    let domain = parse_domain(&read(&format!("{domain}-domain.pddl")))
        .unwrap_or_else(|errors| panic!("{domain}: {errors:#?}"));
    let problem = parse_problem(&read(&format!("{problem}.pddl")), &domain)
        .unwrap_or_else(|errors| panic!("{problem}: {errors:#?}"));
    (domain, problem)
}

/// Validates `plan` and checks that it never visits a state twice.
pub fn assert_valid_loop_free(domain: &Domain, problem: &Problem, plan: &Plan) {
    validate(domain, problem, plan).unwrap_or_else(|error| panic!("{error}\n{plan}"));
    let mut states = vec![
        validate(domain, problem, &Plan::default())
            .map_or_else(|_| None, |validated| Some(validated.final_state)),
    ];
    // Replaying prefixes on a goal-free copy gives the state after every step.
    let mut open = problem.clone();
    open.goal.clear();
    states.clear();
    for length in 0..=plan.len() {
        let prefix = Plan { steps: plan.steps[..length].to_vec() };
        let state = validate(domain, &open, &prefix).expect("every prefix of a valid plan applies");
        assert!(
            !states.contains(&Some(state.final_state.clone())),
            "plan revisits a state:\n{plan}"
        );
        states.push(Some(state.final_state));
    }
}

/// Whether oracles must be present (CI), in which case a missing oracle fails instead of skipping.
pub fn oracles_required() -> bool {
    std::env::var("LAMP_REQUIRE_ORACLES").is_ok_and(|value| value == "1")
}

/// The path of Fast Downward's driver script shipped by the `up-fast-downward` wheel.
pub fn fast_downward_driver() -> Option<String> {
    let output = std::process::Command::new("python3")
        .args([
            "-c",
            "import importlib.util, os\n\
             spec = importlib.util.find_spec('up_fast_downward')\n\
             print(os.path.join(os.path.dirname(spec.origin), 'downward', 'fast-downward.py'))",
        ])
        .output()
        .ok()?;
    let path = String::from_utf8(output.stdout).ok()?.trim().to_owned();
    (output.status.success() && std::path::Path::new(&path).exists()).then_some(path)
}
