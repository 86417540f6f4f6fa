//! The plugin side of the boundary: panic catching, error reporting, and reading and writing the
//! flat ABI data.

// This module turns raw pointers handed over by the host into references and slices, and hands
// heap memory to the host; each `unsafe` block states the ABI rule it relies on.
#![allow(unsafe_code)]

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::ptr;
use std::time::Duration;

use lamp_plugin_abi::{ByteSlice, F64Slice, OwnedBytes, OwnedF64s, Status, status};
use lamp_plugin_api::{HostError, PluginError};

/// Runs `body`, turning its error or panic into a status and a message in `out_error`.
pub(crate) fn guard(
    out_error: *mut OwnedBytes,
    body: impl FnOnce() -> Result<Status, PluginError>,
) -> Status {
    let error = match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(status)) => return status,
        Ok(Err(error)) => error,
        Err(payload) => PluginError::Panicked { message: panic_message(payload.as_ref()) },
    };
    let (code, message) = error_to_status(&error);
    if !out_error.is_null() {
        // SAFETY: the host passes a valid, writable `OwnedBytes` slot (ABI rule for `out_error`);
        // `write` does not drop the slot's previous contents, which the host leaves empty.
        unsafe { out_error.write(owned_bytes(message.into_bytes())) };
    }
    code
}

/// Runs a function that returns nothing across the boundary (destructors), swallowing a panic:
/// there is no channel to report it, and unwinding further would abort the host.
pub(crate) fn guard_silent(body: impl FnOnce()) {
    let _ = catch_unwind(AssertUnwindSafe(body));
}

/// The status code and message the host turns back into the same [`PluginError`].
pub(crate) fn error_to_status(error: &PluginError) -> (Status, String) {
    match error {
        PluginError::InvalidRequest { message } => (status::INVALID_REQUEST, message.clone()),
        PluginError::Host(HostError::Unsupported { service }) => {
            (status::UNSUPPORTED, service.clone())
        }
        PluginError::Host(HostError::Failed { message }) => (status::HOST_ERROR, message.clone()),
        PluginError::Cancelled => (status::CANCELLED, String::new()),
        PluginError::Panicked { message } => (status::PANICKED, message.clone()),
        PluginError::Failed { message } => (status::FAILED, message.clone()),
    }
}

pub(crate) fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(text) = payload.downcast_ref::<&str>() {
        (*text).to_string()
    } else if let Some(text) = payload.downcast_ref::<String>() {
        text.clone()
    } else {
        "a panic with a non-text payload".to_string()
    }
}

/// Hands `bytes` to the host; it comes back through [`free_bytes`].
pub(crate) fn owned_bytes(bytes: Vec<u8>) -> OwnedBytes {
    if bytes.is_empty() {
        return OwnedBytes::EMPTY;
    }
    let boxed = bytes.into_boxed_slice();
    let len = boxed.len();
    OwnedBytes { data: Box::into_raw(boxed).cast::<u8>(), len }
}

/// Hands `values` to the host; they come back through [`free_f64s`].
pub(crate) fn owned_f64s(values: Vec<f64>) -> OwnedF64s {
    if values.is_empty() {
        return OwnedF64s::EMPTY;
    }
    let boxed = values.into_boxed_slice();
    let len = boxed.len();
    OwnedF64s { data: Box::into_raw(boxed).cast::<f64>(), len }
}

/// The entry table's `free_bytes`.
pub(crate) unsafe extern "C" fn free_bytes(bytes: OwnedBytes) {
    guard_silent(|| {
        if !bytes.data.is_null() {
            // SAFETY: non-null `OwnedBytes` only come from `owned_bytes`, which leaked a boxed
            // slice of exactly `len` bytes; the host returns each one once.
            drop(unsafe { Box::from_raw(ptr::slice_from_raw_parts_mut(bytes.data, bytes.len)) });
        }
    });
}

