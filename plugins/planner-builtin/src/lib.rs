//! The built-in task planners of lamp-planner behind the [`Planner`] plugin trait: `gbfs-ff`
//! (lazy greedy best-first search with FF and preferred operators; one plan) and `topk` (the
//! `plan_count` best distinct loop-free plans).
//!
//! Linked statically, construct [`BuiltinPlanner`] directly; built as a shared library, the
//! plugin's configuration is the JSON object `{"algorithm": "gbfs-ff"}` (the default) or
//! `{"algorithm": "topk"}`, with an optional `"operators"`: the most ground operators (by
//! default lamp-planner's 2,000,000).
//! Both planners are deterministic, so the request's seed is not used. Cancellation is polled
//! before the search starts; a running search stops on its budget, not on cancellation.

use lamp_planner::{Algorithm, Budget, Status, Unsolvable, parse_task};
use lamp_plugin_api::config::{self, ConfigError, PluginConfig};
use lamp_plugin_api::{
    HostServices, Plan, PlanRequest, PlanResponse, PlanStatus, PlanStep, Planner, PluginError,
};
use lamp_plugin_sdk::PluginFactory;

/// Which built-in search to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BuiltinAlgorithm {
    /// One plan by lazy GBFS with FF and preferred operators (`gbfs-ff`).
    GbfsFf,
    /// The request's `plan_count` distinct plans (`topk`).
    TopK,
}

impl BuiltinAlgorithm {
    /// The configuration name of the algorithm.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            BuiltinAlgorithm::GbfsFf => "gbfs-ff",
            BuiltinAlgorithm::TopK => "topk",
        }
    }
}

/// A built-in planner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BuiltinPlanner {
    algorithm: BuiltinAlgorithm,
    max_operators: usize,
}

impl BuiltinPlanner {
    /// A planner running `algorithm`, with lamp-planner's default grounding limit.
    #[must_use]
    pub fn new(algorithm: BuiltinAlgorithm) -> Self {
        Self { algorithm, max_operators: Budget::DEFAULT.max_operators }
    }

    /// The same planner with another limit on ground operators.
    #[must_use]
    pub fn with_max_operators(self, max_operators: usize) -> Self {
        Self { max_operators, ..self }
    }

    /// The algorithm it runs.
    #[must_use]
    pub fn algorithm(&self) -> BuiltinAlgorithm {
        self.algorithm
    }
}

/// The configuration key naming the algorithm.
pub const ALGORITHM_OPTION: &str = "algorithm";
/// The configuration key of the grounding limit.
pub const OPERATORS_OPTION: &str = "operators";

impl BuiltinAlgorithm {
    /// The algorithm named `name` in the configuration.
    ///
    /// # Errors
    /// [`ConfigError::BadValue`] for a name that is neither `gbfs-ff` nor `topk`.
    pub fn from_name(name: &str) -> Result<Self, ConfigError> {
        [BuiltinAlgorithm::GbfsFf, BuiltinAlgorithm::TopK]
            .into_iter()
            .find(|algorithm| algorithm.name() == name)
            .ok_or_else(|| {
                config::bad_value(
                    ALGORITHM_OPTION,
                    format!("unknown algorithm `{name}`; expected `gbfs-ff` or `topk`"),
                )
            })
    }
}

impl PluginFactory for BuiltinPlanner {
    /// The configuration is `{"algorithm": "gbfs-ff" | "topk", "operators": N}`; without an
    /// algorithm, `gbfs-ff`; without a limit, lamp-planner's default.
    fn create(config: &[u8]) -> Result<Self, PluginError> {
        let mut config = PluginConfig::parse(config)?;
        let algorithm = match config.text(ALGORITHM_OPTION)? {
            None => BuiltinAlgorithm::GbfsFf,
            Some(name) => BuiltinAlgorithm::from_name(&name)?,
        };
        let operators = config.count(OPERATORS_OPTION)?;
        config.finish()?;
        let planner = Self::new(algorithm);
        Ok(operators.map_or(planner, |limit| planner.with_max_operators(limit)))
    }
}

impl Planner for BuiltinPlanner {
    fn plan(
        &mut self,
        request: &PlanRequest,
        host: &dyn HostServices,
    ) -> Result<PlanResponse, PluginError> {
        if host.is_cancelled() {
            return Err(PluginError::Cancelled);
        }
        let (domain, problem) = match parse_task(&request.domain, &request.problem) {
            Ok(task) => task,
            Err(message) => return Ok(PlanResponse::failed(message)),
        };
        let algorithm = match self.algorithm {
            BuiltinAlgorithm::GbfsFf => Algorithm::GbfsFf,
            BuiltinAlgorithm::TopK => Algorithm::TopK { k: request.plan_count.max(1) },
        };
        let budget = Budget {
            max_expansions: request.budget.max_expansions,
            time_limit: request.budget.time_limit,
            max_operators: self.max_operators,
        };
        host.report_progress(
            0.0,
            &format!("grounding and searching with {}", self.algorithm.name()),
        );
        let cancelled = || host.is_cancelled();
        let output = match lamp_planner::plan_until(
            &domain, &problem, algorithm, &budget, &cancelled,
        ) {
            // Stopped because the run was cancelled: whatever was found is not what was asked.
            _ if host.is_cancelled() => return Err(PluginError::Cancelled),
            Ok(output) => output,
            Err(lamp_planner::PlannerError::TooManyOperators { limit }) => {
                return Ok(PlanResponse::failed(format!(
                    "grounding exceeds the limit of {limit} operators; raise it with the \
                         planner's `operators` option (`plugins {{ planner {} {{ operators N }} }}`)",
                    self.algorithm.name()
                )));
            }
            Err(error) => {
                let cause = std::error::Error::source(&error)
                    .map(|source| format!(": {source}"))
                    .unwrap_or_default();
                return Ok(PlanResponse::failed(format!("{error}{cause}")));
            }
        };
        host.report_progress(1.0, "done");
        let status = match output.status {
            Status::Solved => PlanStatus::Solved,
            Status::Unsolvable(Unsolvable::GoalUnreachable { literal }) => PlanStatus::Unsolvable {
                reason: format!("the goal literal {literal} can never hold"),
            },
            Status::Unsolvable(Unsolvable::SearchSpaceExhausted) => PlanStatus::Unsolvable {
                reason: "the search exhausted every reachable state".to_string(),
            },
            Status::BudgetExhausted => PlanStatus::BudgetExhausted,
        };
        let plans = output
            .plans
            .into_iter()
            .map(|plan| Plan {
                steps: plan
                    .steps
                    .into_iter()
                    .map(|step| PlanStep { action: step.action, arguments: step.arguments })
                    .collect(),
            })
            .collect();
        Ok(PlanResponse { status, plans })
    }
}

#[cfg(feature = "shared-library")]
lamp_plugin_sdk::export_plugin! {
    planner: BuiltinPlanner,
    name: "lamp-builtin-planner",
    version: env!("CARGO_PKG_VERSION"),
    description: "Lazy GBFS with FF (the default) or top-k plans (config {\"algorithm\": \"topk\"}).",
}
