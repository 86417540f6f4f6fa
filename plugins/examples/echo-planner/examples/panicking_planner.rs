//! Test fixture: a planner library whose `plan` panics, to check that the panic is caught at the
//! boundary and reported as `PluginError::Panicked` instead of aborting the host.

use lamp_plugin_sdk::api::{HostServices, PlanRequest, PlanResponse, Planner, PluginError};
use lamp_plugin_sdk::{PluginFactory, export_plugin};

/// Panics on every request.
pub struct PanickingPlanner;

impl PluginFactory for PanickingPlanner {
    fn create(_config: &[u8]) -> Result<Self, PluginError> {
        Ok(PanickingPlanner)
    }
}

impl Planner for PanickingPlanner {
    fn plan(
        &mut self,
        request: &PlanRequest,
        _: &dyn HostServices,
    ) -> Result<PlanResponse, PluginError> {
        panic!("deliberate panic while planning with seed {}", request.seed)
    }
}

export_plugin! {
    planner: PanickingPlanner,
    name: "panicking-planner",
    version: "1.0.0",
    description: "Panics on every request.",
}
