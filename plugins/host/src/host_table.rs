//! The host's callback table: [`HostServices`] offered to a plugin through the C ABI.
//!
//! The context pointer of every call points to a `&dyn HostServices` on the host's stack, valid
//! for that one call. Panics in the host's services are caught here, because unwinding through the
//! plugin's frames would abort.

// Implements `extern "C"` callbacks that read the plugin's slices and write into its buffers;
// each `unsafe` block states the ABI rule it relies on.
#![allow(unsafe_code)]

use std::ffi::c_void;
use std::panic::{AssertUnwindSafe, catch_unwind};

use lamp_plugin_abi::{
    ByteSlice, ErrorBuffer, F64Buffer, F64Slice, HostVtable, Pose, Status, status,
};
use lamp_plugin_api::{HostError, HostServices};

/// The table every plugin call receives.
pub(crate) static HOST_VTABLE: HostVtable = HostVtable {
    struct_size: size_of::<HostVtable>(),
    report_progress: Some(report_progress),
    is_cancelled: Some(is_cancelled),
    configuration_is_valid: Some(configuration_is_valid),
    edge_is_valid: Some(edge_is_valid),
    solve_ik: Some(solve_ik),
    forward_kinematics: Some(forward_kinematics),
    distance: Some(distance),
    interpolate: Some(interpolate),
    sample_configuration: Some(sample_configuration),
};

/// The context pointer for `host`, valid while `slot` lives.
pub(crate) fn context_of<'a>(slot: &'a &'a dyn HostServices) -> *mut c_void {
    std::ptr::from_ref(slot).cast_mut().cast::<c_void>()
}

/// The services behind a context pointer.
///
/// # Safety
/// `context` must come from [`context_of`] during the plugin call it was passed to.
unsafe fn services<'a>(context: *mut c_void) -> &'a dyn HostServices {
    // SAFETY: the caller's contract: a live `&dyn HostServices` slot.
    unsafe { *context.cast::<&dyn HostServices>() }
}

/// Borrowed text from the plugin, or a message for the error buffer.
///
/// # Safety
/// `slice` must be valid for the call (ABI rule).
unsafe fn text<'a>(slice: ByteSlice, what: &str) -> Result<&'a str, HostError> {
    if slice.len == 0 {
        return Ok("");
    }
    if slice.data.is_null() {
        return Err(HostError::failed(format!("{what} is null")));
    }
    // SAFETY: non-null and valid for `len` bytes (ABI rule).
    let bytes = unsafe { std::slice::from_raw_parts(slice.data, slice.len) };
    std::str::from_utf8(bytes).map_err(|_| HostError::failed(format!("{what} is not UTF-8")))
}

/// Borrowed values from the plugin.
///
/// # Safety
/// `slice` must be valid for the call (ABI rule).
unsafe fn values<'a>(slice: F64Slice, what: &str) -> Result<&'a [f64], HostError> {
    if slice.len == 0 {
        return Ok(&[]);
    }
    if slice.data.is_null() {
        return Err(HostError::failed(format!("{what} is null")));
    }
    // SAFETY: non-null and valid for `len` values (ABI rule).
    Ok(unsafe { std::slice::from_raw_parts(slice.data, slice.len) })
}

/// Runs a service, writing its failure into `error` and returning the status.
fn serve(error: *mut ErrorBuffer, body: impl FnOnce() -> Result<Status, HostError>) -> Status {
    let failure = match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(code)) => return code,
        Ok(Err(failure)) => failure,
        Err(_) => HostError::failed("a host service panicked"),
    };
    let (code, message) = match failure {
        HostError::Unsupported { service } => (status::UNSUPPORTED, service),
        HostError::Failed { message } => (status::HOST_ERROR, message),
    };
    // SAFETY: the plugin passes a writable error buffer or null (ABI rule).
    if let Some(buffer) = unsafe { error.as_mut() } {
        write_truncated(buffer, &message);
    }
    code
}

fn write_truncated(buffer: &mut ErrorBuffer, message: &str) {
    if buffer.data.is_null() {
        buffer.len = 0;
        return;
    }
    let mut end = message.len().min(buffer.capacity);
    while !message.is_char_boundary(end) {
        end -= 1;
    }
    // SAFETY: `data` is writable for `capacity >= end` bytes (ABI rule for `ErrorBuffer`).
    unsafe { std::ptr::copy_nonoverlapping(message.as_ptr(), buffer.data, end) };
    buffer.len = end;
}

/// Writes `values` into the plugin's buffer, or asks for a larger one.
///
/// # Safety
/// `out` must be null or a valid buffer for the call (ABI rule).
unsafe fn write_values(out: *mut F64Buffer, values: &[f64]) -> Result<Status, HostError> {
    // SAFETY: null or valid by the caller's contract.
    let Some(buffer) = (unsafe { out.as_mut() }) else {
        return Err(HostError::failed("the output buffer is null"));
    };
    buffer.len = values.len();
    if values.len() > buffer.capacity || (buffer.data.is_null() && !values.is_empty()) {
        return Ok(status::BUFFER_TOO_SMALL);
    }
    // SAFETY: `data` is writable for `capacity >= len` values (ABI rule for `F64Buffer`).
    unsafe { std::ptr::copy_nonoverlapping(values.as_ptr(), buffer.data, values.len()) };
    Ok(status::OK)
}

