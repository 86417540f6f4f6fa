//! Motion planners: a start and a goal configuration in, a valid path (or why there is none) out.

use std::time::Duration;

use crate::error::PluginError;
use crate::host::HostServices;

/// Limits on one motion-planning call. `None` means no limit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MotionBudget {
    /// Most iterations (samples or expansions); deterministic, so tests use it.
    pub max_iterations: Option<u64>,
    /// Wall-clock limit.
    pub time_limit: Option<Duration>,
}

/// What a motion planner is asked.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionRequest {
    /// The robot, as the host's oracles name it.
    pub robot: String,
    /// Start configuration (host layout).
    pub start: Vec<f64>,
    /// Goal configuration (host layout).
    pub goal: Vec<f64>,
    /// Limits on the search.
    pub budget: MotionBudget,
    /// Seed for the planner's own `ChaCha8Rng`.
    pub seed: u64,
}

/// Why a motion planner returned no path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoPathReason {
    /// The start configuration is invalid.
    StartInvalid,
    /// The goal configuration is invalid.
    GoalInvalid,
    /// The iteration or time budget ran out.
    BudgetExhausted,
    /// Another reason, described in the message.
    Other,
}

/// A motion planner's answer.
#[derive(Clone, Debug, PartialEq)]
pub enum MotionOutcome {
    /// Waypoints from the start to the goal; every consecutive pair is a valid edge.
    Path(Vec<Vec<f64>>),
    /// There is no path, or none was found.
    NoPath {
        /// The reason.
        reason: NoPathReason,
        /// Details for the user (may be empty).
        message: String,
    },
}

/// A motion planner.
///
/// # Example
/// A planner that only tries the straight edge from start to goal.
/// ```
/// use lamp_plugin_api::{
///     HostError, HostServices, MotionOutcome, MotionPlanner, MotionRequest, NoPathReason,
///     PluginError,
/// };
///
/// struct StraightLine;
///
/// impl MotionPlanner for StraightLine {
///     fn plan_path(
///         &mut self,
///         request: &MotionRequest,
///         host: &dyn HostServices,
///     ) -> Result<MotionOutcome, PluginError> {
///         let (robot, start, goal) = (&request.robot, &request.start, &request.goal);
///         if !host.configuration_is_valid(robot, start)? {
///             let message = String::new();
///             return Ok(MotionOutcome::NoPath { reason: NoPathReason::StartInvalid, message });
///         }
///         if !host.configuration_is_valid(robot, goal)? {
///             let message = String::new();
///             return Ok(MotionOutcome::NoPath { reason: NoPathReason::GoalInvalid, message });
///         }
///         Ok(if host.edge_is_valid(robot, start, goal)? {
///             MotionOutcome::Path(vec![start.clone(), goal.clone()])
///         } else {
///             let message = "the straight edge collides".to_string();
///             MotionOutcome::NoPath { reason: NoPathReason::Other, message }
///         })
///     }
/// }
///
/// // A rail from 0 to 10 with a wall at 5.
/// struct Rail;
/// impl HostServices for Rail {
///     fn configuration_is_valid(&self, _: &str, q: &[f64]) -> Result<bool, HostError> {
///         Ok((0.0..=10.0).contains(&q[0]) && q[0] != 5.0)
///     }
///     fn edge_is_valid(&self, _: &str, a: &[f64], b: &[f64]) -> Result<bool, HostError> {
///         Ok(a[0].min(b[0]) > 5.0 || a[0].max(b[0]) < 5.0)
///     }
/// }
///
/// let mut request = MotionRequest {
///     robot: "cart".into(),
///     start: vec![1.0],
///     goal: vec![4.0],
///     budget: Default::default(),
///     seed: 0,
/// };
/// let outcome = StraightLine.plan_path(&request, &Rail).unwrap();
/// assert_eq!(outcome, MotionOutcome::Path(vec![vec![1.0], vec![4.0]]));
/// request.goal = vec![7.0];
/// let outcome = StraightLine.plan_path(&request, &Rail).unwrap();
/// assert!(matches!(outcome, MotionOutcome::NoPath { reason: NoPathReason::Other, .. }));
/// ```
pub trait MotionPlanner: Send {
    /// Plans a path for `request` using the host's validity oracles.
    ///
    /// # Errors
    /// [`PluginError`] when the call produced no answer at all; "no path" is a
    /// [`MotionOutcome`], not an error.
    fn plan_path(
        &mut self,
        request: &MotionRequest,
        host: &dyn HostServices,
    ) -> Result<MotionOutcome, PluginError>;
}
