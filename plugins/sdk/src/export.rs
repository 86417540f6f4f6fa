//! The generic `extern "C"` trampolines and entry tables behind [`crate::export_plugin!`].
//!
//! Public only so that the macro can name them from the plugin's crate; not a stable API.

// Trampolines dereference the host's pointers and the plugin's own instance handles; each
// `unsafe` block states the ABI rule it relies on.
#![allow(unsafe_code)]

use std::ffi::c_void;

use lamp_plugin_abi::{
    ABI_MAJOR, ABI_MINOR, ByteSlice, HostVtable, KIND_MOTION_PLANNER, KIND_PLANNER, KIND_REFINER,
    MOTION_NO_PATH, MOTION_PATH_FOUND, MotionPlannerVtable, MotionRequest as AbiMotionRequest,
    MotionResult, NO_PATH_BUDGET_EXHAUSTED, NO_PATH_GOAL_INVALID, NO_PATH_OTHER,
    NO_PATH_START_INVALID, OwnedBytes, PlanRequest as AbiPlanRequest, PlannerVtable,
    PluginDescriptor, PluginEntry, PluginKind, RefineRequest as AbiRefineRequest, RefinerVtable,
    Status, TrustedEntry, status, v1_0_sizes,
};
use lamp_plugin_api::wire::{self, WireDocument};
use lamp_plugin_api::{
    CandidateStream, MotionBudget, MotionOutcome, MotionPlanner, MotionRequest, NoPathReason,
    PlanBudget, PlanRequest, Planner, PluginError, RefineRequest, Refiner,
};

use crate::PluginFactory;
use crate::boundary::{
    bytes, f64s, free_bytes, free_f64s, guard, guard_silent, limit, owned_bytes, owned_f64s,
    sized_struct, text, time_limit, write_out,
};
use crate::host_proxy::HostProxy;

/// A plugin's name, version and one-line description.
#[derive(Clone, Copy, Debug)]
pub struct Descriptor {
    /// The plugin's name (non-empty).
    pub name: &'static str,
    /// The plugin's own version.
    pub version: &'static str,
    /// One line on what it does.
    pub description: &'static str,
}

const fn entry<T: PluginFactory>(kind: PluginKind, descriptor: Descriptor) -> PluginEntry {
    PluginEntry {
        abi_major: ABI_MAJOR,
        abi_minor: ABI_MINOR,
        struct_size: size_of::<PluginEntry>(),
        descriptor: PluginDescriptor {
            struct_size: size_of::<PluginDescriptor>(),
            kind,
            name: ByteSlice::from_text(descriptor.name),
            version: ByteSlice::from_text(descriptor.version),
            description: ByteSlice::from_text(descriptor.description),
        },
        create: Some(create::<T>),
        destroy: Some(destroy::<T>),
        free_bytes: Some(free_bytes),
        free_f64s: Some(free_f64s),
        get_extension: Some(get_extension),
        planner: std::ptr::null(),
        refiner: std::ptr::null(),
        motion_planner: std::ptr::null(),
    }
}

/// The entry table of planner `T`.
#[must_use]
pub const fn planner_entry<T: PluginFactory + Planner>(
    descriptor: Descriptor,
    vtable: &'static PlannerVtable,
) -> PluginEntry {
    PluginEntry { planner: vtable, ..entry::<T>(KIND_PLANNER, descriptor) }
}

/// The entry table of refiner `T`.
#[must_use]
pub const fn refiner_entry<T: PluginFactory + Refiner>(
    descriptor: Descriptor,
    vtable: &'static RefinerVtable,
) -> PluginEntry {
    PluginEntry { refiner: vtable, ..entry::<T>(KIND_REFINER, descriptor) }
}

/// The entry table of motion planner `T`.
#[must_use]
pub const fn motion_planner_entry<T: PluginFactory + MotionPlanner>(
    descriptor: Descriptor,
    vtable: &'static MotionPlannerVtable,
) -> PluginEntry {
    PluginEntry { motion_planner: vtable, ..entry::<T>(KIND_MOTION_PLANNER, descriptor) }
}

