//! Adapters from a plugin's C tables to the safe traits: each call converts the request to flat
//! ABI data, passes the host's callback table, and turns the status and plugin-owned outputs back
//! into values (returning every plugin allocation to the plugin's own `free_*` functions).

// Calls the plugin's validated `extern "C"` functions; each `unsafe` block states the ABI rule it
// relies on.
#![allow(unsafe_code)]

use std::ffi::c_void;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use lamp_plugin_abi::{
    ByteSlice, F64Slice, MOTION_NO_PATH, MOTION_PATH_FOUND, MotionPlannerVtable,
    MotionRequest as AbiMotionRequest, MotionResult, NO_LIMIT, NO_PATH_BUDGET_EXHAUSTED,
    NO_PATH_GOAL_INVALID, NO_PATH_START_INVALID, OwnedBytes, OwnedF64s,
    PlanRequest as AbiPlanRequest, PlannerVtable, PluginEntry, RefineRequest as AbiRefineRequest,
    RefinerVtable, Status, status,
};
use lamp_plugin_api::wire::{self, WireDocument};
use lamp_plugin_api::{
    Candidate, CandidateStream, HostError, HostServices, MotionOutcome, MotionPlanner,
    MotionRequest, NoPathReason, PlanRequest, PlanResponse, Planner, PluginError, RefineRequest,
    Refiner,
};

use crate::host_table::{HOST_VTABLE, context_of};

/// The error a plugin reported with `code` and `message` (the inverse of the SDK's encoding).
pub(crate) fn status_to_error(code: Status, message: String) -> PluginError {
    match code {
        status::FAILED => PluginError::Failed { message },
        status::PANICKED => PluginError::Panicked { message },
        status::INVALID_REQUEST => PluginError::InvalidRequest { message },
        status::CANCELLED => PluginError::Cancelled,
        status::UNSUPPORTED => PluginError::Host(HostError::Unsupported { service: message }),
        status::HOST_ERROR => PluginError::Host(HostError::Failed { message }),
        other => PluginError::failed(format!("unexpected status {other}: {message}")),
    }
}

/// One plugin instance. Calls on it and on its streams take `call_lock`, so the plugin sees one
/// call at a time as the ABI promises; it is destroyed after its last stream is closed.
pub(crate) struct Instance {
    entry: &'static PluginEntry,
    handle: *mut c_void,
    name: String,
    call_lock: Mutex<()>,
}

// SAFETY: the ABI lets an instance be used from any thread, one call at a time; `call_lock`
// serialises every call that passes the handle, and the handle is never dereferenced here.
unsafe impl Send for Instance {}
// SAFETY: as above; shared access only reaches the plugin through `call_lock`.
unsafe impl Sync for Instance {}

impl Instance {
    pub(crate) fn new(entry: &'static PluginEntry, handle: *mut c_void, name: String) -> Self {
        Self { entry, handle, name, call_lock: Mutex::new(()) }
    }

    /// Runs `call` while holding the instance's call lock.
    fn exclusive<R>(&self, call: impl FnOnce() -> R) -> R {
        // A poisoned lock only means an earlier call panicked on the host side; the plugin's
        // state is unaffected, so keep serving.
        let _guard = self.call_lock.lock().unwrap_or_else(PoisonError::into_inner);
        call()
    }

    /// Copies plugin-owned bytes and returns them to the plugin.
    pub(crate) fn take_bytes(&self, bytes: OwnedBytes) -> Vec<u8> {
        if bytes.data.is_null() {
            return Vec::new();
        }
        // SAFETY: non-null plugin-owned bytes are valid for `len` bytes until freed (ABI rule).
        let copy = unsafe { std::slice::from_raw_parts(bytes.data, bytes.len) }.to_vec();
        if let Some(free_bytes) = self.entry.free_bytes {
            // SAFETY: returned once to the plugin that allocated them.
            unsafe { free_bytes(bytes) };
        }
        copy
    }

    /// Copies plugin-owned text (lossily, if not UTF-8) and returns it to the plugin.
    pub(crate) fn take_text(&self, bytes: OwnedBytes) -> String {
        String::from_utf8_lossy(&self.take_bytes(bytes)).into_owned()
    }

    fn take_f64s(&self, values: OwnedF64s) -> Vec<f64> {
        if values.data.is_null() {
            return Vec::new();
        }
        // SAFETY: non-null plugin-owned values are valid for `len` values until freed.
        let copy = unsafe { std::slice::from_raw_parts(values.data, values.len) }.to_vec();
        if let Some(free_f64s) = self.entry.free_f64s {
            // SAFETY: returned once to the plugin that allocated them.
            unsafe { free_f64s(values) };
        }
        copy
    }

