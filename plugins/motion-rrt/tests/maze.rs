//! The planner statically linked, on a 2-D maze host: valid paths, determinism, the no-path
//! reasons, budgets, options, and host failures and cancellation returned as errors.

mod support;

use std::cell::Cell;
use std::time::Duration;

use lamp_motion_rrt::{RrtConnectPlanner, RrtOptions};
use lamp_plugin_api::{
    HostError, HostServices, MotionOutcome, MotionPlanner, MotionRequest, NoPathReason, PluginError,
};
use lamp_plugin_sdk::PluginFactory;

use support::{Maze, assert_valid_path, length, request};

const START: [f64; 2] = [1.0, 1.0];
const GOAL: [f64; 2] = [9.0, 9.0];
/// More iterations than any test may run: a search that does not stop on failure would hang.
const HUGE_BUDGET: u64 = 1_000_000_000;

fn plan(
    planner: &mut RrtConnectPlanner,
    request: &MotionRequest,
    host: &dyn HostServices,
) -> MotionOutcome {
    planner.plan_path(request, host).expect("the maze host never fails")
}

fn path(outcome: MotionOutcome) -> Vec<Vec<f64>> {
    match outcome {
        MotionOutcome::Path(path) => path,
        other => panic!("expected a path, got {other:?}"),
    }
}

fn reason(outcome: MotionOutcome) -> NoPathReason {
    match outcome {
        MotionOutcome::NoPath { reason, .. } => reason,
        other => panic!("expected no path, got {other:?}"),
    }
}

#[test]
fn finds_a_path_through_the_maze_whose_every_edge_the_host_accepts() {
    let maze = Maze::two_walls();
    let request = request(START, GOAL, 5_000, 7);
    let path = path(plan(&mut RrtConnectPlanner::default(), &request, &maze));
    assert!(path.len() >= 4, "two walls need at least two turns: {path:?}");
    assert_valid_path(&maze, &request, &path);
}

#[test]
fn the_same_seed_gives_the_same_path_and_another_seed_another() {
    let maze = Maze::two_walls();
    let mut planner = RrtConnectPlanner::default();
    let first = plan(&mut planner, &request(START, GOAL, 5_000, 7), &maze);
    assert_eq!(plan(&mut planner, &request(START, GOAL, 5_000, 7), &maze), first);
    assert_ne!(plan(&mut planner, &request(START, GOAL, 5_000, 8), &maze), first);
}

#[test]
fn an_open_straight_edge_is_the_whole_path() {
    let maze = Maze::two_walls();
    let request = request([1.0, 1.0], [2.0, 9.0], 5_000, 1);
    let path = path(plan(&mut RrtConnectPlanner::default(), &request, &maze));
    assert_eq!(path, vec![request.start.clone(), request.goal.clone()]);
}

#[test]
fn invalid_ends_are_reported_as_such() {
    let maze = Maze::two_walls();
    let mut planner = RrtConnectPlanner::default();
    let inside_wall = [3.5, 4.0];
    let outcome = plan(&mut planner, &request(inside_wall, GOAL, 5_000, 1), &maze);
    assert_eq!(reason(outcome), NoPathReason::StartInvalid);
    let outcome = plan(&mut planner, &request(START, inside_wall, 5_000, 1), &maze);
    assert_eq!(reason(outcome), NoPathReason::GoalInvalid);
    let outside = [11.0, 1.0];
    assert_eq!(
        reason(plan(&mut planner, &request(START, outside, 5_000, 1), &maze)),
        NoPathReason::GoalInvalid
    );
}