/// The planner table of `T`.
#[must_use]
pub const fn planner_vtable<T: PluginFactory + Planner>() -> PlannerVtable {
    PlannerVtable { struct_size: size_of::<PlannerVtable>(), plan: Some(plan::<T>) }
}

/// The refiner table of `T`.
#[must_use]
pub const fn refiner_vtable<T: PluginFactory + Refiner>() -> RefinerVtable {
    RefinerVtable {
        struct_size: size_of::<RefinerVtable>(),
        open_stream: Some(open_stream::<T>),
        next_candidate: Some(next_candidate),
        close_stream: Some(close_stream),
    }
}

/// The motion-planner table of `T`.
#[must_use]
pub const fn motion_planner_vtable<T: PluginFactory + MotionPlanner>() -> MotionPlannerVtable {
    MotionPlannerVtable {
        struct_size: size_of::<MotionPlannerVtable>(),
        plan_path: Some(plan_path::<T>),
    }
}

fn trusted(entry: PluginEntry) -> TrustedEntry {
    // Tables built in-process live for the process, like those of a library that is never
    // unloaded; one small leak per registered plugin.
    let entry: &'static PluginEntry = Box::leak(Box::new(entry));
    // SAFETY: every pointer in the table was just built by this crate from 'static data and
    // its own trampolines.
    unsafe { TrustedEntry::new(entry) }
}

/// The entry table of planner `T`, for use in this process without a shared library (the host
/// still validates it and calls it through the C ABI, as it would a loaded plugin).
#[must_use]
pub fn in_process_planner<T: PluginFactory + Planner>(descriptor: Descriptor) -> TrustedEntry {
    let vtable: &'static PlannerVtable = Box::leak(Box::new(planner_vtable::<T>()));
    trusted(planner_entry::<T>(descriptor, vtable))
}

/// The entry table of refiner `T`, for use in this process (see [`in_process_planner`]).
#[must_use]
pub fn in_process_refiner<T: PluginFactory + Refiner>(descriptor: Descriptor) -> TrustedEntry {
    let vtable: &'static RefinerVtable = Box::leak(Box::new(refiner_vtable::<T>()));
    trusted(refiner_entry::<T>(descriptor, vtable))
}

/// The entry table of motion planner `T`, for use in this process (see [`in_process_planner`]).
#[must_use]
pub fn in_process_motion_planner<T: PluginFactory + MotionPlanner>(
    descriptor: Descriptor,
) -> TrustedEntry {
    let vtable: &'static MotionPlannerVtable = Box::leak(Box::new(motion_planner_vtable::<T>()));
    trusted(motion_planner_entry::<T>(descriptor, vtable))
}

unsafe extern "C" fn create<T: PluginFactory>(
    config: ByteSlice,
    out_instance: *mut *mut c_void,
    out_error: *mut OwnedBytes,
) -> Status {
    guard(out_error, || {
        // SAFETY: the host's config slice is valid for the call (ABI rule for `create`).
        let config = unsafe { bytes(config) }?;
        let instance = Box::into_raw(Box::new(T::create(config)?)).cast::<c_void>();
        // SAFETY: `out_instance` is a writable slot for the call (ABI rule for `create`).
        if let Err(error) = unsafe { write_out(out_instance, instance, "out_instance") } {
            // SAFETY: `instance` was leaked just above and never handed out.
            drop(unsafe { Box::from_raw(instance.cast::<T>()) });
            return Err(error);
        }
        Ok(status::OK)
    })
}

unsafe extern "C" fn destroy<T: PluginFactory>(instance: *mut c_void) {
    guard_silent(|| {
        if !instance.is_null() {
            // SAFETY: instances are boxes leaked by `create::<T>`; the host destroys each once.
            drop(unsafe { Box::from_raw(instance.cast::<T>()) });
        }
    });
}

unsafe extern "C" fn get_extension(_id: ByteSlice) -> *const c_void {
    // ABI v1.0 defines no extension.
    std::ptr::null()
}

/// The plugin instance behind a handle.
///
/// # Safety
/// `instance` must be null or a handle made by `create::<T>` and not yet destroyed, used by one
/// thread at a time (ABI rule).
unsafe fn instance<'a, T>(instance: *mut c_void) -> Result<&'a mut T, PluginError> {
    // SAFETY: forwarded contract.
    unsafe { instance.cast::<T>().as_mut() }
        .ok_or_else(|| PluginError::invalid_request("the instance handle is null"))
}

