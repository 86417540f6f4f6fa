//! Checks an entry table before anything in it is called: ABI version first (at offsets every
//! version shares), then table sizes, required functions and the descriptor.

// Reads the plugin's static tables through raw pointers; each `unsafe` block states what has been
// checked before it.
#![allow(unsafe_code)]

use lamp_plugin_abi::{
    ABI_MAJOR, ABI_MINOR, ByteSlice, KIND_MOTION_PLANNER, KIND_PLANNER, KIND_REFINER, PluginEntry,
    v1_0_sizes,
};

use crate::error::LoadError;
use crate::plugin_info::{PluginInfo, PluginKind};

/// A validated entry and what it describes.
pub(crate) struct Validated {
    pub entry: &'static PluginEntry,
    pub info: PluginInfo,
}

/// Validates the entry table at `entry`.
///
/// # Safety
/// `entry` must point to static data of a library that stays loaded: at least the two leading
/// `u32` of a [`PluginEntry`], and, if they name ABI major [`ABI_MAJOR`], a whole v1.0 entry whose
/// non-null pointers point to static data as the ABI documents.
pub(crate) unsafe fn validate(
    entry: *const PluginEntry,
    origin: &str,
) -> Result<Validated, LoadError> {
    let invalid =
        |problem: String| LoadError::InvalidDescriptor { origin: origin.to_string(), problem };
    if entry.is_null() {
        return Err(invalid("the entry symbol is null".to_string()));
    }
    // SAFETY: the two leading `u32` are present in every ABI version (caller's contract).
    let (plugin_major, plugin_minor) = unsafe {
        let versions = entry.cast::<u32>();
        (versions.read(), versions.add(1).read())
    };
    if plugin_major != ABI_MAJOR || plugin_minor > ABI_MINOR {
        return Err(LoadError::AbiMismatch {
            origin: origin.to_string(),
            plugin_major,
            plugin_minor,
            host_major: ABI_MAJOR,
            host_minor: ABI_MINOR,
        });
    }
    // SAFETY: major 1: the plugin promises a whole v1.0 entry (caller's contract).
    let entry: &'static PluginEntry = unsafe { &*entry };
    let too_small =
        |table: &'static str, declared: usize, required: usize| LoadError::TableTooSmall {
            origin: origin.to_string(),
            table,
            declared,
            required,
            host_major: ABI_MAJOR,
        };
    if entry.struct_size < v1_0_sizes::ENTRY {
        return Err(too_small("entry table", entry.struct_size, v1_0_sizes::ENTRY));
    }
    let descriptor = &entry.descriptor;
    if descriptor.struct_size < v1_0_sizes::DESCRIPTOR {
        return Err(too_small("descriptor", descriptor.struct_size, v1_0_sizes::DESCRIPTOR));
    }
    // SAFETY: descriptor strings are static data of the plugin (caller's contract).
    let name = unsafe { static_text(descriptor.name) }
        .ok_or_else(|| invalid("the name is not UTF-8".to_string()))?;
    if name.trim().is_empty() {
        return Err(invalid("the name is empty".to_string()));
    }
    let named_origin = || format!("{origin} (plugin `{name}`)");
    // SAFETY: as above.
    let version = unsafe { static_text(descriptor.version) }
        .ok_or_else(|| invalid(format!("the version of `{name}` is not UTF-8")))?;
    // SAFETY: as above.
    let description = unsafe { static_text(descriptor.description) }
        .ok_or_else(|| invalid(format!("the description of `{name}` is not UTF-8")))?;
    let missing = |function: &str| LoadError::InvalidDescriptor {
        origin: named_origin(),
        problem: format!("the required function `{function}` is null"),
    };
    if entry.create.is_none() {
        return Err(missing("create"));
    }
    if entry.destroy.is_none() {
        return Err(missing("destroy"));
    }
    if entry.free_bytes.is_none() {
        return Err(missing("free_bytes"));
    }
    if entry.free_f64s.is_none() {
        return Err(missing("free_f64s"));
    }
    let kind = match descriptor.kind {
        KIND_PLANNER => {
            // SAFETY: non-null vtable pointers point to static tables (caller's contract).
            let Some(vtable) = (unsafe { entry.planner.as_ref() }) else {
                return Err(missing("planner table"));
            };
            if vtable.struct_size < v1_0_sizes::PLANNER {
                return Err(too_small("planner table", vtable.struct_size, v1_0_sizes::PLANNER));
            }
            if vtable.plan.is_none() {
                return Err(missing("plan"));
            }
            PluginKind::Planner
        }
        KIND_REFINER => {
            // SAFETY: as above.
            let Some(vtable) = (unsafe { entry.refiner.as_ref() }) else {
                return Err(missing("refiner table"));
            };
            if vtable.struct_size < v1_0_sizes::REFINER {
                return Err(too_small("refiner table", vtable.struct_size, v1_0_sizes::REFINER));
            }
            if vtable.open_stream.is_none() {
                return Err(missing("open_stream"));
            }
            if vtable.next_candidate.is_none() {
                return Err(missing("next_candidate"));
            }
            if vtable.close_stream.is_none() {
                return Err(missing("close_stream"));
            }
            PluginKind::Refiner
        }
        KIND_MOTION_PLANNER => {
            // SAFETY: as above.
            let Some(vtable) = (unsafe { entry.motion_planner.as_ref() }) else {
                return Err(missing("motion-planner table"));
            };
            if vtable.struct_size < v1_0_sizes::MOTION_PLANNER {
                let size = vtable.struct_size;
                return Err(too_small("motion-planner table", size, v1_0_sizes::MOTION_PLANNER));
            }
            if vtable.plan_path.is_none() {
                return Err(missing("plan_path"));
            }
            PluginKind::MotionPlanner
        }
        other => return Err(invalid(format!("`{name}` has the unknown kind {other}"))),
    };
    let info = PluginInfo {
        kind,
        name: name.to_string(),
        version: version.to_string(),
        description: description.to_string(),
        abi_major: plugin_major,
        abi_minor: plugin_minor,
        origin: origin.to_string(),
    };
    Ok(Validated { entry, info })
}