#[test]
fn a_tiny_budget_on_a_hard_maze_is_exhausted() {
    let maze = Maze::serpentine();
    let mut planner = RrtConnectPlanner::default();
    let mut request = request(START, [9.5, 9.0], 30, 3);
    assert_eq!(reason(plan(&mut planner, &request, &maze)), NoPathReason::BudgetExhausted);
    // A time limit is a budget too.
    request.budget.max_iterations = Some(HUGE_BUDGET);
    request.budget.time_limit = Some(Duration::ZERO);
    let outcome = plan(&mut planner, &request, &maze);
    assert!(
        matches!(&outcome, MotionOutcome::NoPath { reason: NoPathReason::BudgetExhausted, message } if message.contains("within")),
        "{outcome:?}"
    );
    // Without an iteration budget in the request, the planner's own `iterations` applies.
    let mut few = RrtConnectPlanner::create(br#"{"iterations": 30}"#).unwrap();
    request.budget.max_iterations = None;
    request.budget.time_limit = None;
    assert_eq!(reason(plan(&mut few, &request, &maze)), NoPathReason::BudgetExhausted);
}

#[test]
fn shortcutting_as_configured_shortens_the_path() {
    let maze = Maze::two_walls();
    let request = request(START, GOAL, 5_000, 11);
    let raw = RrtOptions { shortcut_attempts: 0, ..RrtOptions::default() };
    let raw = path(plan(&mut RrtConnectPlanner::new(raw), &request, &maze));
    let mut shortcutting = RrtConnectPlanner::create(br#"{"shortcuts": 300}"#).unwrap();
    let short = path(plan(&mut shortcutting, &request, &maze));
    assert_valid_path(&maze, &request, &raw);
    assert_valid_path(&maze, &request, &short);
    assert!(length(&short) < length(&raw), "{} >= {}", length(&short), length(&raw));
}

#[test]
fn a_longer_step_makes_longer_edges() {
    let maze = Maze::two_walls();
    let request = request(START, GOAL, 5_000, 5);
    let options = |step| RrtOptions { step, shortcut_attempts: 0, ..RrtOptions::default() };
    let fine = path(plan(&mut RrtConnectPlanner::new(options(0.1)), &request, &maze));
    let coarse = path(plan(&mut RrtConnectPlanner::new(options(1.0)), &request, &maze));
    assert!(fine.len() > coarse.len(), "{} <= {}", fine.len(), coarse.len());
}

/// The maze, with one service failing from its `fail_from`-th call on.
struct FailingMaze {
    maze: Maze,
    service: &'static str,
    fail_from: usize,
    calls: Cell<usize>,
}

impl FailingMaze {
    fn new(service: &'static str, fail_from: usize) -> Self {
        Self { maze: Maze::two_walls(), service, fail_from, calls: Cell::new(0) }
    }

    fn gate(&self, service: &str) -> Result<(), HostError> {
        if service != self.service {
            return Ok(());
        }
        self.calls.set(self.calls.get() + 1);
        if self.calls.get() >= self.fail_from {
            return Err(HostError::failed(format!("{service} lost the world")));
        }
        Ok(())
    }
}

impl HostServices for FailingMaze {
    fn is_cancelled(&self) -> bool {
        self.gate("is_cancelled").is_err()
    }
    fn configuration_is_valid(&self, robot: &str, q: &[f64]) -> Result<bool, HostError> {
        self.gate("configuration_is_valid")?;
        self.maze.configuration_is_valid(robot, q)
    }
    fn edge_is_valid(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<bool, HostError> {
        self.gate("edge_is_valid")?;
        self.maze.edge_is_valid(robot, a, b)
    }
    fn distance(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<f64, HostError> {
        self.gate("distance")?;
        self.maze.distance(robot, a, b)
    }
    fn interpolate(
        &self,
        robot: &str,
        a: &[f64],
        b: &[f64],
        t: f64,
    ) -> Result<Vec<f64>, HostError> {
        self.gate("interpolate")?;
        self.maze.interpolate(robot, a, b, t)
    }
    fn sample_configuration(&self, robot: &str, seed: u64) -> Result<Vec<f64>, HostError> {
        self.gate("sample_configuration")?;
        self.maze.sample_configuration(robot, seed)
    }
}

#[test]
fn a_failing_host_service_is_returned_as_the_first_error_and_stops_the_search() {
    let mut planner = RrtConnectPlanner::default();
    let request = request(START, GOAL, HUGE_BUDGET, 7);
    for service in [
        "sample_configuration",
        "distance",
        "interpolate",
        "configuration_is_valid",
        "edge_is_valid",
    ] {
        for fail_from in [1, 20] {
            let host = FailingMaze::new(service, fail_from);
            assert_eq!(
                planner.plan_path(&request, &host),
                Err(PluginError::Host(HostError::failed(format!("{service} lost the world")))),
                "{service} failing from call {fail_from}"
            );
            assert_eq!(host.calls.get(), fail_from, "{service}: no call after the failure");
        }
    }
}

#[test]
fn cancellation_stops_the_search() {
    let mut planner = RrtConnectPlanner::default();
    let request = request(START, GOAL, HUGE_BUDGET, 7);
    for cancelled_from in [1, 2, 50] {
        let host = FailingMaze::new("is_cancelled", cancelled_from);
        assert_eq!(planner.plan_path(&request, &host), Err(PluginError::Cancelled));
        assert_eq!(host.calls.get(), cancelled_from);
    }
}

#[test]
fn hosts_without_sampling_unknown_robots_and_odd_requests_are_errors() {
    /// The maze's oracles without sampling.
    struct NoSampling(Maze);
    impl HostServices for NoSampling {
        fn configuration_is_valid(&self, robot: &str, q: &[f64]) -> Result<bool, HostError> {
            self.0.configuration_is_valid(robot, q)
        }
        fn edge_is_valid(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<bool, HostError> {
            self.0.edge_is_valid(robot, a, b)
        }
    }
    /// The maze, sampling one coordinate too many.
    struct WrongSamples(Maze);
    impl HostServices for WrongSamples {
        fn configuration_is_valid(&self, robot: &str, q: &[f64]) -> Result<bool, HostError> {
            self.0.configuration_is_valid(robot, q)
        }
        fn edge_is_valid(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<bool, HostError> {
            self.0.edge_is_valid(robot, a, b)
        }
        fn sample_configuration(&self, _robot: &str, _seed: u64) -> Result<Vec<f64>, HostError> {
            Ok(vec![1.0, 2.0, 3.0])
        }
    }

    let mut planner = RrtConnectPlanner::default();
    let blocked = request(START, GOAL, HUGE_BUDGET, 7);
    assert_eq!(
        planner.plan_path(&blocked, &NoSampling(Maze::two_walls())),
        Err(PluginError::Host(HostError::unsupported("sample_configuration")))
    );
    let Err(PluginError::Host(HostError::Failed { message })) =
        planner.plan_path(&blocked, &WrongSamples(Maze::two_walls()))
    else {
        panic!("a sample of the wrong length must be an error")
    };
    assert!(message.contains("returned 3 values; its configurations have 2"), "{message}");

    let unknown = MotionRequest { robot: "arm".into(), ..blocked.clone() };
    assert_eq!(
        planner.plan_path(&unknown, &Maze::two_walls()),
        Err(PluginError::Host(HostError::failed("no robot `arm`")))
    );
    let mismatched = MotionRequest { goal: vec![9.0], ..blocked };
    assert!(matches!(
        planner.plan_path(&mismatched, &Maze::two_walls()),
        Err(PluginError::InvalidRequest { .. })
    ));
}

/// Configurations are all free, but no edge may cross the segment x = 5, y < 8: only the host's
/// edge check knows the wall is there.
struct ThinWall;

impl HostServices for ThinWall {
    fn configuration_is_valid(&self, robot: &str, q: &[f64]) -> Result<bool, HostError> {
        support::check_robot(robot)?;
        Ok(q.iter().all(|coordinate| (0.0..=support::SIZE).contains(coordinate)))
    }
    fn edge_is_valid(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<bool, HostError> {
        support::check_robot(robot)?;
        if (a[0] - 5.0).signum() == (b[0] - 5.0).signum() {
            return Ok(true);
        }
        let t = (5.0 - a[0]) / (b[0] - a[0]);
        Ok(a[1] + t * (b[1] - a[1]) >= 8.0)
    }
    fn distance(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<f64, HostError> {
        Maze::two_walls().distance(robot, a, b)
    }
    fn interpolate(
        &self,
        robot: &str,
        a: &[f64],
        b: &[f64],
        t: f64,
    ) -> Result<Vec<f64>, HostError> {
        Maze::two_walls().interpolate(robot, a, b, t)
    }
    fn sample_configuration(&self, robot: &str, seed: u64) -> Result<Vec<f64>, HostError> {
        Maze::two_walls().sample_configuration(robot, seed)
    }
}

#[test]
fn edges_are_checked_by_the_host_not_by_sub_stepping() {
    let request = request([2.0, 2.0], [8.0, 2.0], 5_000, 4);
    let path = path(plan(&mut RrtConnectPlanner::default(), &request, &ThinWall));
    assert_valid_path(&ThinWall, &request, &path);
    assert!(path.iter().any(|q| q[1] >= 8.0), "the path must pass above the wall: {path:?}");
}
