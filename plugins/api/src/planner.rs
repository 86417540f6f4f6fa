//! Task planners: a PDDL domain and problem in, one plan or the top k plans out.

use std::time::Duration;

use serde::{Deserialize, Serialize};

use crate::error::PluginError;
use crate::host::HostServices;

/// Limits on one planner call. `None` means no limit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PlanBudget {
    /// Most search nodes expanded over the whole call; deterministic, so tests use it.
    pub max_expansions: Option<u64>,
    /// Wall-clock limit; results cut by the clock may differ between machines.
    pub time_limit: Option<Duration>,
}

/// What a planner is asked.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlanRequest {
    /// The PDDL domain text.
    pub domain: String,
    /// The PDDL problem text.
    pub problem: String,
    /// How many distinct plans are wanted (1 for a single plan).
    pub plan_count: usize,
    /// Limits on the search.
    pub budget: PlanBudget,
    /// Seed for the planner's own `ChaCha8Rng` (tie-breaking, restarts).
    pub seed: u64,
}

impl PlanRequest {
    /// A request for one plan with no limits and seed 0.
    #[must_use]
    pub fn new(domain: impl Into<String>, problem: impl Into<String>) -> Self {
        Self {
            domain: domain.into(),
            problem: problem.into(),
            plan_count: 1,
            budget: PlanBudget::default(),
            seed: 0,
        }
    }
}

/// One step of a plan: a ground action.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlanStep {
    /// The action's name as in the domain.
    pub action: String,
    /// The objects bound to its parameters, in parameter order.
    pub arguments: Vec<String>,
}

/// A sequence of ground actions.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Plan {
    /// The steps in execution order.
    pub steps: Vec<PlanStep>,
}

/// How a planner call ended.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum PlanStatus {
    /// The requested plans were found (for top-k: k plans, or all that exist if fewer).
    Solved,
    /// No (further) plan exists.
    Unsolvable {
        /// Why, for the user (for example the goal literal that can never hold).
        reason: String,
    },
    /// The budget ran out; the response holds the plans found before.
    BudgetExhausted,
    /// The planner could not handle the task (for example malformed or unsupported PDDL).
    Failed {
        /// What went wrong, for the user.
        message: String,
    },
}

/// A planner's answer.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlanResponse {
    /// How the call ended.
    pub status: PlanStatus,
    /// The plans found, best (or first found) first.
    pub plans: Vec<Plan>,
}

impl PlanResponse {
    /// A failed call with its reason, and no plans.
    pub fn failed(message: impl Into<String>) -> PlanResponse {
        PlanResponse { status: PlanStatus::Failed { message: message.into() }, plans: Vec::new() }
    }
}

/// A task planner.
///
/// # Example
/// A planner for problems whose goal is already true: it answers with the empty plan when the
/// problem text has an empty goal, and gives up otherwise.
/// ```
/// use lamp_plugin_api::{
///     HostServices, MinimalHost, Plan, PlanRequest, PlanResponse, PlanStatus, Planner,
///     PluginError,
/// };
///
/// struct TrivialPlanner;
///
/// impl Planner for TrivialPlanner {
///     fn plan(
///         &mut self,
///         request: &PlanRequest,
///         host: &dyn HostServices,
///     ) -> Result<PlanResponse, PluginError> {
///         if host.is_cancelled() {
///             return Err(PluginError::Cancelled);
///         }
///         let goal_is_empty = request.problem.replace(' ', "").contains("(:goal(and))");
///         Ok(if goal_is_empty {
///             PlanResponse { status: PlanStatus::Solved, plans: vec![Plan::default()] }
///         } else {
///             let message = "only empty goals are supported".to_string();
///             PlanResponse { status: PlanStatus::Failed { message }, plans: Vec::new() }
///         })
///     }
/// }
///
/// let request = PlanRequest::new("(define (domain d))", "(define (problem p) (:goal (and)))");
/// let response = TrivialPlanner.plan(&request, &MinimalHost).unwrap();
/// assert_eq!(response.status, PlanStatus::Solved);
/// assert_eq!(response.plans, vec![Plan::default()]);
/// ```
pub trait Planner: Send {
    /// Plans for `request`, reporting progress and polling cancellation through `host`.
    ///
    /// # Errors
    /// [`PluginError`] when the call produced no answer at all; "no plan" is a
    /// [`PlanStatus`], not an error.
    fn plan(
        &mut self,
        request: &PlanRequest,
        host: &dyn HostServices,
    ) -> Result<PlanResponse, PluginError>;
}
