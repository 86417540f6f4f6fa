//! The C ABI between the lamp host and its plugins: the one exported entry table, one vtable per
//! plugin kind, the host's callback vtable, status codes and the ABI version.
//!
//! Everything here is `#[repr(C)]` flat data: integers, `f64`, `bool`, pointer-plus-length
//! slices and nullable function pointers. No Rust trait object, `Vec`, `String` or generic type
//! crosses the boundary, so a plugin built by another compiler version (or written in C or C++)
//! can be loaded.
//!
//! # Versioning
//! The ABI version ([`ABI_MAJOR`].[`ABI_MINOR`]) is independent of every crate version.
//! A host accepts a plugin whose major equals its own and whose minor is not newer.
//! Every struct that may grow starts with a `struct_size` field and only ever gains fields at its
//! end; each field says in which ABI version it appeared ("Since v1.0"). A reader uses a field only
//! when the writer's `struct_size` covers it.
//!
//! # Ownership
//! Whoever allocates frees: memory a plugin returns ([`OwnedBytes`], [`OwnedF64s`]) goes back to
//! the plugin's own [`PluginEntry::free_bytes`] / [`PluginEntry::free_f64s`]; everything the host
//! passes in (slices, requests, the host vtable) is borrowed for the duration of one call only.
//! The host writes its callback results into buffers the plugin provides ([`F64Buffer`],
//! [`ErrorBuffer`]), so no allocation crosses from host to plugin.
//!
//! # Threads
//! One plugin instance is called from one thread at a time, but not always the same thread.
//!
//! # The safety argument
//! Every `unsafe` block of the host and of lamp-plugin-sdk relies on these rules and names the
//! one it uses ("ABI rule"); nothing else is assumed of the peer.
//! 1. What a caller lends (slices, requests, the host table and its context) is valid for reads
//!    during the one call; a slice's `data` may be null only when its `len` is 0.
//! 2. An output slot or buffer a caller lends is null or valid for writes during the call; a
//!    callee writes at most a buffer's `capacity` and reports what it wrote in `len`.
//! 3. Memory a plugin hands out goes back to that plugin's own `free_*`, exactly once.
//! 4. A field is read only when the writer's `struct_size` covers it.
//! 5. No unwinding crosses the boundary: every callback and trampoline catches panics.
//! 6. An instance sees one call at a time (see Threads).

#![no_std]
// The ABI is a set of `#[repr(C)]` declarations holding raw pointers; a few `unsafe impl Sync`
// (for statics of immutable tables) and one `unsafe` constructor are its whole unsafe surface.
#![allow(unsafe_code)]

use core::ffi::c_void;
use core::mem::{offset_of, size_of};

/// The ABI major version; a host refuses any plugin with another major.
/// Since v1.0.
pub const ABI_MAJOR: u32 = 1;

/// The ABI minor version; a host refuses plugins with a newer minor than its own.
/// Since v1.0; v1.1 added [`HostVtable::sample_configuration`].
pub const ABI_MINOR: u32 = 1;

/// The name of the one symbol a plugin library exports: a static [`PluginEntry`] (data, not a
/// function, so the host can check it without running any plugin code).
/// Since v1.0.
pub const ENTRY_SYMBOL: &str = "lamp_plugin_entry";

/// [`ENTRY_SYMBOL`] with its terminating NUL, as dynamic loaders want it.
/// Since v1.0.
pub const ENTRY_SYMBOL_NUL: &[u8] = b"lamp_plugin_entry\0";

/// A status code returned by every ABI function that can fail.
pub type Status = i32;

/// The status codes. Unknown codes from a newer peer are treated as [`status::FAILED`].
pub mod status {
    use super::Status;

    /// The call succeeded and wrote its outputs. Since v1.0.
    pub const OK: Status = 0;
    /// The callee failed for its own reason; a UTF-8 message is in the error output. Since v1.0.
    pub const FAILED: Status = 1;
    /// The callee panicked; the panic message is in the error output. Since v1.0.
    pub const PANICKED: Status = 2;
    /// The request could not be understood (malformed document, wrong wire version). Since v1.0.
    pub const INVALID_REQUEST: Status = 3;
    /// The callee stopped because the host asked to cancel. Since v1.0.
    pub const CANCELLED: Status = 4;
    /// A candidate stream has no further candidate. Since v1.0.
    pub const END_OF_STREAM: Status = 5;
    /// An output buffer was too small; its `len` holds the length needed. Since v1.0.
    pub const BUFFER_TOO_SMALL: Status = 6;
    /// The host does not offer the requested service. Since v1.0.
    pub const UNSUPPORTED: Status = 7;
    /// A host service failed; the message is in the error buffer. Since v1.0.
    pub const HOST_ERROR: Status = 8;
}

