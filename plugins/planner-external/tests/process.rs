//! The plugin around stand-in planners (small shell commands in place of Fast Downward): exit
//! codes, plan files, time limit, cancellation and the typed errors. No oracle needed.
#![cfg(unix)]

mod common;

use std::cell::Cell;
use std::time::{Duration, Instant};

use common::{is_valid, request};
use lamp_planner_external::{CommandLine, ExternalError, ExternalOptions, ExternalPlanner};
use lamp_plugin_api::{HostServices, MinimalHost, PlanStatus, Planner, PluginError};
use lamp_plugin_host::PluginLibrary;
use lamp_plugin_sdk::{Descriptor, in_process_planner};

/// A planner whose Fast Downward is the shell script `script` (run in the scratch folder; the
/// planner's own arguments follow as `$0`, `$1`, …).
fn stand_in(script: &str) -> ExternalPlanner {
    ExternalPlanner::new(ExternalOptions {
        command: Some(CommandLine {
            program: "sh".into(),
            arguments: vec!["-c".into(), script.into()],
        }),
        ..ExternalOptions::default()
    })
}

/// The optimal gripper-2 plan as Fast Downward writes it.
const GRIPPER_2_PLAN: &str = "(pick ball1 rooma left)\n(pick ball2 rooma right)\n\
     (move rooma roomb)\n(drop ball1 roomb left)\n(drop ball2 roomb right)\n\
     ; cost = 5 (unit cost)\n";

#[test]
fn a_missing_program_is_a_typed_error_that_says_how_to_install() {
    let mut planner = ExternalPlanner::new(ExternalOptions {
        command: Some(CommandLine::program("/nonexistent/fast-downward.py")),
        ..ExternalOptions::default()
    });
    let task = request("gripper", "gripper-2");
    let error = planner.plan_external(&task, &MinimalHost).expect_err("nothing to run");
    assert!(
        matches!(&error, ExternalError::Spawn { program, .. } if program == "/nonexistent/fast-downward.py")
    );
    assert_eq!(
        miette::Diagnostic::code(&error).map(|code| code.to_string()).as_deref(),
        Some("lamp::planner::external::spawn")
    );
    let help = miette::Diagnostic::help(&error).map(|help| help.to_string()).unwrap_or_default();
    assert!(help.contains("pip install up-fast-downward"), "{help}");
    match planner.plan(&task, &MinimalHost) {
        Err(PluginError::Failed { message }) => {
            assert!(message.contains("pip install up-fast-downward"), "{message}")
        }
        other => panic!("expected a failure, got {other:?}"),
    }
}

#[test]
fn a_plan_file_is_read_and_validated() {
    let script = format!("printf '{}' > sas_plan", GRIPPER_2_PLAN.replace('\n', "\\n"));
    let task = request("gripper", "gripper-2");
    let response = stand_in(&script).plan(&task, &MinimalHost).expect("answers");
    assert_eq!(response.status, PlanStatus::Solved);
    assert_eq!(response.plans.len(), 1);
    assert_eq!(response.plans[0].steps.len(), 5);
    assert!(is_valid(&task, &response.plans[0]));
}

#[test]
fn the_inputs_and_the_search_reach_the_planner() {
    // Succeeds only when the domain and problem files are the request's and the search is lazy
    // greedy with FF and preferred operators.
    let script = format!(
        "grep -q '(define (domain gripper' \"$0\" && grep -q '(:goal' \"$1\" \
         && [ \"$2 $3 $4 $5\" = '--evaluator h=ff() --search lazy_greedy([h],preferred=[h])' ] \
         && printf '{}' > sas_plan",
        GRIPPER_2_PLAN.replace('\n', "\\n")
    );
    let response = stand_in(&script).plan(&request("gripper", "gripper-2"), &MinimalHost);
    assert_eq!(response.expect("answers").status, PlanStatus::Solved);
}

