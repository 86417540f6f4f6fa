//! The `external` planner: a [`Planner`] that runs a classical planner installed on the machine,
//! Fast Downward for one plan and K* for the top k, on the request's domain and problem text.
//!
//! A call checks the PDDL with lamp-pddl, writes it into a scratch folder (removed afterwards),
//! runs the planner there under the request's time limit (polling the host's cancellation; both
//! kill the planner's whole process tree), reads the `sas_plan` files it wrote, and validates every
//! plan with lamp-planner's validator before returning it: a plan the task does not allow is an
//! error, never a result.
//!
//! - One plan (`plan_count` 1): Fast Downward's lazy greedy best-first search with FF and
//!   preferred operators (`--evaluator h=ff() --search lazy_greedy([h],preferred=[h])`).
//! - More plans: K* (`kstar(lmcut(),k=N)`), which returns the `N` cheapest plans in cost order;
//!   unlike lamp-planner's `topk`, its plans may revisit a state.
//!
//! The planner is found in this order: the option `command` (`kstar-command` for K*); for Fast
//! Downward then `fast-downward` and `fast-downward.py` on `PATH`, then the driver script inside
//! the pip package `up-fast-downward`; for K*, the pip package `kstar-planner`. Fast Downward's exit
//! codes decide the status (see [`exit_codes`]). The expansion budget and the seed are not used:
//! neither planner takes them, and both searches are deterministic.
//!
//! Linked statically, construct [`ExternalPlanner::new`]; built as a shared library, the
//! configuration is a JSON object of the options ([`ExternalOptions::from_config`]).

mod call;
mod error;
pub mod exit_codes;
mod options;
mod plan_files;
mod process;
mod resolve;
mod sas_plan;

use lamp_plugin_api::{HostServices, PlanRequest, PlanResponse, Planner, PluginError};
use lamp_plugin_sdk::PluginFactory;

pub use error::{ExternalError, INSTALL_HELP};
pub use options::{
    COMMAND_OPTION, CommandLine, DEFAULT_PYTHON, ExternalOptions, KSTAR_COMMAND_OPTION,
    PYTHON_OPTION,
};
pub use resolve::Engine;
pub use sas_plan::{SasPlan, SasPlanError, parse_sas_plan};

/// The planner of the plugin.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExternalPlanner {
    options: ExternalOptions,
    /// Commands found by earlier calls, so that the search for them runs once per engine.
    fast_downward: Option<CommandLine>,
    kstar: Option<CommandLine>,
}

impl ExternalPlanner {
    /// A planner with `options`. Nothing is looked up until a call needs it.
    #[must_use]
    pub fn new(options: ExternalOptions) -> Self {
        Self { options, fast_downward: None, kstar: None }
    }

    /// The options it runs with.
    #[must_use]
    pub fn options(&self) -> &ExternalOptions {
        &self.options
    }

    /// The command that runs `engine` (found once, then remembered).
    ///
    /// # Errors
    /// [`ExternalError::NotInstalled`] when no command is configured or found.
    pub fn command(&mut self, engine: Engine) -> Result<CommandLine, ExternalError> {
        let cached = match engine {
            Engine::FastDownward => &mut self.fast_downward,
            Engine::KStar => &mut self.kstar,
        };
        if let Some(command) = cached {
            return Ok(command.clone());
        }
        let command = resolve::resolve(engine, &self.options)?;
        *cached = Some(command.clone());
        Ok(command)
    }

    /// Plans `request` with the typed error of this crate ([`Planner::plan`] converts it).
    ///
    /// # Errors
    /// [`ExternalError`] when no planner is installed, it cannot run or fails, it writes a plan
    /// that does not parse or validate, or the host cancels.
    pub fn plan_external(
        &mut self,
        request: &PlanRequest,
        host: &dyn HostServices,
    ) -> Result<PlanResponse, ExternalError> {
        if host.is_cancelled() {
            return Err(ExternalError::Cancelled);
        }
        let engine = if request.plan_count > 1 { Engine::KStar } else { Engine::FastDownward };
        let command = self.command(engine)?;
        call::plan_with(engine, &command, request, host)
    }
}

impl PluginFactory for ExternalPlanner {
    fn create(config: &[u8]) -> Result<Self, PluginError> {
        Ok(Self::new(ExternalOptions::from_config(config)?))
    }
}

impl Planner for ExternalPlanner {
    fn plan(
        &mut self,
        request: &PlanRequest,
        host: &dyn HostServices,
    ) -> Result<PlanResponse, PluginError> {
        self.plan_external(request, host).map_err(|error| match error {
            ExternalError::Cancelled => PluginError::Cancelled,
            ExternalError::NotInstalled { .. } | ExternalError::Spawn { .. } => {
                PluginError::failed(format!("{error}; {INSTALL_HELP}"))
            }
            // The solver shows only the message: it must say that the goal was not judged.
            ExternalError::NoOutput { .. } => PluginError::failed(format!(
                "{error}; this says nothing about the goal: check that the command runs a Fast \
                 Downward driver, or set the plugin's `command` option to one"
            )),
            other => PluginError::failed(other.to_string()),
        })
    }
}

#[cfg(feature = "shared-library")]
lamp_plugin_sdk::export_plugin! {
    planner: ExternalPlanner,
    name: "lamp-external-planner",
    version: env!("CARGO_PKG_VERSION"),
    description: "Runs Fast Downward (one plan) or K* (top k) as an external process; \
                  config lines `command ...`, `kstar-command ...`, `python ...`.",
}
