//! The plugin built as a shared library, loaded by path through lamp-plugin-host, planning the
//! same maze as the statically linked planner: every oracle, sampling included, crosses the C ABI.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command;
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
        let exe = std::env::current_exe().expect("the test binary knows its path");
        let profile_dir = exe
            .parent()
            .and_then(Path::parent)
            .expect("test binaries live in <target>/<profile>/deps")
            .to_path_buf();
        let target_dir = profile_dir.parent().expect("<target>/<profile>").to_path_buf();
        let profile = profile_dir.file_name().and_then(|name| name.to_str()).unwrap_or("debug");
        let mut command = Command::new(env!("CARGO"));
        command
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .args([
                "build",
                "--quiet",
                "--package",
                env!("CARGO_PKG_NAME"),
                "--lib",
                "--features",
                "shared-library",
            ])
            .arg("--target-dir")
            .arg(&target_dir);
        match profile {
            "debug" => {}
            "release" => {
                command.arg("--release");
            }
            other => {
                command.args(["--profile", other]);
            }
        }
        let status = command.status().expect("cargo runs");
        assert!(status.success(), "building the plugin library failed: {status}");
        let file = format!(
            "{}lamp_motion_rrt{}",
            std::env::consts::DLL_PREFIX,
            std::env::consts::DLL_SUFFIX
        );
        profile_dir.join(file)
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
