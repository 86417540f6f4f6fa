//! Test fixture: a planner library that declares the next ABI major version.
//!
//! A host must refuse it from its entry table alone. Its `create` aborts the process, so a host
//! that called anything before checking the version would fail its test loudly.

use lamp_plugin_sdk::abi::ABI_MAJOR;
use lamp_plugin_sdk::api::{HostServices, PlanRequest, PlanResponse, Planner, PluginError};
use lamp_plugin_sdk::{PluginFactory, export_plugin};

/// Never instantiated by a correct host.
pub struct FutureAbiPlanner;

impl PluginFactory for FutureAbiPlanner {
    fn create(_config: &[u8]) -> Result<Self, PluginError> {
        std::process::abort()
    }
}

impl Planner for FutureAbiPlanner {
    fn plan(&mut self, _: &PlanRequest, _: &dyn HostServices) -> Result<PlanResponse, PluginError> {
        std::process::abort()
    }
}

export_plugin! {
    @abi(ABI_MAJOR + 1, 0)
    planner: FutureAbiPlanner,
    name: "future-abi-planner",
    version: "2.0.0",
    description: "Declares the next ABI major; must be refused before any call.",
}