/// What a plugin is. Since v1.0.
pub type PluginKind = u32;

/// A task planner: PDDL in, plans out. Since v1.0.
pub const KIND_PLANNER: PluginKind = 1;
/// A refiner: grounded action and world state in, a stream of target configurations out.
/// Since v1.0.
pub const KIND_REFINER: PluginKind = 2;
/// A motion planner: start and goal configurations in, a path out. Since v1.0.
pub const KIND_MOTION_PLANNER: PluginKind = 3;

/// "No limit" for the `u64` budget fields.
pub const NO_LIMIT: u64 = u64::MAX;

/// A pose as seven `f64`: position x, y, z then unit quaternion qx, qy, qz, qw.
pub type Pose = [f64; 7];

/// Borrowed bytes (UTF-8 where the field says text), valid for the duration of one call unless
/// stated otherwise. `data` may be null only when `len` is 0.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct ByteSlice {
    /// First byte.
    pub data: *const u8,
    /// Number of bytes.
    pub len: usize,
}

impl ByteSlice {
    /// The empty slice.
    pub const EMPTY: Self = Self { data: core::ptr::null(), len: 0 };

    /// Borrows `bytes`.
    #[must_use]
    pub const fn new(bytes: &[u8]) -> Self {
        Self { data: bytes.as_ptr(), len: bytes.len() }
    }

    /// Borrows the UTF-8 bytes of `text`.
    #[must_use]
    pub const fn from_text(text: &str) -> Self {
        Self::new(text.as_bytes())
    }
}

/// Borrowed `f64` values, valid for the duration of one call. `data` may be null only when
/// `len` is 0.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct F64Slice {
    /// First value.
    pub data: *const f64,
    /// Number of values.
    pub len: usize,
}

impl F64Slice {
    /// Borrows `values`.
    #[must_use]
    pub const fn new(values: &[f64]) -> Self {
        Self { data: values.as_ptr(), len: values.len() }
    }
}

/// Bytes allocated by the plugin and handed to the host, which copies them and then returns them
/// to the plugin's [`PluginEntry::free_bytes`]. `data` is null when `len` is 0.
#[repr(C)]
#[derive(Debug)]
pub struct OwnedBytes {
    /// First byte.
    pub data: *mut u8,
    /// Number of bytes (also the allocation's size).
    pub len: usize,
}

impl OwnedBytes {
    /// Nothing allocated.
    pub const EMPTY: Self = Self { data: core::ptr::null_mut(), len: 0 };
}

/// `f64` values allocated by the plugin, returned to its [`PluginEntry::free_f64s`].
/// `data` is null when `len` is 0.
#[repr(C)]
#[derive(Debug)]
pub struct OwnedF64s {
    /// First value.
    pub data: *mut f64,
    /// Number of values (also the allocation's size).
    pub len: usize,
}

impl OwnedF64s {
    /// Nothing allocated.
    pub const EMPTY: Self = Self { data: core::ptr::null_mut(), len: 0 };
}

/// A plugin-provided buffer the host writes `f64` values into.
/// On success the host sets `len` to the number written; when `capacity` is too small it writes
/// nothing, sets `len` to the number needed and returns [`status::BUFFER_TOO_SMALL`].
#[repr(C)]
#[derive(Debug)]
pub struct F64Buffer {
    /// First writable value.
    pub data: *mut f64,
    /// Number of writable values.
    pub capacity: usize,
    /// Set by the host.
    pub len: usize,
}

/// A plugin-provided buffer the host writes a UTF-8 error message into, truncated at a character
/// boundary to `capacity` bytes; `len` is the number of bytes written.
#[repr(C)]
#[derive(Debug)]
pub struct ErrorBuffer {
    /// First writable byte.
    pub data: *mut u8,
    /// Number of writable bytes.
    pub capacity: usize,
    /// Set by the host.
    pub len: usize,
}

