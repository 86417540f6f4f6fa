//! Classical planners over grounded STRIPS: greedy best-first with FF, and top-k.
//!
//! The entry point is [`plan`]: a domain, a problem, an [`Algorithm`] and a [`Budget`] in, a
//! [`PlannerOutput`] out with a [`Status`] (solved, unsolvable with the reason, or out of budget)
//! and the plans found. [`validate`] checks any plan against the lifted model. The layers are
//! public for tools and tests: [`ground()`] (relaxed-reachability grounding into a [`GroundTask`]),
//! [`SearchSpace`] (lazy GBFS with FF and preferred operators over a forbidden-plan trie).
//!
//! Everything is deterministic: the same inputs give the same plans in the same order (see the
//! orders documented in `task`, `heuristic` and `search`), unless a wall-clock limit cuts a search.

mod ground;
mod heuristic;
mod lost_goals;
mod plan;
mod search;
mod state;
mod successors;
mod task;
mod topk;
mod validate;

use std::time::Duration;

use lamp_pddl::{Domain, PddlErrors, Problem};
use thiserror::Error;

pub use ground::{ground, ground_until};
pub use heuristic::{Estimate, FfHeuristic};
pub use plan::{Plan, PlanParseError, PlanStep};
pub use search::{PREFERRED_BOOST, SearchEnd, SearchSpace, Statistics};
pub use state::{State, StateId, StateRegistry};
pub use task::{FactId, GroundAtom, GroundTask, GroundingVerdict, Operator, OperatorId};
pub use topk::{top_k, top_k_until};
pub use validate::{Validated, ValidationError, validate};

/// A domain and a problem parsed from PDDL text; on bad text, a one-line message naming which
/// file is wrong and every error in it (what a planner plugin answers with).
pub fn parse_task(domain: &str, problem: &str) -> Result<(Domain, Problem), String> {
    let one_line = |what: &str, errors: &PddlErrors| {
        let details: Vec<String> = errors.errors.iter().map(ToString::to_string).collect();
        format!("the {what} is not valid PDDL: {}", details.join("; "))
    };
    let domain = lamp_pddl::parse_domain(domain).map_err(|errors| one_line("domain", &errors))?;
    let problem = lamp_pddl::parse_problem(problem, &domain)
        .map_err(|errors| one_line("problem", &errors))?;
    Ok((domain, problem))
}

/// Which planner to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Algorithm {
    /// One plan by lazy greedy best-first search with FF and preferred operators.
    GbfsFf,
    /// Up to `k` distinct loop-free plans (see [`top_k`]).
    TopK { k: usize },
}

/// Limits on one planner call. Expansion counts are deterministic; a time limit is not (a result
/// cut by the clock may differ between machines), so tests and reproducible runs use expansions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget {
    /// Most search nodes evaluated, over all searches of the call.
    pub max_expansions: Option<u64>,
    /// Wall-clock limit for the whole call.
    pub time_limit: Option<Duration>,
    /// Most ground operators; grounding beyond this fails with [`PlannerError::TooManyOperators`].
    pub max_operators: usize,
}

impl Budget {
    /// The default limits: two million expansions, no clock, two million operators.
    pub const DEFAULT: Self =
        Self { max_expansions: Some(2_000_000), time_limit: None, max_operators: 2_000_000 };

    /// The default limits with `expansions` as the expansion limit.
    #[must_use]
    pub fn expansions(expansions: u64) -> Self {
        Self { max_expansions: Some(expansions), ..Self::DEFAULT }
    }
}

impl Default for Budget {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Why a task has no (further) plan.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Unsolvable {
    /// A goal literal can never hold: proved by relaxed reachability or static facts, before search.
    GoalUnreachable { literal: String },
    /// Search expanded every reachable state (pruning only proven dead ends) without a goal.
    SearchSpaceExhausted,
}

/// How a planner call ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Status {
    /// The requested plans were found (for top-k: `k` plans, or every loop-free plan if fewer exist).
    Solved,
    /// No plan exists.
    Unsolvable(Unsolvable),
    /// The budget ran out first; `plans` holds what was found before.
    BudgetExhausted,
}

/// The result of [`plan`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlannerOutput {
    pub status: Status,
    /// Plans in the order found (at most one for GBFS).
    pub plans: Vec<Plan>,
    pub statistics: Statistics,
}

/// Errors that prevent planning at all (as opposed to a task without a plan).
#[derive(Debug, Error, miette::Diagnostic)]
pub enum PlannerError {
    #[error("the planning task is not valid PDDL")]
    #[diagnostic(code(lamp::planner::invalid_input))]
    InvalidInput(#[diagnostic_source] PddlErrors),

    #[error("grounding exceeds the limit of {limit} operators")]
    #[diagnostic(
        code(lamp::planner::too_many_operators),
        help("Raise Budget::max_operators, or reduce the objects or action parameters.")
    )]
    TooManyOperators { limit: usize },

    #[error("grounding was stopped before it finished")]
    #[diagnostic(code(lamp::planner::stopped))]
    Stopped,
}

/// Grounds and solves `problem` with `algorithm` within `budget`.
///
/// # Errors
/// [`PlannerError`] when the model is invalid or too large to ground.
pub fn plan(
    domain: &Domain,
    problem: &Problem,
    algorithm: Algorithm,
    budget: &Budget,
) -> Result<PlannerOutput, PlannerError> {
    plan_until(domain, problem, algorithm, budget, &|| false)
}

/// [`plan`] that stops grounding and search once `stop` says so (a cancelled run, polled every
/// few hundred bindings or evaluations): grounding then fails with [`PlannerError::Stopped`],
/// search ends with [`Status::BudgetExhausted`] and the plans found so far.
///
/// # Errors
/// As [`plan`], and [`PlannerError::Stopped`].
pub fn plan_until(
    domain: &Domain,
    problem: &Problem,
    algorithm: Algorithm,
    budget: &Budget,
    stop: &dyn Fn() -> bool,
) -> Result<PlannerOutput, PlannerError> {
    let task = ground_until(domain, problem, budget.max_operators, stop)?;
    Ok(match algorithm {
        Algorithm::GbfsFf => top_k_until(&task, 1, budget, stop),
        Algorithm::TopK { k } => top_k_until(&task, k, budget, stop),
    })
}

/// One plan for a grounded task by lazy GBFS with FF and preferred operators.
#[must_use]
pub fn gbfs_ff(task: &GroundTask, budget: &Budget) -> PlannerOutput {
    top_k(task, 1, budget)
}

/// Turns operator ids into a named plan.
#[must_use]
pub fn named_plan(task: &GroundTask, operators: &[OperatorId]) -> Plan {
    Plan {
        steps: operators
            .iter()
            .map(|&id| {
                let operator = &task.operators[id as usize];
                PlanStep { action: operator.action.clone(), arguments: operator.arguments.clone() }
            })
            .collect(),
    }
}