    fn decode<T: WireDocument>(&self, bytes: &[u8]) -> Result<T, PluginError> {
        wire::decode(bytes).map_err(|error| {
            PluginError::failed(format!("plugin `{}` answered with {error}", self.name))
        })
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        if let (false, Some(destroy)) = (self.handle.is_null(), self.entry.destroy) {
            // SAFETY: the handle came from this plugin's `create` and is destroyed once.
            unsafe { destroy(self.handle) };
        }
    }
}

fn limit(value: Option<u64>) -> u64 {
    value.unwrap_or(NO_LIMIT)
}

fn seconds(limit: Option<Duration>) -> f64 {
    limit.map_or(f64::INFINITY, |limit| limit.as_secs_f64())
}

/// A loaded planner.
pub(crate) struct LoadedPlanner {
    instance: Arc<Instance>,
    vtable: &'static PlannerVtable,
}

impl LoadedPlanner {
    pub(crate) fn new(instance: Arc<Instance>, vtable: &'static PlannerVtable) -> Self {
        Self { instance, vtable }
    }
}

impl Planner for LoadedPlanner {
    fn plan(
        &mut self,
        request: &PlanRequest,
        host: &dyn HostServices,
    ) -> Result<PlanResponse, PluginError> {
        let plan = self.vtable.plan.ok_or_else(|| PluginError::failed("`plan` is null"))?;
        let abi_request = AbiPlanRequest {
            struct_size: size_of::<AbiPlanRequest>(),
            domain: ByteSlice::from_text(&request.domain),
            problem: ByteSlice::from_text(&request.problem),
            plan_count: u64::try_from(request.plan_count).unwrap_or(u64::MAX),
            seed: request.seed,
            max_expansions: limit(request.budget.max_expansions),
            time_limit_seconds: seconds(request.budget.time_limit),
        };
        let mut response = OwnedBytes::EMPTY;
        let mut error = OwnedBytes::EMPTY;
        let code = self.instance.exclusive(|| {
            // SAFETY: a validated `plan` with this plugin's live instance, the host table and a
            // context valid for the call, and a request and output slots valid for the call.
            unsafe {
                plan(
                    self.instance.handle,
                    &HOST_VTABLE,
                    context_of(&host),
                    &abi_request,
                    &raw mut response,
                    &raw mut error,
                )
            }
        });
        let response = self.instance.take_bytes(response);
        let message = self.instance.take_text(error);
        match code {
            status::OK => self.instance.decode(&response),
            code => Err(status_to_error(code, message)),
        }
    }
}

/// A loaded refiner.
pub(crate) struct LoadedRefiner {
    instance: Arc<Instance>,
    vtable: &'static RefinerVtable,
}

impl LoadedRefiner {
    pub(crate) fn new(instance: Arc<Instance>, vtable: &'static RefinerVtable) -> Self {
        Self { instance, vtable }
    }
}

impl Refiner for LoadedRefiner {
    fn refine(
        &mut self,
        request: &RefineRequest,
        host: &dyn HostServices,
    ) -> Result<Box<dyn CandidateStream>, PluginError> {
        let open_stream =
            self.vtable.open_stream.ok_or_else(|| PluginError::failed("`open_stream` is null"))?;
        // A request the host cannot even write (a non-finite number) is the caller's error.
        let action = wire::encode(&request.action)?;
        let world = wire::encode(&request.world)?;
        let abi_request = AbiRefineRequest {
            struct_size: size_of::<AbiRefineRequest>(),
            action: ByteSlice::new(&action),
            world: ByteSlice::new(&world),
            seed: request.seed,
        };
        let mut stream: *mut c_void = std::ptr::null_mut();
        let mut error = OwnedBytes::EMPTY;
        let code = self.instance.exclusive(|| {
            // SAFETY: a validated `open_stream`, as for `plan`.
            unsafe {
                open_stream(
                    self.instance.handle,
                    &HOST_VTABLE,
                    context_of(&host),
                    &abi_request,
                    &raw mut stream,
                    &raw mut error,
                )
            }
        });
        let message = self.instance.take_text(error);
        match code {
            status::OK if !stream.is_null() => Ok(Box::new(LoadedStream {
                instance: Arc::clone(&self.instance),
                vtable: self.vtable,
                handle: stream,
            })),
            status::OK => Err(PluginError::failed("`open_stream` returned a null stream")),
            code => Err(status_to_error(code, message)),
        }
    }
}

/// A candidate stream of a loaded refiner.
struct LoadedStream {
    instance: Arc<Instance>,
    vtable: &'static RefinerVtable,
    handle: *mut c_void,
}

// SAFETY: as for `Instance`: the stream handle is only passed to the plugin under the instance's
// call lock, and the ABI lets it move between threads.
unsafe impl Send for LoadedStream {}

