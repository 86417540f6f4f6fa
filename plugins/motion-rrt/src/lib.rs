//! The `rrt-connect` motion-planner plugin: lamp-rrt's RRT-Connect with shortcutting, run in
//! the host's configuration space through [`HostServices`] alone.
//!
//! Random states come from the host's `sample_configuration` (only the host knows the layout of
//! a configuration), seeded by a `ChaCha8Rng` that the request's seed starts, so the same
//! request gives the same path. Distances, interpolations, state and edge validity are the
//! host's too; the host checks each edge whole at its own resolution.
//!
//! Linked statically, construct [`RrtConnectPlanner::new`] with [`RrtOptions`]; built as a shared
//! library, the configuration is the options' JSON object (see [`RrtOptions::from_config`]).

mod host_space;
mod options;

use lamp_plugin_api::{
    HostServices, MotionOutcome, MotionPlanner, MotionRequest, NoPathReason, PluginError,
};
use lamp_plugin_sdk::PluginFactory;
use lamp_rrt::{RrtConfig, RrtError, rrt_connect};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::host_space::HostSpace;
pub use crate::options::{ITERATIONS_OPTION, RrtOptions, SHORTCUTS_OPTION, STEP_OPTION};

/// RRT-Connect over the host's oracles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RrtConnectPlanner {
    options: RrtOptions,
}

impl RrtConnectPlanner {
    /// A planner with `options`.
    #[must_use]
    pub fn new(options: RrtOptions) -> Self {
        Self { options }
    }

    /// Its options.
    #[must_use]
    pub fn options(&self) -> &RrtOptions {
        &self.options
    }

    /// lamp-rrt's configuration for `request`: the request's budget where it sets one, else
    /// the planner's own iteration count.
    fn config(&self, request: &MotionRequest) -> RrtConfig {
        let max_iterations = request
            .budget
            .max_iterations
            .map_or(self.options.iterations, |n| usize::try_from(n).unwrap_or(usize::MAX));
        RrtConfig {
            step: self.options.step,
            max_iterations,
            timeout: request.budget.time_limit,
            shortcut_attempts: self.options.shortcut_attempts,
        }
    }
}

impl PluginFactory for RrtConnectPlanner {
    fn create(config: &[u8]) -> Result<Self, PluginError> {
        Ok(Self::new(RrtOptions::from_config(config)?))
    }
}

impl MotionPlanner for RrtConnectPlanner {
    fn plan_path(
        &mut self,
        request: &MotionRequest,
        host: &dyn HostServices,
    ) -> Result<MotionOutcome, PluginError> {
        let (start, goal) = (&request.start, &request.goal);
        if start.is_empty() || start.len() != goal.len() {
            return Err(PluginError::invalid_request(format!(
                "the start has {} values and the goal {}; both need the same, non-zero count",
                start.len(),
                goal.len()
            )));
        }
        if host.is_cancelled() {
            return Err(PluginError::Cancelled);
        }
        host.report_progress(0.0, "rrt-connect: growing two trees");
        let space = HostSpace::new(host, &request.robot, start.len());
        let mut rng = ChaCha8Rng::seed_from_u64(request.seed);
        let result = rrt_connect(&space, start, goal, &self.config(request), &mut rng);
        // A failed oracle or a cancellation spoils whatever the search concluded afterwards.
        if let Some(failure) = space.into_failure() {
            return Err(failure);
        }
        host.report_progress(1.0, "rrt-connect: done");
        Ok(match result {
            Ok((path, _stats)) => MotionOutcome::Path(path),
            Err(error) => {
                let reason = match error {
                    RrtError::InvalidStart => NoPathReason::StartInvalid,
                    RrtError::InvalidGoal => NoPathReason::GoalInvalid,
                    RrtError::NoPath { .. } | RrtError::Timeout { .. } => {
                        NoPathReason::BudgetExhausted
                    }
                    // Only this plugin's space stops the search, and only after a failure,
                    // which was returned above.
                    RrtError::Stopped { .. } => NoPathReason::Other,
                };
                MotionOutcome::NoPath { reason, message: error.to_string() }
            }
        })
    }
}

#[cfg(feature = "shared-library")]
lamp_plugin_sdk::export_plugin! {
    motion_planner: RrtConnectPlanner,
    name: "rrt-connect",
    version: env!("CARGO_PKG_VERSION"),
    description: "RRT-Connect with shortcutting over the host's oracles (config {\"step\", \"shortcuts\", \"iterations\"}).",
}