#[test]
fn a_plan_that_does_not_parse_or_validate_is_an_error() {
    let task = request("gripper", "gripper-2");
    let error = stand_in("echo '(pick ball1' > sas_plan").plan_external(&task, &MinimalHost);
    assert!(matches!(error, Err(ExternalError::PlanSyntax { .. })), "{error:?}");
    let error = stand_in("echo '(move rooma roomc)' > sas_plan").plan_external(&task, &MinimalHost);
    assert!(
        matches!(&error, Err(ExternalError::InvalidPlan { file, .. }) if file == "sas_plan"),
        "{error:?}"
    );
    let error = stand_in("echo '(move rooma roomb)' > sas_plan").plan_external(&task, &MinimalHost);
    assert!(matches!(error, Err(ExternalError::InvalidPlan { .. })), "misses the goal: {error:?}");
}

#[test]
fn exit_codes_become_statuses_or_errors() {
    let task = request("gripper", "gripper-2");
    let status = |script: &str| stand_in(script).plan(&task, &MinimalHost).map(|r| r.status);
    // A planner's verdict comes with its log: Fast Downward always prints one.
    let unsolvable = status("echo 'Search stopped without finding a solution.'; exit 11");
    assert!(matches!(unsolvable, Ok(PlanStatus::Unsolvable { .. })), "{unsolvable:?}");
    let unsolvable = status("echo 'Translator proved the task unsolvable.'; exit 10");
    assert!(matches!(unsolvable, Ok(PlanStatus::Unsolvable { .. })), "{unsolvable:?}");
    assert_eq!(status("echo 'Time limit reached.'; exit 23"), Ok(PlanStatus::BudgetExhausted));
    assert!(
        matches!(status("echo refused; exit 31"), Ok(PlanStatus::Failed { message }) if message.contains("refused"))
    );
    let error = stand_in("echo driver trouble; exit 35").plan_external(&task, &MinimalHost);
    assert!(
        matches!(&error, Err(ExternalError::Failed { log, .. }) if log.contains("driver trouble")),
        "{error:?}"
    );
    let error = stand_in("echo 'Solution found.'; exit 0").plan_external(&task, &MinimalHost);
    assert!(
        matches!(&error, Err(ExternalError::Failed { reason, log, .. })
            if reason.contains("wrote no plan") && log.contains("Solution found.")),
        "no plan written: {error:?}"
    );
}

/// A command that prints nothing and writes no plan is no planner: whatever its exit code, the
/// call fails saying so, with the code, and never answers that the task is unsolvable (which the
/// solver reported as a goal the learned model has no way to).
#[test]
fn a_planner_that_prints_nothing_and_plans_nothing_produced_no_output() {
    let task = request("gripper", "gripper-2");
    for code in [12, 11, 0, 23] {
        let script = format!("exit {code}");
        let error = stand_in(&script).plan_external(&task, &MinimalHost);
        let Err(error) = error else { panic!("exit {code}: {error:?}") };
        assert!(
            matches!(&error, ExternalError::NoOutput { code: found, .. } if *found == code),
            "exit {code}: {error:?}"
        );
        assert_eq!(
            miette::Diagnostic::code(&error).map(|code| code.to_string()).as_deref(),
            Some("lamp::planner::external::no_output")
        );
        let message = error.to_string();
        assert!(message.contains("produced no output"), "{message}");
        assert!(message.contains(&format!("exited with code {code}")), "{message}");
        let help =
            miette::Diagnostic::help(&error).map(|help| help.to_string()).unwrap_or_default();
        assert!(help.contains("was not found unreachable"), "{help}");
        match stand_in(&script).plan(&task, &MinimalHost) {
            Err(PluginError::Failed { message }) => {
                assert!(message.contains("produced no output"), "{message}");
                assert!(message.contains("says nothing about the goal"), "{message}");
            }
            other => panic!("exit {code}: a failure, not a status: {other:?}"),
        }
    }
    // K* (more than one plan) alike: a silent run that ends normally found nothing, proved nothing.
    let mut top_k = request("gripper", "gripper-2");
    top_k.plan_count = 2;
    let mut planner = ExternalPlanner::new(ExternalOptions {
        kstar_command: Some(CommandLine {
            program: "sh".into(),
            arguments: vec!["-c".into(), "exit 0".into()],
        }),
        ..ExternalOptions::default()
    });
    let error = planner.plan_external(&top_k, &MinimalHost);
    assert!(matches!(error, Err(ExternalError::NoOutput { code: 0, .. })), "{error:?}");
    // K* that ends normally with a log but no plan file found nothing and proved nothing (K*
    // proving a task unsolvable exits with its own code): a failure with its log, not a verdict
    // that the learned model has no way to the goal.
    let mut planner = ExternalPlanner::new(ExternalOptions {
        kstar_command: Some(CommandLine {
            program: "sh".into(),
            arguments: vec!["-c".into(), "echo 'Search done.'; exit 0".into()],
        }),
        ..ExternalOptions::default()
    });
    let error = planner.plan_external(&top_k, &MinimalHost);
    assert!(
        matches!(&error, Err(ExternalError::Failed { reason, log, .. })
            if reason.contains("wrote no plan") && log.contains("Search done.")),
        "{error:?}"
    );
    // Printing is not enough to be believed when a plan was promised: exit 0 needs a plan.
    let error = stand_in("echo working").plan_external(&task, &MinimalHost);
    assert!(matches!(error, Err(ExternalError::Failed { .. })), "{error:?}");
}

