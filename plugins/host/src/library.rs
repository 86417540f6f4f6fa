//! Plugin libraries: opening, validating, describing, and creating instances.

// Opens shared libraries and calls the plugin's `create`; each `unsafe` block states what has
// been validated before it.
#![allow(unsafe_code)]

use std::ffi::c_void;
use std::path::Path;
use std::sync::Arc;

use lamp_plugin_abi::{ByteSlice, ENTRY_SYMBOL, OwnedBytes, PluginEntry, TrustedEntry, status};
use lamp_plugin_api::{MotionPlanner, Planner, PluginError, Refiner};
use libloading::Library;

use crate::adapters::{
    Instance, LoadedMotionPlanner, LoadedPlanner, LoadedRefiner, status_to_error,
};
use crate::error::LoadError;
use crate::plugin_info::{PluginInfo, PluginKind};
use crate::validate::validate;

/// A validated plugin, from a shared library or linked into this process.
#[derive(Clone, Debug)]
pub struct PluginLibrary {
    entry: &'static PluginEntry,
    info: PluginInfo,
}

impl PluginLibrary {
    /// Opens the shared library at `path` and validates its entry table without running any
    /// plugin function.
    ///
    /// # Trust
    /// Opening a library runs its static initialisers, and the host believes the layout its entry
    /// table declares; load only libraries you would run. Refusals are typed and no plugin code
    /// runs after a refusal, but a library that lies about its tables can still crash the
    /// process. The library stays loaded for the rest of the process (see the crate docs).
    ///
    /// # Errors
    /// [`LoadError::Load`], [`LoadError::MissingSymbol`], [`LoadError::AbiMismatch`],
    /// [`LoadError::TableTooSmall`] or [`LoadError::InvalidDescriptor`].
    pub fn open(path: &Path) -> Result<Self, LoadError> {
        // SAFETY: loading runs the library's initialisers; that is the documented trust the
        // caller extends to the file (see "Trust" above).
        let library = unsafe { Library::new(path) }.map_err(|error| LoadError::Load {
            path: path.to_path_buf(),
            message: loader_message(&error),
        })?;
        // Never unloaded: every table pointer below then lives for the process.
        let library: &'static Library = Box::leak(Box::new(library));
        // SAFETY: the symbol is looked up as data (a pointer to the entry), not called.
        let symbol = unsafe { library.get::<*const PluginEntry>(ENTRY_SYMBOL) };
        let entry = match symbol {
            Ok(symbol) => *symbol,
            Err(_) => {
                return Err(LoadError::MissingSymbol {
                    path: path.to_path_buf(),
                    symbol: ENTRY_SYMBOL,
                });
            }
        };
        let origin = path.display().to_string();
        // SAFETY: `entry` is the address of the library's exported entry, static data of a
        // library that is never unloaded.
        let validated = unsafe { validate(entry, &origin) }?;
        Ok(Self { entry: validated.entry, info: validated.info })
    }

    /// Validates an entry table built in this process (a statically linked plugin), exactly as a
    /// loaded one.
    ///
    /// # Errors
    /// As for [`open`](Self::open), except the loading errors.
    pub fn from_trusted_entry(entry: TrustedEntry) -> Result<Self, LoadError> {
        // SAFETY: a `TrustedEntry` guarantees valid static tables.
        let validated = unsafe { validate(entry.entry(), "in-process") }?;
        Ok(Self { entry: validated.entry, info: validated.info })
    }

    /// What the plugin says it is.
    #[must_use]
    pub fn info(&self) -> &PluginInfo {
        &self.info
    }

    /// Creates a planner instance from `config`.
    ///
    /// # Errors
    /// [`LoadError::WrongKind`] when the plugin is not a planner; [`LoadError::Create`] or
    /// [`LoadError::Panicked`] when the plugin refuses.
    pub fn create_planner(&self, config: &[u8]) -> Result<Box<dyn Planner>, LoadError> {
        self.expect_kind(PluginKind::Planner)?;
        // SAFETY: validated: a planner entry has a non-null planner table.
        let vtable = unsafe { &*self.entry.planner };
        Ok(Box::new(LoadedPlanner::new(self.create(config)?, vtable)))
    }

    /// Creates a refiner instance from `config`.
    ///
    /// # Errors
    /// As for [`create_planner`](Self::create_planner).
    pub fn create_refiner(&self, config: &[u8]) -> Result<Box<dyn Refiner>, LoadError> {
        self.expect_kind(PluginKind::Refiner)?;
        // SAFETY: validated: a refiner entry has a non-null refiner table.
        let vtable = unsafe { &*self.entry.refiner };
        Ok(Box::new(LoadedRefiner::new(self.create(config)?, vtable)))
    }

    /// Creates a motion-planner instance from `config`.
    ///
    /// # Errors
    /// As for [`create_planner`](Self::create_planner).
    pub fn create_motion_planner(
        &self,
        config: &[u8],
    ) -> Result<Box<dyn MotionPlanner>, LoadError> {
        self.expect_kind(PluginKind::MotionPlanner)?;
        // SAFETY: validated: a motion-planner entry has a non-null motion-planner table.
        let vtable = unsafe { &*self.entry.motion_planner };
        Ok(Box::new(LoadedMotionPlanner::new(self.create(config)?, vtable)))
    }

    fn expect_kind(&self, expected: PluginKind) -> Result<(), LoadError> {
        if self.info.kind == expected {
            Ok(())
        } else {
            Err(LoadError::WrongKind {
                name: self.info.name.clone(),
                expected,
                found: self.info.kind,
            })
        }
    }

    fn create(&self, config: &[u8]) -> Result<Arc<Instance>, LoadError> {
        let create = self.entry.create.ok_or_else(|| LoadError::InvalidDescriptor {
            origin: self.info.origin.clone(),
            problem: "the required function `create` is null".to_string(),
        })?;
        let mut handle: *mut c_void = std::ptr::null_mut();
        let mut error = OwnedBytes::EMPTY;
        // SAFETY: a validated entry's `create`, called with a config slice and output slots that
        // are valid for the call.
        let code = unsafe { create(ByteSlice::new(config), &raw mut handle, &raw mut error) };
        let instance = Instance::new(self.entry, handle, self.info.name.clone());
        let message = instance.take_text(error);
        let name = self.info.name.clone();
        match code {
            status::OK if !handle.is_null() => Ok(Arc::new(instance)),
            status::OK => Err(LoadError::Create {
                name,
                source: PluginError::failed("`create` succeeded but returned a null instance"),
            }),
            status::PANICKED => Err(LoadError::Panicked { name, message }),
            code => Err(LoadError::Create { name, source: status_to_error(code, message) }),
        }
    }
}

/// libloading's error with the dynamic loader's own reason: its message alone is "dlopen
/// failed", and the reason ("…: cannot open shared object file: No such file or directory",
/// "…: invalid ELF header") is its source.
fn loader_message(error: &libloading::Error) -> String {
    let mut message = error.to_string();
    let mut cause = std::error::Error::source(error);
    while let Some(inner) = cause {
        message.push_str(&format!(": {inner}"));
        cause = inner.source();
    }
    message
}