/// Calls the macro `$then` with the description of every fallible host service, in the order of
/// their fields in [`HostVtable`]: the one place a service's C signature is written.
///
/// Each entry reads
/// `fn name(argument: AbiType as RustType, ...) writes (output: *mut Slot, ...) as Answer;`:
/// the callback takes the host's `context`, then the arguments, then the output slots, then an
/// [`ErrorBuffer`], and returns a [`Status`]; the `as` types are the
/// `lamp_plugin_api::HostServices` method's argument and answer types. This crate declares the
/// table from it; the host generates its `extern "C"` callbacks and the SDK its calls through the
/// table, so a signature cannot differ between the three. `report_progress` and `is_cancelled`
/// cannot fail and have no outputs; they are written out by hand beside it.
///
/// A new service goes at the end, with the minor version it appeared in: a peer reads a field
/// only when the other side's `struct_size` covers it.
#[macro_export]
macro_rules! for_each_host_service {
    ($then:ident) => {
        $then! {
            /// Whether configuration `q` of robot `robot` is within limits and collision-free.
            /// Since v1.0.
            fn configuration_is_valid(robot: $crate::ByteSlice as &str, q: $crate::F64Slice as &[f64])
                writes (out_valid: *mut bool) as bool;
            /// Whether the straight segment from `a` to `b` (in the host's interpolation) is
            /// valid. Since v1.0.
            fn edge_is_valid(
                robot: $crate::ByteSlice as &str,
                a: $crate::F64Slice as &[f64],
                b: $crate::F64Slice as &[f64]
            ) writes (out_valid: *mut bool) as bool;
            /// Inverse kinematics of link `link` to `target`, starting from `seed_q`. Sets
            /// `out_found`; when found, writes the configuration into `out_q`. Since v1.0.
            fn solve_ik(
                robot: $crate::ByteSlice as &str,
                link: $crate::ByteSlice as &str,
                target: *const $crate::Pose as &$crate::Pose,
                seed_q: $crate::F64Slice as &[f64]
            ) writes (out_found: *mut bool, out_q: *mut $crate::F64Buffer) as Option<Vec<f64>>;
            /// World pose of link `link` at configuration `q`. Since v1.0.
            fn forward_kinematics(
                robot: $crate::ByteSlice as &str,
                q: $crate::F64Slice as &[f64],
                link: $crate::ByteSlice as &str
            ) writes (out_pose: *mut $crate::Pose) as $crate::Pose;
            /// The host's configuration-space distance between `a` and `b`. Since v1.0.
            fn distance(
                robot: $crate::ByteSlice as &str,
                a: $crate::F64Slice as &[f64],
                b: $crate::F64Slice as &[f64]
            ) writes (out_distance: *mut f64) as f64;
            /// The configuration a fraction `t` in [0, 1] of the way from `a` to `b`. Since v1.0.
            fn interpolate(
                robot: $crate::ByteSlice as &str,
                a: $crate::F64Slice as &[f64],
                b: $crate::F64Slice as &[f64],
                t: f64 as f64
            ) writes (out_q: *mut $crate::F64Buffer) as Vec<f64>;
            /// A configuration of `robot` drawn uniformly over its sampling space by the host's
            /// own generator seeded with `seed` (the same seed gives the same configuration),
            /// written into `out_q`. A plugin calls it only when the host's `struct_size` covers
            /// this field (see [`v1_1_sizes::HOST`]). Since v1.1.
            fn sample_configuration(robot: $crate::ByteSlice as &str, seed: u64 as u64)
                writes (out_q: *mut $crate::F64Buffer) as Vec<f64>;
        }
    };
}