/// The entry table's `free_f64s`.
pub(crate) unsafe extern "C" fn free_f64s(values: OwnedF64s) {
    guard_silent(|| {
        if !values.data.is_null() {
            // SAFETY: as in `free_bytes`, for boxed slices leaked by `owned_f64s`.
            drop(unsafe { Box::from_raw(ptr::slice_from_raw_parts_mut(values.data, values.len)) });
        }
    });
}

/// The bytes of a host slice.
///
/// # Safety
/// `slice` must follow the ABI: `data` valid for `len` bytes for the duration of the call.
pub(crate) unsafe fn bytes<'a>(slice: ByteSlice) -> Result<&'a [u8], PluginError> {
    if slice.len == 0 {
        return Ok(&[]);
    }
    if slice.data.is_null() {
        return Err(PluginError::invalid_request("a null byte slice with a non-zero length"));
    }
    // SAFETY: non-null and valid for `len` bytes by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(slice.data, slice.len) })
}

/// The UTF-8 text of a host slice; `what` names it in the error.
///
/// # Safety
/// As for [`bytes`].
pub(crate) unsafe fn text<'a>(slice: ByteSlice, what: &str) -> Result<&'a str, PluginError> {
    // SAFETY: forwarded contract.
    let bytes = unsafe { bytes(slice) }?;
    std::str::from_utf8(bytes)
        .map_err(|error| PluginError::invalid_request(format!("{what} is not UTF-8: {error}")))
}

/// The values of a host slice.
///
/// # Safety
/// `slice` must follow the ABI: `data` valid for `len` values for the duration of the call.
pub(crate) unsafe fn f64s<'a>(slice: F64Slice) -> Result<&'a [f64], PluginError> {
    if slice.len == 0 {
        return Ok(&[]);
    }
    if slice.data.is_null() {
        return Err(PluginError::invalid_request("a null f64 slice with a non-zero length"));
    }
    // SAFETY: non-null and valid for `len` values by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(slice.data, slice.len) })
}

/// A reference to a host struct after checking it is non-null and at least `minimum_size` bytes
/// as the host declared it (`struct_size` is the struct's first field).
///
/// # Safety
/// `pointer` must be null or point to a valid value for the duration of the call.
pub(crate) unsafe fn sized_struct<'a, T>(
    pointer: *const T,
    declared_size: impl FnOnce(&T) -> usize,
    minimum_size: usize,
    what: &str,
) -> Result<&'a T, PluginError> {
    // SAFETY: null or valid by the caller's contract.
    let Some(value) = (unsafe { pointer.as_ref() }) else {
        return Err(PluginError::invalid_request(format!("{what} is null")));
    };
    let size = declared_size(value);
    if size < minimum_size {
        return Err(PluginError::invalid_request(format!(
            "{what} declares {size} bytes; ABI v1.0 needs at least {minimum_size}"
        )));
    }
    Ok(value)
}

/// `None` for [`lamp_plugin_abi::NO_LIMIT`].
pub(crate) fn limit(value: u64) -> Option<u64> {
    (value != lamp_plugin_abi::NO_LIMIT).then_some(value)
}

/// `None` for an infinite limit; an error for a negative or NaN one.
pub(crate) fn time_limit(seconds: f64) -> Result<Option<Duration>, PluginError> {
    if seconds == f64::INFINITY {
        return Ok(None);
    }
    Duration::try_from_secs_f64(seconds).map(Some).map_err(|_| {
        PluginError::invalid_request(format!("time limit {seconds} s is not a duration"))
    })
}

/// Writes `value` to an output slot after checking it is non-null.
///
/// # Safety
/// `slot` must be null or valid for writes for the duration of the call.
pub(crate) unsafe fn write_out<T>(slot: *mut T, value: T, what: &str) -> Result<(), PluginError> {
    if slot.is_null() {
        return Err(PluginError::invalid_request(format!("{what} is null")));
    }
    // SAFETY: non-null and writable by the caller's contract; outputs hold no value to drop.
    unsafe { slot.write(value) };
    Ok(())
}
