//! Loading real shared libraries: the example planner plans through the C ABI, and every kind of
//! bad library is refused with its typed error before any of its functions runs.

mod support;

use std::path::Path;
use std::sync::Mutex;

use lamp_plugin_api::{
    HostServices, MinimalHost, PlanBudget, PlanRequest, PlanStatus, PlanStep, PluginError,
};
use lamp_plugin_host::{LoadError, PluginKind, PluginLibrary};
use miette::Diagnostic;

const DOMAIN: &str = "(define (domain blocks) (:predicates (on ?x ?y) (clear ?x)))";
const PROBLEM: &str = "(define (problem stack) (:domain blocks)
    (:objects a b c)
    (:init (clear a) (clear b) (clear c))
    (:goal (and (on a b) (on b c))))";

fn code(diagnostic: &dyn Diagnostic) -> String {
    diagnostic.code().map(|code| code.to_string()).unwrap_or_default()
}

/// Records what the plugin reports.
#[derive(Default)]
struct RecordingHost {
    progress: Mutex<Vec<(f64, String)>>,
    cancelled: bool,
}

impl HostServices for RecordingHost {
    fn report_progress(&self, fraction: f64, message: &str) {
        self.progress
            .lock()
            .expect("no test panics while holding it")
            .push((fraction, message.to_string()));
    }
    fn is_cancelled(&self) -> bool {
        self.cancelled
    }
}

#[test]
fn the_echo_planner_loads_and_plans_through_the_c_abi() {
    let library = PluginLibrary::open(&support::echo_planner()).unwrap();
    let info = library.info();
    assert_eq!(info.kind, PluginKind::Planner);
    assert_eq!(info.name, "echo-planner");
    assert_eq!(info.version, env!("CARGO_PKG_VERSION"));
    assert_eq!((info.abi_major, info.abi_minor), (1, 1));

    let mut planner = library.create_planner(&[]).unwrap();
    let host = RecordingHost::default();
    let response = planner.plan(&PlanRequest::new(DOMAIN, PROBLEM), &host).unwrap();
    assert_eq!(response.status, PlanStatus::Solved);
    let steps: Vec<PlanStep> = response.plans.into_iter().flat_map(|plan| plan.steps).collect();
    let step = |arguments: [&str; 3]| PlanStep {
        action: "achieve".into(),
        arguments: arguments.iter().map(ToString::to_string).collect(),
    };
    assert_eq!(steps, vec![step(["on", "a", "b"]), step(["on", "b", "c"])]);
    assert_eq!(
        *host.progress.lock().unwrap(),
        vec![(0.0, "reading the goal".to_string()), (1.0, "done".to_string())]
    );

    // The budget and the failure status cross the boundary too.
    let mut request = PlanRequest::new(DOMAIN, PROBLEM);
    request.budget = PlanBudget { max_expansions: Some(1), time_limit: None };
    assert_eq!(planner.plan(&request, &MinimalHost).unwrap().status, PlanStatus::BudgetExhausted);
    request.problem = "(define (problem p) (:goal (not (on a b))))".into();
    let status = planner.plan(&request, &MinimalHost).unwrap().status;
    assert!(
        matches!(&status, PlanStatus::Failed { message } if message.contains("(not (on a b))"))
    );

    // Cancellation is polled through the host table and comes back as a typed error.
    let cancelled = RecordingHost { cancelled: true, ..RecordingHost::default() };
    assert_eq!(
        planner.plan(&PlanRequest::new(DOMAIN, PROBLEM), &cancelled),
        Err(PluginError::Cancelled)
    );
}