#[test]
fn malformed_pddl_is_a_failed_status_before_anything_runs() {
    let mut task = request("gripper", "gripper-2");
    task.problem = "(define (problem broken".into();
    let response = stand_in("exit 99").plan(&task, &MinimalHost).expect("answers");
    assert!(
        matches!(response.status, PlanStatus::Failed { message } if message.contains("problem"))
    );
}

#[test]
fn the_time_limit_kills_the_planner_and_everything_it_started() {
    let mut task = request("gripper", "gripper-2");
    task.budget.time_limit = Some(Duration::from_millis(300));
    let started = Instant::now();
    // The sleep runs in a child of the shell, as the search runs in a child of Fast Downward's
    // driver; both must go.
    let response = stand_in("sleep 30; exit 0").plan(&task, &MinimalHost).expect("answers");
    assert_eq!(response.status, PlanStatus::BudgetExhausted);
    assert!(response.plans.is_empty());
    assert!(started.elapsed() < Duration::from_secs(20), "took {:?}", started.elapsed());
}

/// A host that asks to stop from its `after`-th poll on.
struct CancellingHost {
    polls: Cell<u32>,
    after: u32,
}

impl HostServices for CancellingHost {
    fn is_cancelled(&self) -> bool {
        self.polls.set(self.polls.get() + 1);
        self.polls.get() >= self.after
    }
}

#[test]
fn cancellation_before_or_during_the_run_is_the_plugin_error() {
    for after in [1, 5] {
        let host = CancellingHost { polls: Cell::new(0), after };
        let started = Instant::now();
        let result = stand_in("sleep 30; exit 0").plan(&request("gripper", "gripper-2"), &host);
        assert_eq!(result, Err(PluginError::Cancelled), "cancelled at poll {after}");
        assert!(started.elapsed() < Duration::from_secs(20), "took {:?}", started.elapsed());
    }
}

#[test]
fn through_the_c_abi_the_configuration_names_the_command() {
    let descriptor = Descriptor { name: "lamp-external-planner", version: "test", description: "" };
    let library =
        PluginLibrary::from_trusted_entry(in_process_planner::<ExternalPlanner>(descriptor))
            .expect("the SDK builds a valid entry");
    let mut planner = library
        .create_planner(br#"{"command": "/nonexistent/planner --flag"}"#)
        .expect("valid options");
    match planner.plan(&request("gripper", "gripper-2"), &MinimalHost) {
        Err(PluginError::Failed { message }) => {
            assert!(message.contains("/nonexistent/planner"), "{message}")
        }
        other => panic!("expected a failure, got {other:?}"),
    }
    assert!(
        library.create_planner(br#"{"search": "astar"}"#).is_err(),
        "unknown options are refused"
    );
}
