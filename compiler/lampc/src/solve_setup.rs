//! What every solve of a checked spec sets up the same way, `lampc solve` and `lampc eval` alike:
//! the three plugins from the spec's `plugins` block with the command line's overrides, and the
//! solver's settings (seed, plan count, the deterministic budgets, resolutions, time limits).
//!
//! The budgets are constants here so that an evaluation solves with exactly the settings a user
//! gets from `lampc solve`.

use std::path::Path;

use lamp_abstraction::SamplerArtifact;
use lamp_plugin_api::{MotionBudget, MotionPlanner, PlanBudget, Planner, Refiner};
use lamp_spec::Spec;
use lamp_tamp::MotionSettings;
use lamp_tamp::{Plugins, SolveSettings};
use lamp_world::MotionConfig;

use crate::plugin_setup::{self, RuntimeOptions, SetupError};

/// Wasted candidates (refused, backtracked over, needing a replan) per plan before it is given up.
pub(crate) const MAX_REFUSED: usize = 100;
/// RRT-Connect iterations per motion call (deterministic; the time limit is a safety net only).
pub(crate) const MOTION_ITERATIONS: u64 = 4000;
/// Rounds over the plans with fresh samples.
pub(crate) const ROUNDS: usize = 20;
/// Plans asked of the planner when neither the command line nor the spec says.
pub(crate) const DEFAULT_PLAN_COUNT: usize = 3;

/// What the command line may override of the spec's solve settings.
#[derive(Clone, Debug, Default)]
pub(crate) struct Overrides<'a> {
    /// The planner, refiner and motion planner: a built-in name or a library path.
    pub(crate) planner: Option<&'a str>,
    pub(crate) refiner: Option<&'a str>,
    pub(crate) motion: Option<&'a str>,
    /// Plans to ask the planner for (top-k).
    pub(crate) plans: Option<usize>,
    /// The run's seed.
    pub(crate) seed: Option<u64>,
    /// Fail instead of dropping goal atoms no plan reaches.
    pub(crate) no_relax: bool,
}

/// The three plugins of a solve, and the options the runtime took out of their blocks.
pub(crate) struct SolvePlugins {
    pub(crate) planner: Box<dyn Planner>,
    pub(crate) refiner: Box<dyn Refiner>,
    pub(crate) motion: Box<dyn MotionPlanner>,
    pub(crate) runtime: RuntimeOptions,
}

impl SolvePlugins {
    /// The plugins as the solver takes them.
    pub(crate) fn as_plugins(&mut self) -> Plugins<'_> {
        Plugins {
            planner: self.planner.as_mut(),
            refiner: self.refiner.as_mut(),
            motion: self.motion.as_mut(),
        }
    }
}

/// A plugin of the spec (or of the command line) that could not be set up: the spec file and the
/// plugin kind, then why, with the code and help of the underlying error.
#[derive(Debug, thiserror::Error)]
#[error("{spec_file}: the {kind} plugin: {error}")]
pub(crate) struct PluginSetupError {
    spec_file: String,
    kind: &'static str,
    error: SetupError,
}

impl PluginSetupError {
    /// The `kind` plugin of `spec_file` could not be set up.
    pub(crate) fn new(spec_file: &str, kind: &'static str, error: SetupError) -> Self {
        PluginSetupError { spec_file: spec_file.to_string(), kind, error }
    }
}

impl miette::Diagnostic for PluginSetupError {
    fn code<'a>(&'a self) -> Option<Box<dyn std::fmt::Display + 'a>> {
        self.error.code()
    }

    fn help<'a>(&'a self) -> Option<Box<dyn std::fmt::Display + 'a>> {
        self.error.help()
    }
}

/// Sets up the spec's plugins (or the command line's), the `gmm` refiner sampling `artifact`.
/// An error names the spec file and the plugin kind.
pub(crate) fn plugins(
    spec: &Spec,
    spec_dir: &Path,
    spec_file: &str,
    overrides: &Overrides<'_>,
    artifact: &SamplerArtifact,
) -> Result<SolvePlugins, PluginSetupError> {
    let plugins_spec = &spec.plugins;
    let mut runtime = RuntimeOptions::default();
    let plugin_error =
        |kind: &'static str, error: SetupError| PluginSetupError::new(spec_file, kind, error);
    let planner = plugin_setup::planner(
        &plugin_setup::chosen(&plugins_spec.planner, spec_dir, overrides.planner),
        &mut runtime,
    )
    .map_err(|m| plugin_error("planner", m))?;
    let refiner = plugin_setup::refiner(
        &plugin_setup::chosen(&plugins_spec.refiner, spec_dir, overrides.refiner),
        artifact,
    )
    .map_err(|m| plugin_error("refiner", m))?;
    let motion = plugin_setup::motion(
        &plugin_setup::chosen(&plugins_spec.motion, spec_dir, overrides.motion),
        &mut runtime,
    )
    .map_err(|m| plugin_error("motion", m))?;
    Ok(SolvePlugins { planner, refiner, motion, runtime })
}

/// The solver's settings for `spec` with `overrides`; `cancelled` is polled to stop the search
/// (an interrupt, a time limit).
pub(crate) fn settings<'a>(
    spec: &Spec,
    runtime: &RuntimeOptions,
    overrides: &Overrides<'_>,
    cancelled: &'a dyn Fn() -> bool,
) -> SolveSettings<'a> {
    let mut config = MotionConfig::default();
    if let Some(resolution) = runtime.linear_resolution {
        config.linear_resolution = resolution;
    }
    if let Some(resolution) = runtime.angular_resolution {
        config.angular_resolution = resolution;
    }
    SolveSettings {
        seed: overrides.seed.unwrap_or(spec.seed),
        plan_count: overrides.plans.or(runtime.plan_count).unwrap_or(DEFAULT_PLAN_COUNT),
        planner_budget: PlanBudget { time_limit: runtime.planner_timeout, ..PlanBudget::default() },
        rounds: ROUNDS,
        max_refused: MAX_REFUSED,
        motion: MotionSettings {
            config,
            budget: MotionBudget {
                max_iterations: Some(MOTION_ITERATIONS),
                time_limit: runtime.motion_timeout,
            },
            grab_ranges: lamp_tamp::grab_ranges(spec),
        },
        relax_goal: !overrides.no_relax,
        cancelled,
    }
}
