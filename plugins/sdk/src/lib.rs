//! Write lamp plugins in safe Rust.
//!
//! A plugin author implements one of the safe traits of lamp-plugin-api ([`api::Planner`],
//! [`api::Refiner`] or [`api::MotionPlanner`]) and [`PluginFactory`], then invokes
//! [`export_plugin!`] once in the library's root. The macro emits the C entry table that
//! lamp-plugin-host looks up, with one `extern "C"` trampoline per ABI function. The trampolines
//! live in this crate and:
//! - catch every panic at the boundary and report it as a `Panicked` status with its message
//!   (a panic unwinding out of an `extern "C"` function would abort the host);
//! - convert between the flat ABI data and the safe value types, decoding the versioned JSON
//!   documents of [`api::wire`] once per call;
//! - own all memory they hand to the host: it comes back through the plugin's own `free_*`
//!   functions, so host and plugin never free each other's allocations.
//!
//! # Example
//! ```
//! use lamp_plugin_sdk::api::{
//!     HostServices, Plan, PlanRequest, PlanResponse, PlanStatus, Planner, PluginError,
//! };
//! use lamp_plugin_sdk::{PluginFactory, export_plugin};
//!
//! /// Answers every request with the empty plan.
//! pub struct EmptyPlanner;
//!
//! impl Planner for EmptyPlanner {
//!     fn plan(
//!         &mut self,
//!         _request: &PlanRequest,
//!         _host: &dyn HostServices,
//!     ) -> Result<PlanResponse, PluginError> {
//!         Ok(PlanResponse { status: PlanStatus::Solved, plans: vec![Plan::default()] })
//!     }
//! }
//!
//! impl PluginFactory for EmptyPlanner {
//!     fn create(_config: &[u8]) -> Result<Self, PluginError> {
//!         Ok(EmptyPlanner)
//!     }
//! }
//!
//! export_plugin! {
//!     planner: EmptyPlanner,
//!     name: "empty-planner",
//!     version: "1.0.0",
//!     description: "Answers every request with the empty plan.",
//! }
//! ```

pub use lamp_plugin_abi as abi;
pub use lamp_plugin_api as api;

mod boundary;
#[doc(hidden)]
pub mod export;
mod host_proxy;

pub use export::{Descriptor, in_process_motion_planner, in_process_planner, in_process_refiner};

use lamp_plugin_api::PluginError;

/// How the host creates an instance of a plugin: from the configuration bytes it was given (the
/// plugin decides their format; often empty).
pub trait PluginFactory: Sized + Send + 'static {
    /// Creates an instance.
    ///
    /// # Errors
    /// [`PluginError`] when the configuration is not acceptable.
    fn create(config: &[u8]) -> Result<Self, PluginError>;
}

/// Exports a plugin from a `cdylib`: emits the static entry table named
/// [`abi::ENTRY_SYMBOL`] for one type implementing [`PluginFactory`] and one plugin trait.
///
/// ```text
/// export_plugin! {
///     planner: MyPlanner,            // or `refiner: MyRefiner`, `motion_planner: MyMotionPlanner`
///     name: "my-planner",            // non-empty
///     version: env!("CARGO_PKG_VERSION"),
///     description: "One line on what it does.",
/// }
/// ```
/// Use it once per library: a library holds one plugin.
#[macro_export]
macro_rules! export_plugin {
    (planner: $ty:ty, name: $name:expr, version: $version:expr, description: $description:expr $(,)?) => {
        $crate::export_plugin!(@abi($crate::abi::ABI_MAJOR, $crate::abi::ABI_MINOR)
            planner: $ty, name: $name, version: $version, description: $description);
    };
    (refiner: $ty:ty, name: $name:expr, version: $version:expr, description: $description:expr $(,)?) => {
        $crate::export_plugin!(@abi($crate::abi::ABI_MAJOR, $crate::abi::ABI_MINOR)
            refiner: $ty, name: $name, version: $version, description: $description);
    };
    (motion_planner: $ty:ty, name: $name:expr, version: $version:expr, description: $description:expr $(,)?) => {
        $crate::export_plugin!(@abi($crate::abi::ABI_MAJOR, $crate::abi::ABI_MINOR)
            motion_planner: $ty, name: $name, version: $version, description: $description);
    };
    // Reports the given ABI version instead of this SDK's; only for testing a host's refusal.
    (@abi($major:expr, $minor:expr) planner: $ty:ty, name: $name:expr, version: $version:expr, description: $description:expr $(,)?) => {
        $crate::export_plugin!(@emit $major, $minor, $ty, $name, $version, $description,
            PlannerVtable, planner_vtable, planner_entry);
    };
    (@abi($major:expr, $minor:expr) refiner: $ty:ty, name: $name:expr, version: $version:expr, description: $description:expr $(,)?) => {
        $crate::export_plugin!(@emit $major, $minor, $ty, $name, $version, $description,
            RefinerVtable, refiner_vtable, refiner_entry);
    };
    (@abi($major:expr, $minor:expr) motion_planner: $ty:ty, name: $name:expr, version: $version:expr, description: $description:expr $(,)?) => {
        $crate::export_plugin!(@emit $major, $minor, $ty, $name, $version, $description,
            MotionPlannerVtable, motion_planner_vtable, motion_planner_entry);
    };
    (@emit $major:expr, $minor:expr, $ty:ty, $name:expr, $version:expr, $description:expr,
        $vtable_type:ident, $vtable_fn:ident, $entry_fn:ident) => {
        const _: () = {
            static VTABLE: $crate::abi::$vtable_type = $crate::export::$vtable_fn::<$ty>();
            // `export_name` makes this table the library's one public symbol; every function it
            // points to is a panic-catching trampoline of lamp-plugin-sdk, so the plugin's own
            // code stays free of `unsafe`.
            #[allow(unsafe_code)]
            #[unsafe(export_name = "lamp_plugin_entry")]
            static ENTRY: $crate::abi::PluginEntry = $crate::abi::PluginEntry {
                abi_major: $major,
                abi_minor: $minor,
                ..$crate::export::$entry_fn::<$ty>(
                    $crate::Descriptor { name: $name, version: $version, description: $description },
                    &VTABLE,
                )
            };
        };
    };
}