#[test]
fn a_plugin_refusing_its_configuration_is_a_create_error() {
    let library = PluginLibrary::open(&support::echo_planner()).unwrap();
    assert!(library.create_planner(b"{}").is_ok(), "the empty object is no options");
    let Err(error) = library.create_planner(br#"{"unexpected": 1}"#) else { panic!("created") };
    assert_eq!(code(&error), "lamp::plugin::create");
    assert!(matches!(
        &error,
        LoadError::Create { source: PluginError::InvalidRequest { message }, .. }
            if message == "unknown option `unexpected`; this plugin reads no options"
    ));
}

#[test]
fn asking_for_another_kind_is_refused() {
    let library = PluginLibrary::open(&support::echo_planner()).unwrap();
    let Err(error) = library.create_refiner(&[]) else { panic!("created") };
    assert_eq!(code(&error), "lamp::plugin::wrong_kind");
    assert!(matches!(
        error,
        LoadError::WrongKind { expected: PluginKind::Refiner, found: PluginKind::Planner, .. }
    ));
    assert!(library.create_motion_planner(&[]).is_err());
}

#[test]
fn another_abi_major_is_refused_before_any_call() {
    // The fixture aborts the process in every function, so reaching the assertions at all shows
    // that nothing was called.
    let error = PluginLibrary::open(&support::fixture("future_abi_planner")).unwrap_err();
    assert_eq!(code(&error), "lamp::plugin::abi_mismatch");
    assert!(matches!(
        error,
        LoadError::AbiMismatch {
            plugin_major: 2,
            plugin_minor: 0,
            host_major: 1,
            host_minor: 1,
            ..
        }
    ));
    let help = error.help().unwrap().to_string();
    assert_eq!(help, "rebuild the plugin against lamp-plugin-sdk ABI v1");
}

#[test]
fn a_panicking_plugin_reports_the_panic_instead_of_crashing() {
    let library = PluginLibrary::open(&support::fixture("panicking_planner")).unwrap();
    let mut planner = library.create_planner(&[]).unwrap();
    let mut request = PlanRequest::new(DOMAIN, PROBLEM);
    request.seed = 17;
    let error = planner.plan(&request, &MinimalHost).unwrap_err();
    assert_eq!(
        error,
        PluginError::Panicked { message: "deliberate panic while planning with seed 17".into() }
    );
    assert_eq!(code(&error), "lamp::plugin::panicked");
    // The instance is still usable after a caught panic.
    assert!(matches!(planner.plan(&request, &MinimalHost), Err(PluginError::Panicked { .. })));
}

#[test]
fn a_library_without_the_entry_symbol_is_refused() {
    let path = support::fixture("no_entry_library");
    let error = PluginLibrary::open(&path).unwrap_err();
    assert_eq!(code(&error), "lamp::plugin::missing_symbol");
    assert!(
        matches!(&error, LoadError::MissingSymbol { symbol: "lamp_plugin_entry", path: p } if *p == path)
    );
}

#[test]
fn a_file_that_is_no_library_is_a_load_error() {
    let error =
        PluginLibrary::open(Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml").as_path())
            .unwrap_err();
    assert_eq!(code(&error), "lamp::plugin::load");
    let missing = PluginLibrary::open(Path::new("no-such-plugin.so")).unwrap_err();
    assert!(matches!(missing, LoadError::Load { .. }));
}

/// The dynamic loader's reason, not only libloading's "dlopen failed" (the wording is glibc's).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[test]
fn a_load_error_carries_the_loader_reason() {
    let folder = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let text = folder.join("libtext.so");
    // Longer than an ELF header, so that the loader reads one and finds text.
    std::fs::write(&text, "this is text, not a shared library\n".repeat(4)).unwrap();
    let message = PluginLibrary::open(&text).unwrap_err().to_string();
    assert!(message.contains("dlopen failed: "), "{message}");
    assert!(message.contains("libtext.so") && message.contains("invalid ELF header"), "{message}");

    let missing = folder.join("libmissing.so");
    let message = PluginLibrary::open(&missing).unwrap_err().to_string();
    assert!(
        message.contains("cannot open shared object file: No such file or directory"),
        "{message}"
    );
}

#[test]
fn loading_the_same_library_twice_shares_one_mapping() {
    let first = PluginLibrary::open(&support::echo_planner()).unwrap();
    let second = PluginLibrary::open(&support::echo_planner()).unwrap();
    assert_eq!(first.info(), second.info());
    let mut planners = [first.create_planner(&[]).unwrap(), second.create_planner(&[]).unwrap()];
    for planner in &mut planners {
        let response = planner.plan(&PlanRequest::new(DOMAIN, PROBLEM), &MinimalHost).unwrap();
        assert_eq!(response.plans[0].steps.len(), 2);
    }
}