/// Declares [`HostVtable`] from the service descriptions.
macro_rules! host_vtable {
    ($(
        $(#[$doc:meta])*
        fn $name:ident($($argument:ident: $raw:ty as $rust:ty),* $(,)?)
            writes ($($output:ident: $slot:ty),*) as $answer:ty;
    )*) => {
        /// The host's services, passed by the host with every plugin call and valid during that
        /// call only. Every callback takes the `context` pointer the host passed alongside this
        /// table. Fallible callbacks (see [`for_each_host_service!`]) return a [`Status`] and
        /// write a message into `error` on failure.
        #[repr(C)]
        #[derive(Clone, Copy, Debug)]
        pub struct HostVtable {
            /// `size_of::<HostVtable>()` as the host knows it. Since v1.0.
            pub struct_size: usize,
            /// Reports progress in [0, 1] with a short UTF-8 message. Since v1.0.
            pub report_progress:
                Option<unsafe extern "C" fn(context: *mut c_void, fraction: f64, message: ByteSlice)>,
            /// Whether the host asks the plugin to stop; a plugin polls it in long loops.
            /// Since v1.0.
            pub is_cancelled: Option<unsafe extern "C" fn(context: *mut c_void) -> bool>,
            $(
                $(#[$doc])*
                pub $name: Option<
                    unsafe extern "C" fn(
                        context: *mut c_void,
                        $($argument: $raw,)*
                        $($output: $slot,)*
                        error: *mut ErrorBuffer,
                    ) -> Status,
                >,
            )*
        }
    };
}

for_each_host_service!(host_vtable);

/// A planning request, owned by the host and borrowed for one call.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PlanRequest {
    /// `size_of::<PlanRequest>()` as the host knows it. Since v1.0.
    pub struct_size: usize,
    /// The PDDL domain text (UTF-8). Since v1.0.
    pub domain: ByteSlice,
    /// The PDDL problem text (UTF-8). Since v1.0.
    pub problem: ByteSlice,
    /// How many distinct plans are wanted (at least 1). Since v1.0.
    pub plan_count: u64,
    /// The seed for the plugin's own generator. Since v1.0.
    pub seed: u64,
    /// Most search nodes to expand, or [`NO_LIMIT`]. Since v1.0.
    pub max_expansions: u64,
    /// Wall-clock limit in seconds, or `f64::INFINITY`. Since v1.0.
    pub time_limit_seconds: f64,
}

/// The planner's function table. Since v1.0.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PlannerVtable {
    /// `size_of::<PlannerVtable>()` as the plugin knows it. Since v1.0.
    pub struct_size: usize,
    /// Plans. On [`status::OK`] writes the response document (UTF-8 JSON, the `PlanResponse`
    /// wire type of lamp-plugin-api) into `out_response`; otherwise a UTF-8 message into
    /// `out_error`. Both are plugin-owned. Since v1.0.
    pub plan: Option<
        unsafe extern "C" fn(
            instance: *mut c_void,
            host: *const HostVtable,
            host_context: *mut c_void,
            request: *const PlanRequest,
            out_response: *mut OwnedBytes,
            out_error: *mut OwnedBytes,
        ) -> Status,
    >,
}

/// A refinement request, owned by the host and borrowed for one call.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RefineRequest {
    /// `size_of::<RefineRequest>()` as the host knows it. Since v1.0.
    pub struct_size: usize,
    /// The grounded action, a versioned JSON document (wire types of lamp-plugin-api).
    /// Since v1.0.
    pub action: ByteSlice,
    /// The world state, a versioned JSON document (wire types of lamp-plugin-api). Since v1.0.
    pub world: ByteSlice,
    /// The seed for the stream's own generator. Since v1.0.
    pub seed: u64,
}

/// The refiner's function table. Since v1.0.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RefinerVtable {
    /// `size_of::<RefinerVtable>()` as the plugin knows it. Since v1.0.
    pub struct_size: usize,
    /// Opens a candidate stream for one action; on [`status::OK`] writes an opaque stream handle,
    /// which the host closes with `close_stream`. Since v1.0.
    pub open_stream: Option<
        unsafe extern "C" fn(
            instance: *mut c_void,
            host: *const HostVtable,
            host_context: *mut c_void,
            request: *const RefineRequest,
            out_stream: *mut *mut c_void,
            out_error: *mut OwnedBytes,
        ) -> Status,
    >,
    /// Produces the stream's next candidate (UTF-8 JSON, the `Candidate` wire type) into
    /// `out_candidate`, or returns [`status::END_OF_STREAM`]. Since v1.0.
    pub next_candidate: Option<
        unsafe extern "C" fn(
            stream: *mut c_void,
            host: *const HostVtable,
            host_context: *mut c_void,
            out_candidate: *mut OwnedBytes,
            out_error: *mut OwnedBytes,
        ) -> Status,
    >,
    /// Frees a stream. Since v1.0.
    pub close_stream: Option<unsafe extern "C" fn(stream: *mut c_void)>,
}

/// A motion-planning request, owned by the host and borrowed for one call.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct MotionRequest {
    /// `size_of::<MotionRequest>()` as the host knows it. Since v1.0.
    pub struct_size: usize,
    /// The robot's name, as the host's oracles know it. Since v1.0.
    pub robot: ByteSlice,
    /// The start configuration. Since v1.0.
    pub start: F64Slice,
    /// The goal configuration. Since v1.0.
    pub goal: F64Slice,
    /// The seed for the plugin's own generator. Since v1.0.
    pub seed: u64,
    /// Most iterations (samples, expansions), or [`NO_LIMIT`]. Since v1.0.
    pub max_iterations: u64,
    /// Wall-clock limit in seconds, or `f64::INFINITY`. Since v1.0.
    pub time_limit_seconds: f64,
}

