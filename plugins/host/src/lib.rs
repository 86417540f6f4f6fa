//! The plugin host: loads plugins from shared libraries (or takes statically linked ones through
//! the same C ABI), validates them before trusting them, and adapts their C tables back to the
//! safe traits of lamp-plugin-api, so the runtime sees `Box<dyn Planner>`, `Box<dyn Refiner>` and
//! `Box<dyn MotionPlanner>` wherever a plugin comes from.
//!
//! Validation happens before any plugin code runs: the entry is static data, so the host reads
//! the ABI major and minor, the struct sizes and the descriptor (kind, name, version) and refuses
//! a plugin that does not fit with a typed [`LoadError`] carrying a `lamp::plugin::*` code.
//!
//! Libraries are never unloaded: once opened, a library stays mapped for the rest of the process.
//! Unloading is unreliable (`dlclose` may be a no-op, thread-local destructors and leaked
//! callbacks would point into unmapped code), and keeping them gives every table the host holds a
//! true `'static` lifetime.

mod adapters;
mod error;
mod host_table;
mod library;
mod plugin_info;
mod validate;

pub use error::LoadError;
pub use library::PluginLibrary;
pub use plugin_info::{PluginInfo, PluginKind};