fn decode<T: WireDocument>(bytes: &[u8]) -> Result<T, PluginError> {
    Ok(wire::decode::<T>(bytes)?)
}

fn encode<T: WireDocument>(value: &T) -> Result<Vec<u8>, PluginError> {
    // The plugin's own answer could not be written (a non-finite number): its failure, not the
    // request's.
    wire::encode(value).map_err(|error| PluginError::failed(error.to_string()))
}

unsafe extern "C" fn plan<T: PluginFactory + Planner>(
    instance_handle: *mut c_void,
    host: *const HostVtable,
    host_context: *mut c_void,
    request: *const AbiPlanRequest,
    out_response: *mut OwnedBytes,
    out_error: *mut OwnedBytes,
) -> Status {
    guard(out_error, || {
        // SAFETY: the ABI rules of `PlannerVtable::plan`: a live instance of this plugin, a host
        // table valid for the call, and a request valid for the call.
        let (planner, host, request) = unsafe {
            let planner = instance::<T>(instance_handle)?;
            let host = HostProxy::new(host, host_context)?;
            let request = sized_struct(
                request,
                |request| request.struct_size,
                v1_0_sizes::PLAN_REQUEST,
                "the plan request",
            )?;
            (planner, host, request)
        };
        let request = PlanRequest {
            // SAFETY: the request's slices are valid for the call.
            domain: unsafe { text(request.domain, "the domain") }?.to_string(),
            // SAFETY: as above.
            problem: unsafe { text(request.problem, "the problem") }?.to_string(),
            plan_count: usize::try_from(request.plan_count).unwrap_or(usize::MAX),
            budget: PlanBudget {
                max_expansions: limit(request.max_expansions),
                time_limit: time_limit(request.time_limit_seconds)?,
            },
            seed: request.seed,
        };
        let response = encode(&planner.plan(&request, &host)?)?;
        // SAFETY: `out_response` is a writable slot for the call.
        unsafe { write_out(out_response, owned_bytes(response), "out_response") }?;
        Ok(status::OK)
    })
}

/// A refiner stream behind a thin handle.
type StreamBox = Box<dyn CandidateStream>;

unsafe extern "C" fn open_stream<T: PluginFactory + Refiner>(
    instance_handle: *mut c_void,
    host: *const HostVtable,
    host_context: *mut c_void,
    request: *const AbiRefineRequest,
    out_stream: *mut *mut c_void,
    out_error: *mut OwnedBytes,
) -> Status {
    guard(out_error, || {
        // SAFETY: the ABI rules of `RefinerVtable::open_stream`, as for `plan`.
        let (refiner, host, request) = unsafe {
            let refiner = instance::<T>(instance_handle)?;
            let host = HostProxy::new(host, host_context)?;
            let request = sized_struct(
                request,
                |request| request.struct_size,
                v1_0_sizes::REFINE_REQUEST,
                "the refine request",
            )?;
            (refiner, host, request)
        };
        let request = RefineRequest {
            // SAFETY: the request's slices are valid for the call.
            action: decode(unsafe { bytes(request.action) }?)?,
            // SAFETY: as above.
            world: decode(unsafe { bytes(request.world) }?)?,
            seed: request.seed,
        };
        let stream: StreamBox = refiner.refine(&request, &host)?;
        let handle = Box::into_raw(Box::new(stream)).cast::<c_void>();
        // SAFETY: `out_stream` is a writable slot for the call.
        if let Err(error) = unsafe { write_out(out_stream, handle, "out_stream") } {
            // SAFETY: `handle` was leaked just above and never handed out.
            drop(unsafe { Box::from_raw(handle.cast::<StreamBox>()) });
            return Err(error);
        }
        Ok(status::OK)
    })
}