/// `MotionResult::outcome`: a path was found. Since v1.0.
pub const MOTION_PATH_FOUND: u32 = 0;
/// `MotionResult::outcome`: no path; see `no_path_reason`. Since v1.0.
pub const MOTION_NO_PATH: u32 = 1;

/// `MotionResult::no_path_reason`: the start configuration is invalid. Since v1.0.
pub const NO_PATH_START_INVALID: u32 = 1;
/// `MotionResult::no_path_reason`: the goal configuration is invalid. Since v1.0.
pub const NO_PATH_GOAL_INVALID: u32 = 2;
/// `MotionResult::no_path_reason`: the iteration or time budget ran out. Since v1.0.
pub const NO_PATH_BUDGET_EXHAUSTED: u32 = 3;
/// `MotionResult::no_path_reason`: the planner proved or gave up for another reason, described
/// in `message`. Since v1.0.
pub const NO_PATH_OTHER: u32 = 4;

/// A motion planner's answer, a host-owned struct the plugin fills in. The host sets
/// `struct_size`; the plugin writes no field beyond it.
#[repr(C)]
#[derive(Debug)]
pub struct MotionResult {
    /// `size_of::<MotionResult>()` as the host knows it. Since v1.0.
    pub struct_size: usize,
    /// [`MOTION_PATH_FOUND`] or [`MOTION_NO_PATH`]. Since v1.0.
    pub outcome: u32,
    /// One of the `NO_PATH_*` codes when `outcome` is [`MOTION_NO_PATH`]. Since v1.0.
    pub no_path_reason: u32,
    /// The path's waypoints back to back, `len` a multiple of the start's length, first the start
    /// and last the goal (plugin-owned). Since v1.0.
    pub waypoints: OwnedF64s,
    /// A UTF-8 explanation (plugin-owned, may be empty). Since v1.0.
    pub message: OwnedBytes,
}

/// The motion planner's function table. Since v1.0.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct MotionPlannerVtable {
    /// `size_of::<MotionPlannerVtable>()` as the plugin knows it. Since v1.0.
    pub struct_size: usize,
    /// Plans a path and fills `out_result` on [`status::OK`]. Since v1.0.
    pub plan_path: Option<
        unsafe extern "C" fn(
            instance: *mut c_void,
            host: *const HostVtable,
            host_context: *mut c_void,
            request: *const MotionRequest,
            out_result: *mut MotionResult,
            out_error: *mut OwnedBytes,
        ) -> Status,
    >,
}

/// What the plugin is, readable before any plugin code runs.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PluginDescriptor {
    /// `size_of::<PluginDescriptor>()` as the plugin knows it. Since v1.0.
    pub struct_size: usize,
    /// One of the `KIND_*` constants. Since v1.0.
    pub kind: PluginKind,
    /// The plugin's name (UTF-8, non-empty, static). Since v1.0.
    pub name: ByteSlice,
    /// The plugin's own version (UTF-8, static). Since v1.0.
    pub version: ByteSlice,
    /// One line on what it does (UTF-8, static, may be empty). Since v1.0.
    pub description: ByteSlice,
}

/// The table behind [`ENTRY_SYMBOL`]. It is immutable static data of the plugin library.
///
/// `abi_major` and `abi_minor` come first and stay first in every ABI version, so that any host
/// can read them from any plugin.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PluginEntry {
    /// The ABI major the plugin was built for. Since v1.0.
    pub abi_major: u32,
    /// The ABI minor the plugin was built for. Since v1.0.
    pub abi_minor: u32,
    /// `size_of::<PluginEntry>()` as the plugin knows it. Since v1.0.
    pub struct_size: usize,
    /// What the plugin is. Since v1.0.
    pub descriptor: PluginDescriptor,
    /// Creates an instance from a configuration document (bytes, may be empty). On
    /// [`status::OK`] writes an opaque instance handle, destroyed with `destroy`. Since v1.0.
    pub create: Option<
        unsafe extern "C" fn(
            config: ByteSlice,
            out_instance: *mut *mut c_void,
            out_error: *mut OwnedBytes,
        ) -> Status,
    >,
    /// Destroys an instance. Since v1.0.
    pub destroy: Option<unsafe extern "C" fn(instance: *mut c_void)>,
    /// Frees bytes this plugin allocated. Since v1.0.
    pub free_bytes: Option<unsafe extern "C" fn(bytes: OwnedBytes)>,
    /// Frees `f64` values this plugin allocated. Since v1.0.
    pub free_f64s: Option<unsafe extern "C" fn(values: OwnedF64s)>,
    /// Returns an optional capability table by UTF-8 identifier, or null. No extension is
    /// defined in v1.0. Since v1.0.
    pub get_extension: Option<unsafe extern "C" fn(id: ByteSlice) -> *const c_void>,
    /// The planner table when `descriptor.kind` is [`KIND_PLANNER`], else null. Since v1.0.
    pub planner: *const PlannerVtable,
    /// The refiner table when `descriptor.kind` is [`KIND_REFINER`], else null. Since v1.0.
    pub refiner: *const RefinerVtable,
    /// The motion-planner table when `descriptor.kind` is [`KIND_MOTION_PLANNER`], else null.
    /// Since v1.0.
    pub motion_planner: *const MotionPlannerVtable,
}