/// Writes one output value.
///
/// # Safety
/// `out` must be null or writable for the call (ABI rule).
unsafe fn write_one<T>(out: *mut T, value: T) -> Result<Status, HostError> {
    if out.is_null() {
        return Err(HostError::failed("an output slot is null"));
    }
    // SAFETY: non-null and writable by the caller's contract.
    unsafe { out.write(value) };
    Ok(status::OK)
}

unsafe extern "C" fn report_progress(context: *mut c_void, fraction: f64, message: ByteSlice) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the context of this call and the plugin's message slice (ABI rules).
        let (host, message) = unsafe { (services(context), text(message, "the message")) };
        host.report_progress(fraction, message.unwrap_or("(progress message is not UTF-8)"));
    }));
}

unsafe extern "C" fn is_cancelled(context: *mut c_void) -> bool {
    // SAFETY: the context of this call (ABI rule).
    let host = unsafe { services(context) };
    // A host whose cancellation check panics cannot be trusted to want the work: stop.
    catch_unwind(AssertUnwindSafe(|| host.is_cancelled())).unwrap_or(true)
}

unsafe extern "C" fn configuration_is_valid(
    context: *mut c_void,
    robot: ByteSlice,
    q: F64Slice,
    out_valid: *mut bool,
    error: *mut ErrorBuffer,
) -> Status {
    serve(error, || {
        // SAFETY: the context and slices of this call; the output slot (ABI rules).
        unsafe {
            let valid = services(context)
                .configuration_is_valid(text(robot, "the robot")?, values(q, "q")?)?;
            write_one(out_valid, valid)
        }
    })
}

unsafe extern "C" fn edge_is_valid(
    context: *mut c_void,
    robot: ByteSlice,
    a: F64Slice,
    b: F64Slice,
    out_valid: *mut bool,
    error: *mut ErrorBuffer,
) -> Status {
    serve(error, || {
        // SAFETY: the context and slices of this call; the output slot (ABI rules).
        unsafe {
            let robot = text(robot, "the robot")?;
            let valid = services(context).edge_is_valid(robot, values(a, "a")?, values(b, "b")?)?;
            write_one(out_valid, valid)
        }
    })
}

unsafe extern "C" fn solve_ik(
    context: *mut c_void,
    robot: ByteSlice,
    link: ByteSlice,
    target: *const Pose,
    seed_q: F64Slice,
    out_found: *mut bool,
    out_q: *mut F64Buffer,
    error: *mut ErrorBuffer,
) -> Status {
    serve(error, || {
        // SAFETY: the context, slices and target of this call; the output slots (ABI rules).
        unsafe {
            let target = target.as_ref().ok_or_else(|| HostError::failed("the target is null"))?;
            let (robot, link) = (text(robot, "the robot")?, text(link, "the link")?);
            let solution =
                services(context).solve_ik(robot, link, target, values(seed_q, "seed_q")?)?;
            write_one(out_found, solution.is_some())?;
            match solution {
                Some(configuration) => write_values(out_q, &configuration),
                None => Ok(status::OK),
            }
        }
    })
}

unsafe extern "C" fn forward_kinematics(
    context: *mut c_void,
    robot: ByteSlice,
    q: F64Slice,
    link: ByteSlice,
    out_pose: *mut Pose,
    error: *mut ErrorBuffer,
) -> Status {
    serve(error, || {
        // SAFETY: the context and slices of this call; the output slot (ABI rules).
        unsafe {
            let (robot, link) = (text(robot, "the robot")?, text(link, "the link")?);
            let pose = services(context).forward_kinematics(robot, values(q, "q")?, link)?;
            write_one(out_pose, pose)
        }
    })
}

unsafe extern "C" fn distance(
    context: *mut c_void,
    robot: ByteSlice,
    a: F64Slice,
    b: F64Slice,
    out_distance: *mut f64,
    error: *mut ErrorBuffer,
) -> Status {
    serve(error, || {
        // SAFETY: the context and slices of this call; the output slot (ABI rules).
        unsafe {
            let robot = text(robot, "the robot")?;
            let distance = services(context).distance(robot, values(a, "a")?, values(b, "b")?)?;
            write_one(out_distance, distance)
        }
    })
}

unsafe extern "C" fn interpolate(
    context: *mut c_void,
    robot: ByteSlice,
    a: F64Slice,
    b: F64Slice,
    t: f64,
    out_q: *mut F64Buffer,
    error: *mut ErrorBuffer,
) -> Status {
    serve(error, || {
        // SAFETY: the context and slices of this call; the output buffer (ABI rules).
        unsafe {
            let robot = text(robot, "the robot")?;
            let q = services(context).interpolate(robot, values(a, "a")?, values(b, "b")?, t)?;
            write_values(out_q, &q)
        }
    })
}

unsafe extern "C" fn sample_configuration(
    context: *mut c_void,
    robot: ByteSlice,
    seed: u64,
    out_q: *mut F64Buffer,
    error: *mut ErrorBuffer,
) -> Status {
    serve(error, || {
        // SAFETY: the context and slice of this call; the output buffer (ABI rules).
        unsafe {
            let q = services(context).sample_configuration(text(robot, "the robot")?, seed)?;
            write_values(out_q, &q)
        }
    })
}