unsafe extern "C" fn next_candidate(
    stream: *mut c_void,
    host: *const HostVtable,
    host_context: *mut c_void,
    out_candidate: *mut OwnedBytes,
    out_error: *mut OwnedBytes,
) -> Status {
    guard(out_error, || {
        // SAFETY: the ABI rules of `RefinerVtable::next_candidate`: a live stream handle made by
        // `open_stream` and a host table valid for the call.
        let (stream, host) = unsafe {
            let stream = stream
                .cast::<StreamBox>()
                .as_mut()
                .ok_or_else(|| PluginError::invalid_request("the stream handle is null"))?;
            (stream, HostProxy::new(host, host_context)?)
        };
        let Some(candidate) = stream.next(&host)? else {
            return Ok(status::END_OF_STREAM);
        };
        let candidate = encode(&candidate)?;
        // SAFETY: `out_candidate` is a writable slot for the call.
        unsafe { write_out(out_candidate, owned_bytes(candidate), "out_candidate") }?;
        Ok(status::OK)
    })
}

unsafe extern "C" fn close_stream(stream: *mut c_void) {
    guard_silent(|| {
        if !stream.is_null() {
            // SAFETY: streams are boxes leaked by `open_stream`; the host closes each once.
            drop(unsafe { Box::from_raw(stream.cast::<StreamBox>()) });
        }
    });
}

unsafe extern "C" fn plan_path<T: PluginFactory + MotionPlanner>(
    instance_handle: *mut c_void,
    host: *const HostVtable,
    host_context: *mut c_void,
    request: *const AbiMotionRequest,
    out_result: *mut MotionResult,
    out_error: *mut OwnedBytes,
) -> Status {
    guard(out_error, || {
        // SAFETY: the ABI rules of `MotionPlannerVtable::plan_path`, as for `plan`.
        let (planner, host, request) = unsafe {
            let planner = instance::<T>(instance_handle)?;
            let host = HostProxy::new(host, host_context)?;
            let request = sized_struct(
                request,
                |request| request.struct_size,
                v1_0_sizes::MOTION_REQUEST,
                "the motion request",
            )?;
            (planner, host, request)
        };
        // SAFETY: the result slot is host-owned and valid for the call.
        let result = unsafe {
            sized_struct(
                out_result.cast_const(),
                |result| result.struct_size,
                v1_0_sizes::MOTION_RESULT,
                "the motion result",
            )
        }?;
        let result_size = result.struct_size;
        let request = MotionRequest {
            // SAFETY: the request's slices are valid for the call.
            robot: unsafe { text(request.robot, "the robot name") }?.to_string(),
            // SAFETY: as above.
            start: unsafe { f64s(request.start) }?.to_vec(),
            // SAFETY: as above.
            goal: unsafe { f64s(request.goal) }?.to_vec(),
            budget: MotionBudget {
                max_iterations: limit(request.max_iterations),
                time_limit: time_limit(request.time_limit_seconds)?,
            },
            seed: request.seed,
        };
        let dimension = request.start.len();
        let answer = match planner.plan_path(&request, &host)? {
            MotionOutcome::Path(waypoints) => {
                if let Some(odd) = waypoints.iter().find(|waypoint| waypoint.len() != dimension) {
                    return Err(PluginError::failed(format!(
                        "the path has a waypoint of {} values; the start has {dimension}",
                        odd.len()
                    )));
                }
                MotionResult {
                    struct_size: result_size,
                    outcome: MOTION_PATH_FOUND,
                    no_path_reason: 0,
                    waypoints: owned_f64s(waypoints.concat()),
                    message: OwnedBytes::EMPTY,
                }
            }
            MotionOutcome::NoPath { reason, message } => MotionResult {
                struct_size: result_size,
                outcome: MOTION_NO_PATH,
                no_path_reason: match reason {
                    NoPathReason::StartInvalid => NO_PATH_START_INVALID,
                    NoPathReason::GoalInvalid => NO_PATH_GOAL_INVALID,
                    NoPathReason::BudgetExhausted => NO_PATH_BUDGET_EXHAUSTED,
                    NoPathReason::Other => NO_PATH_OTHER,
                },
                waypoints: lamp_plugin_abi::OwnedF64s::EMPTY,
                message: owned_bytes(message.into_bytes()),
            },
        };
        // SAFETY: checked non-null and large enough for every v1.0 field written here.
        unsafe { out_result.write(answer) };
        Ok(status::OK)
    })
}