/// The text of a static slice, or `None` when it is not UTF-8 (or null with a length).
///
/// # Safety
/// `slice` must be valid for `len` bytes for the life of the process.
unsafe fn static_text(slice: ByteSlice) -> Option<&'static str> {
    if slice.len == 0 {
        return Some("");
    }
    if slice.data.is_null() {
        return None;
    }
    // SAFETY: non-null and valid for `len` bytes by the caller's contract.
    let bytes = unsafe { std::slice::from_raw_parts(slice.data, slice.len) };
    std::str::from_utf8(bytes).ok()
}

#[cfg(test)]
mod tests {
    use lamp_plugin_abi::{KIND_REFINER, PlannerVtable};
    use lamp_plugin_api::{HostServices, PlanRequest, PlanResponse, Planner, PluginError};
    use lamp_plugin_sdk::{Descriptor, PluginFactory, in_process_planner};

    use super::*;

    struct Idle;

    impl PluginFactory for Idle {
        fn create(_config: &[u8]) -> Result<Self, PluginError> {
            Ok(Idle)
        }
    }

    impl Planner for Idle {
        fn plan(
            &mut self,
            _: &PlanRequest,
            _: &dyn HostServices,
        ) -> Result<PlanResponse, PluginError> {
            Err(PluginError::failed("idle"))
        }
    }

    fn valid() -> PluginEntry {
        let descriptor = Descriptor { name: "idle", version: "1.2.3", description: "does nothing" };
        *in_process_planner::<Idle>(descriptor).entry()
    }

    fn check(entry: PluginEntry) -> Result<PluginInfo, LoadError> {
        let entry: &'static PluginEntry = Box::leak(Box::new(entry));
        // SAFETY: a copy of an SDK-built entry, leaked for the life of the test process.
        unsafe { validate(entry, "test") }.map(|validated| validated.info)
    }

    fn problem(error: LoadError) -> String {
        match error {
            LoadError::InvalidDescriptor { problem, .. } => problem,
            other => panic!("expected an invalid descriptor, got {other:?}"),
        }
    }

    #[test]
    fn a_valid_entry_is_described() {
        let info = check(valid()).unwrap();
        assert_eq!(info.kind, PluginKind::Planner);
        assert_eq!((info.name.as_str(), info.version.as_str()), ("idle", "1.2.3"));
        assert_eq!(info.description, "does nothing");
        assert_eq!((info.abi_major, info.abi_minor, info.origin.as_str()), (1, 1, "test"));
    }

    #[test]
    fn plugins_of_this_or_an_older_minor_load() {
        for minor in [0, ABI_MINOR] {
            let info = check(PluginEntry { abi_minor: minor, ..valid() }).unwrap();
            assert_eq!((info.abi_major, info.abi_minor), (1, minor));
        }
    }

    #[test]
    fn other_majors_and_newer_minors_are_refused() {
        for (major, minor) in [(0, 0), (2, 0), (2, 1), (1, ABI_MINOR + 1)] {
            let entry = PluginEntry { abi_major: major, abi_minor: minor, ..valid() };
            assert!(
                matches!(check(entry), Err(LoadError::AbiMismatch { plugin_major, plugin_minor, .. })
                    if (plugin_major, plugin_minor) == (major, minor)),
                "v{major}.{minor}"
            );
        }
    }

    #[test]
    fn tables_smaller_than_v1_0_are_refused() {
        let entry = PluginEntry { struct_size: v1_0_sizes::ENTRY - 8, ..valid() };
        assert!(matches!(check(entry), Err(LoadError::TableTooSmall { table: "entry table", .. })));
        let mut entry = valid();
        entry.descriptor.struct_size = 8;
        assert!(matches!(check(entry), Err(LoadError::TableTooSmall { table: "descriptor", .. })));
        // SAFETY: the planner table of an SDK-built planner entry.
        let mut vtable: PlannerVtable = unsafe { *valid().planner };
        vtable.struct_size = 4;
        let entry = PluginEntry { planner: Box::leak(Box::new(vtable)), ..valid() };
        assert!(matches!(
            check(entry),
            Err(LoadError::TableTooSmall { table: "planner table", declared: 4, .. })
        ));
    }

    #[test]
    fn malformed_descriptors_and_missing_functions_are_refused() {
        let mut entry = valid();
        entry.descriptor.name = ByteSlice::new(b"\xff\xfe");
        assert_eq!(problem(check(entry).unwrap_err()), "the name is not UTF-8");
        let mut entry = valid();
        entry.descriptor.kind = 9;
        assert_eq!(problem(check(entry).unwrap_err()), "`idle` has the unknown kind 9");
        let mut entry = valid();
        entry.descriptor.kind = KIND_REFINER;
        assert!(problem(check(entry).unwrap_err()).contains("`refiner table` is null"));
        let entry = PluginEntry { create: None, ..valid() };
        assert!(problem(check(entry).unwrap_err()).contains("`create` is null"));
        let entry = PluginEntry { free_bytes: None, ..valid() };
        assert!(problem(check(entry).unwrap_err()).contains("`free_bytes` is null"));
        // SAFETY: as above.
        let mut vtable: PlannerVtable = unsafe { *valid().planner };
        vtable.plan = None;
        let entry = PluginEntry { planner: Box::leak(Box::new(vtable)), ..valid() };
        assert!(problem(check(entry).unwrap_err()).contains("`plan` is null"));
    }
}
