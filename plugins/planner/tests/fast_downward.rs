//! Cross-check against Fast Downward (`lazy_greedy([hff], preferred=[hff])`, as the LAMP authors
//! run it): both planners solve the same tasks, and both plans pass our validator; tasks our
//! planner proves unsolvable are unsolvable for Fast Downward too. Fast Downward reads the PDDL our
//! writer produces.

mod common;

use common::{assert_valid_loop_free, fast_downward_driver, load, oracles_required};
use lamp_pddl::{Domain, Problem};
use lamp_planner::{Algorithm, Budget, Plan, Status, plan, validate};

/// Fast Downward's exit codes for "translator proved unsolvable" and "search proved unsolvable".
const FD_UNSOLVABLE: [i32; 2] = [10, 11];

#[allow(clippy::print_stdout, reason = "the skip notice is the test's output")]
fn driver() -> Option<String> {
    let found = fast_downward_driver();
    if found.is_none() {
        assert!(!oracles_required(), "Fast Downward (pip up-fast-downward) is required");
        println!("skipped: Fast Downward (pip package up-fast-downward) is not installed");
    }
    found
}

/// Runs Fast Downward on the text our writer makes of the parsed fixtures, so that it sees exactly
/// the model our planner plans on.
fn run_fast_downward(driver: &str, domain: &Domain, problem: &Problem) -> (i32, Option<Plan>) {
    let directory = tempfile::tempdir().expect("scratch directory");
    let plan_file = directory.path().join("sas_plan");
    let domain_file = directory.path().join("domain.pddl");
    let problem_file = directory.path().join("problem.pddl");
    std::fs::write(&domain_file, domain.to_string()).expect("write domain");
    std::fs::write(&problem_file, problem.to_string()).expect("write problem");
    let output = std::process::Command::new("python3")
        .current_dir(directory.path())
        .arg(driver)
        .arg("--plan-file")
        .arg(&plan_file)
        .arg(&domain_file)
        .arg(&problem_file)
        .args(["--evaluator", "hff=ff()", "--search", "lazy_greedy([hff], preferred=[hff])"])
        .output()
        .expect("python3 runs");
    let code = output.status.code().unwrap_or(-1);
    let found = std::fs::read_to_string(&plan_file)
        .ok()
        .map(|text| Plan::parse(&text).expect("Fast Downward writes well-formed plans"));
    (code, found)
}

#[test]
fn both_planners_solve_and_both_plans_validate() {
    let Some(driver) = driver() else { return };
    let tasks = [
        ("blocksworld", "blocksworld-sussman"),
        ("blocksworld", "blocksworld-reverse5"),
        ("gripper", "gripper-4"),
        ("gripper", "gripper-20"),
        ("logistics", "logistics-two-cities"),
        ("lights", "lights-two"),
        ("packing", "packing-4"),
        ("cafe", "cafe-18"),
    ];
    for (domain_name, problem_name) in tasks {
        let (domain, problem) = load(domain_name, problem_name);
        let (code, reference) = run_fast_downward(&driver, &domain, &problem);
        assert_eq!(code, 0, "{problem_name}: Fast Downward failed");
        let reference = reference.expect("Fast Downward wrote a plan");
        validate(&domain, &problem, &reference)
            .unwrap_or_else(|error| panic!("{problem_name}: Fast Downward's plan: {error}"));
        let ours = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("valid");
        assert_eq!(ours.status, Status::Solved, "{problem_name}");
        assert_valid_loop_free(&domain, &problem, &ours.plans[0]);
        println!(
            "{problem_name}: ours {} steps, Fast Downward {} steps",
            ours.plans[0].len(),
            reference.len()
        );
    }
}

#[test]
fn both_planners_agree_on_unsolvable_tasks() {
    let Some(driver) = driver() else { return };
    for (domain_name, problem_name) in [
        ("logistics", "logistics-no-airport"),
        ("lights", "lights-blown"),
        ("lights", "lights-paint-and-varnish"),
    ] {
        let (domain, problem) = load(domain_name, problem_name);
        let (code, reference) = run_fast_downward(&driver, &domain, &problem);
        assert!(FD_UNSOLVABLE.contains(&code), "{problem_name}: Fast Downward exit code {code}");
        assert!(reference.is_none());
        let ours = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default()).expect("valid");
        assert!(matches!(ours.status, Status::Unsolvable(_)), "{problem_name}: {:?}", ours.status);
    }
}