// SAFETY: a `PluginEntry` (and its descriptor) is immutable static data: its pointers point to
// static strings and static function tables that nobody writes, so sharing it between threads
// cannot race.
unsafe impl Sync for PluginEntry {}
// SAFETY: as for `PluginEntry`, the descriptor only points to immutable static strings.
unsafe impl Sync for PluginDescriptor {}

/// The sizes of the v1.0 structs. A v1.x peer's struct is at least this large; fields added in
/// later minors are read only when the peer's `struct_size` covers them.
pub mod v1_0_sizes {
    use super::{
        HostVtable, MotionPlannerVtable, MotionRequest, MotionResult, PlanRequest, PlannerVtable,
        PluginDescriptor, PluginEntry, RefineRequest, RefinerVtable, offset_of, size_of,
    };

    /// Size of [`PluginEntry`] in v1.0.
    pub const ENTRY: usize = size_of::<PluginEntry>();
    /// Size of [`PluginDescriptor`] in v1.0.
    pub const DESCRIPTOR: usize = size_of::<PluginDescriptor>();
    /// Size of [`HostVtable`] in v1.0: everything before the first field of v1.1.
    pub const HOST: usize = offset_of!(HostVtable, sample_configuration);
    /// Size of [`PlannerVtable`] in v1.0.
    pub const PLANNER: usize = size_of::<PlannerVtable>();
    /// Size of [`RefinerVtable`] in v1.0.
    pub const REFINER: usize = size_of::<RefinerVtable>();
    /// Size of [`MotionPlannerVtable`] in v1.0.
    pub const MOTION_PLANNER: usize = size_of::<MotionPlannerVtable>();
    /// Size of [`PlanRequest`] in v1.0.
    pub const PLAN_REQUEST: usize = size_of::<PlanRequest>();
    /// Size of [`RefineRequest`] in v1.0.
    pub const REFINE_REQUEST: usize = size_of::<RefineRequest>();
    /// Size of [`MotionRequest`] in v1.0.
    pub const MOTION_REQUEST: usize = size_of::<MotionRequest>();
    /// Size of [`MotionResult`] in v1.0.
    pub const MOTION_RESULT: usize = size_of::<MotionResult>();
}

/// The sizes of the structs that grew in v1.1. A peer uses a v1.1 field only when the other
/// side's `struct_size` is at least the size given here.
pub mod v1_1_sizes {
    use super::{HostVtable, c_void, offset_of, size_of};

    /// Size of [`HostVtable`] in v1.1: up to the end of
    /// [`HostVtable::sample_configuration`]. Every function pointer has the same size.
    pub const HOST: usize = offset_of!(HostVtable, sample_configuration)
        + size_of::<Option<unsafe extern "C" fn(*mut c_void)>>();
}

/// A `'static` entry table whose function pointers are known to be valid, because it was built
/// in this process by lamp-plugin-sdk (a statically linked plugin). The host accepts it without
/// loading a library, and still checks its version and descriptor.
#[derive(Clone, Copy, Debug)]
pub struct TrustedEntry(&'static PluginEntry);

impl TrustedEntry {
    /// Wraps an entry table.
    ///
    /// # Safety
    /// Every non-null pointer in `entry` (strings, vtables and the function pointers in them) must
    /// be valid for the life of the process and behave as this crate documents.
    #[must_use]
    pub const unsafe fn new(entry: &'static PluginEntry) -> Self {
        Self(entry)
    }

    /// The entry table.
    #[must_use]
    pub const fn entry(self) -> &'static PluginEntry {
        self.0
    }
}
