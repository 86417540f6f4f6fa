//! Test fixture: a planner library whose `plan` never returns and never checks for cancellation,
//! to check that the host's time limit holds whatever a plugin does.

use lamp_plugin_sdk::api::{HostServices, PlanRequest, PlanResponse, Planner, PluginError};
use lamp_plugin_sdk::{PluginFactory, export_plugin};

/// Sleeps forever on every request.
pub struct HangingPlanner;

impl PluginFactory for HangingPlanner {
    fn create(_config: &[u8]) -> Result<Self, PluginError> {
        Ok(HangingPlanner)
    }
}

impl Planner for HangingPlanner {
    fn plan(&mut self, _: &PlanRequest, _: &dyn HostServices) -> Result<PlanResponse, PluginError> {
        loop {
            std::thread::sleep(std::time::Duration::from_secs(60));
        }
    }
}

export_plugin! {
    planner: HangingPlanner,
    name: "hanging-planner",
    version: "1.0.0",
    description: "Never returns from a request.",
}