impl CandidateStream for LoadedStream {
    fn next(&mut self, host: &dyn HostServices) -> Result<Option<Candidate>, PluginError> {
        let next_candidate = self
            .vtable
            .next_candidate
            .ok_or_else(|| PluginError::failed("`next_candidate` is null"))?;
        let mut candidate = OwnedBytes::EMPTY;
        let mut error = OwnedBytes::EMPTY;
        let code = self.instance.exclusive(|| {
            // SAFETY: a validated `next_candidate` with a live stream of this plugin, the host
            // table and context, and output slots valid for the call.
            unsafe {
                next_candidate(
                    self.handle,
                    &HOST_VTABLE,
                    context_of(&host),
                    &raw mut candidate,
                    &raw mut error,
                )
            }
        });
        let candidate = self.instance.take_bytes(candidate);
        let message = self.instance.take_text(error);
        match code {
            status::OK => self.instance.decode(&candidate).map(Some),
            status::END_OF_STREAM => Ok(None),
            code => Err(status_to_error(code, message)),
        }
    }
}

impl Drop for LoadedStream {
    fn drop(&mut self) {
        if let Some(close_stream) = self.vtable.close_stream {
            // SAFETY: the stream came from this plugin's `open_stream` and is closed once,
            // before its instance is destroyed (this stream holds the instance alive).
            self.instance.exclusive(|| unsafe { close_stream(self.handle) });
        }
    }
}

/// A loaded motion planner.
pub(crate) struct LoadedMotionPlanner {
    instance: Arc<Instance>,
    vtable: &'static MotionPlannerVtable,
}

impl LoadedMotionPlanner {
    pub(crate) fn new(instance: Arc<Instance>, vtable: &'static MotionPlannerVtable) -> Self {
        Self { instance, vtable }
    }
}

/// `MotionResult::outcome` before the plugin writes it.
const OUTCOME_UNSET: u32 = u32::MAX;

impl MotionPlanner for LoadedMotionPlanner {
    fn plan_path(
        &mut self,
        request: &MotionRequest,
        host: &dyn HostServices,
    ) -> Result<MotionOutcome, PluginError> {
        let plan_path =
            self.vtable.plan_path.ok_or_else(|| PluginError::failed("`plan_path` is null"))?;
        let abi_request = AbiMotionRequest {
            struct_size: size_of::<AbiMotionRequest>(),
            robot: ByteSlice::from_text(&request.robot),
            start: F64Slice::new(&request.start),
            goal: F64Slice::new(&request.goal),
            seed: request.seed,
            max_iterations: limit(request.budget.max_iterations),
            time_limit_seconds: seconds(request.budget.time_limit),
        };
        let mut result = MotionResult {
            struct_size: size_of::<MotionResult>(),
            outcome: OUTCOME_UNSET,
            no_path_reason: 0,
            waypoints: OwnedF64s::EMPTY,
            message: OwnedBytes::EMPTY,
        };
        let mut error = OwnedBytes::EMPTY;
        let code = self.instance.exclusive(|| {
            // SAFETY: a validated `plan_path`, as for `plan`; `result` is host-owned and sized.
            unsafe {
                plan_path(
                    self.instance.handle,
                    &HOST_VTABLE,
                    context_of(&host),
                    &abi_request,
                    &raw mut result,
                    &raw mut error,
                )
            }
        });
        let flat =
            self.instance.take_f64s(std::mem::replace(&mut result.waypoints, OwnedF64s::EMPTY));
        let result_message =
            self.instance.take_text(std::mem::replace(&mut result.message, OwnedBytes::EMPTY));
        let message = self.instance.take_text(error);
        if code != status::OK {
            return Err(status_to_error(code, message));
        }
        match result.outcome {
            MOTION_PATH_FOUND => {
                let dimension = request.start.len();
                if dimension == 0 || !flat.len().is_multiple_of(dimension) {
                    return Err(PluginError::failed(format!(
                        "the path has {} values, not a multiple of the dimension {dimension}",
                        flat.len()
                    )));
                }
                Ok(MotionOutcome::Path(flat.chunks(dimension).map(<[f64]>::to_vec).collect()))
            }
            MOTION_NO_PATH => Ok(MotionOutcome::NoPath {
                reason: match result.no_path_reason {
                    NO_PATH_START_INVALID => NoPathReason::StartInvalid,
                    NO_PATH_GOAL_INVALID => NoPathReason::GoalInvalid,
                    NO_PATH_BUDGET_EXHAUSTED => NoPathReason::BudgetExhausted,
                    _ => NoPathReason::Other,
                },
                message: result_message,
            }),
            other => Err(PluginError::failed(format!("unknown motion outcome {other}"))),
        }
    }
}
