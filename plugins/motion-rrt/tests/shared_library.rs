//! The plugin built as a shared library, loaded by path through lamp-plugin-host, planning the
//! same maze as the statically linked planner: every oracle, sampling included, crosses the C ABI.

mod support;

use std::path::PathBuf;
use std::sync::OnceLock;

use lamp_motion_rrt::{RrtConnectPlanner, RrtOptions};
use lamp_plugin_api::{HostError, MotionOutcome, MotionPlanner, NoPathReason, PluginError};
use lamp_plugin_host::{LoadError, PluginKind, PluginLibrary};

use support::{Maze, assert_valid_path, request};

/// Builds this package's shared library with the same cargo, target folder and profile as this
/// test, once, and returns its path.
fn shared_library() -> &'static PathBuf {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(|| {
        let package = env!("CARGO_PKG_NAME");
        let features = format!("{package}/shared-library");
        let arguments = ["--package", package, "--lib", "--features", features.as_str()];
        lamp_test_support::cargo_build_like_this_test(&arguments)
            .join(lamp_test_support::shared_library_file(package))
    })
}

#[test]
fn the_shared_library_plans_the_maze_exactly_as_the_linked_planner() {
    let library = PluginLibrary::open(shared_library()).unwrap();
    let info = library.info();
    assert_eq!((info.kind, info.name.as_str()), (PluginKind::MotionPlanner, "rrt-connect"));
    assert_eq!((info.abi_major, info.abi_minor), (1, 1));

    let maze = Maze::two_walls();
    let config = br#"{"step": 0.4, "shortcuts": 50}"#;
    let mut loaded = library.create_motion_planner(config).unwrap();
    let mut linked = RrtConnectPlanner::new(RrtOptions::from_config(config).unwrap());
    for seed in [7, 8] {
        let request = request([1.0, 1.0], [9.0, 9.0], 5_000, seed);
        let outcome = loaded.plan_path(&request, &maze).unwrap();
        assert_eq!(outcome, linked.plan_path(&request, &maze).unwrap(), "seed {seed}");
        let MotionOutcome::Path(path) = outcome else { panic!("no path for seed {seed}") };
        assert_valid_path(&maze, &request, &path);
    }

    let invalid_goal = request([1.0, 1.0], [3.5, 4.0], 5_000, 1);
    assert!(matches!(
        loaded.plan_path(&invalid_goal, &maze).unwrap(),
        MotionOutcome::NoPath { reason: NoPathReason::GoalInvalid, .. }
    ));
    let unknown = lamp_plugin_api::MotionRequest { robot: "arm".into(), ..invalid_goal };
    assert_eq!(
        loaded.plan_path(&unknown, &maze),
        Err(PluginError::Host(HostError::failed("no robot `arm`")))
    );
}

#[test]
fn the_shared_library_refuses_bad_options() {
    let library = PluginLibrary::open(shared_library()).unwrap();
    let Err(error) = library.create_motion_planner(br#"{"speed": 3}"#) else { panic!("created") };
    assert!(matches!(
        error,
        LoadError::Create { source: PluginError::InvalidRequest { message }, .. }
            if message.contains("unknown option `speed`")
    ));
}
