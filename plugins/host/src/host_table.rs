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
    ByteSlice, ErrorBuffer, F64Buffer, F64Slice, HostVtable, Pose, Status, for_each_host_service,
    status,
};
use lamp_plugin_api::{HostError, HostServices};

/// Generates the table and one callback per fallible service from the ABI's description, each
/// reading its arguments ([`FromPlugin`]), asking the host's [`HostServices`] and writing the
/// answer into the plugin's slots ([`IntoSlots`]).
macro_rules! host_callbacks {
    ($(
        $(#[$doc:meta])*
        fn $name:ident($($argument:ident: $raw:ty as $rust:ty),* $(,)?)
            writes ($($output:ident: $slot:ty),*) as $answer:ty;
    )*) => {
        /// The table every plugin call receives.
        pub(crate) static HOST_VTABLE: HostVtable = HostVtable {
            struct_size: size_of::<HostVtable>(),
            report_progress: Some(report_progress),
            is_cancelled: Some(is_cancelled),
            $($name: Some(callbacks::$name),)*
        };

        mod callbacks {
            use super::*;
            $(
                pub(super) unsafe extern "C" fn $name(
                    context: *mut c_void,
                    $($argument: $raw,)*
                    $($output: $slot,)*
                    error: *mut ErrorBuffer,
                ) -> Status {
                    serve(error, || {
                        // SAFETY: the context, arguments and output slots of this call, each
                        // valid for the call by the ABI's rules (lamp-plugin-abi).
                        unsafe {
                            let answer: $answer = services(context)
                                .$name($(<$rust>::from_plugin($argument, stringify!($argument))?),*)?;
                            answer.into_slots(($($output,)*))
                        }
                    })
                }
            )*
        }
    };
}

for_each_host_service!(host_callbacks);

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

/// A service argument as the host reads it from the plugin's flat data.
trait FromPlugin: Sized {
    /// Its type in the C signature.
    type Raw;

    /// The argument; `name` names it in the error.
    ///
    /// # Safety
    /// `raw` must be valid for the call (ABI rule).
    unsafe fn from_plugin(raw: Self::Raw, name: &str) -> Result<Self, HostError>;
}

impl FromPlugin for &str {
    type Raw = ByteSlice;

    unsafe fn from_plugin(raw: ByteSlice, name: &str) -> Result<Self, HostError> {
        // SAFETY: forwarded contract.
        unsafe { text(raw, name) }
    }
}

impl FromPlugin for &[f64] {
    type Raw = F64Slice;

    unsafe fn from_plugin(raw: F64Slice, name: &str) -> Result<Self, HostError> {
        if raw.len == 0 {
            return Ok(&[]);
        }
        if raw.data.is_null() {
            return Err(HostError::failed(format!("`{name}` is null")));
        }
        // SAFETY: non-null and valid for `len` values (ABI rule).
        Ok(unsafe { std::slice::from_raw_parts(raw.data, raw.len) })
    }
}

impl FromPlugin for &Pose {
    type Raw = *const Pose;

    unsafe fn from_plugin(raw: *const Pose, name: &str) -> Result<Self, HostError> {
        // SAFETY: null or valid for the call (ABI rule).
        unsafe { raw.as_ref() }.ok_or_else(|| HostError::failed(format!("`{name}` is null")))
    }
}

/// Arguments passed by value.
macro_rules! by_value {
    ($($value:ty),*) => {$(
        impl FromPlugin for $value {
            type Raw = $value;

            unsafe fn from_plugin(raw: $value, _name: &str) -> Result<Self, HostError> {
                Ok(raw)
            }
        }
    )*};
}

by_value!(f64, u64);

/// Borrowed text from the plugin, or a message for the error buffer.
///
/// # Safety
/// `slice` must be valid for the call (ABI rule).
unsafe fn text<'a>(slice: ByteSlice, name: &str) -> Result<&'a str, HostError> {
    if slice.len == 0 {
        return Ok("");
    }
    if slice.data.is_null() {
        return Err(HostError::failed(format!("`{name}` is null")));
    }
    // SAFETY: non-null and valid for `len` bytes (ABI rule).
    let bytes = unsafe { std::slice::from_raw_parts(slice.data, slice.len) };
    std::str::from_utf8(bytes).map_err(|_| HostError::failed(format!("`{name}` is not UTF-8")))
}

/// A service's answer as the host writes it into the plugin's output slots.
trait IntoSlots {
    /// The output parameters of the C signature.
    type Slots;

    /// Writes the answer; [`status::BUFFER_TOO_SMALL`] when a buffer cannot hold it.
    ///
    /// # Safety
    /// Every slot must be null or valid for writes for the call (ABI rule).
    unsafe fn into_slots(self, slots: Self::Slots) -> Result<Status, HostError>;
}

/// Answers written whole into one slot.
macro_rules! one_slot {
    ($($value:ty),*) => {$(
        impl IntoSlots for $value {
            type Slots = (*mut $value,);

            unsafe fn into_slots(self, (slot,): Self::Slots) -> Result<Status, HostError> {
                if slot.is_null() {
                    return Err(HostError::failed("an output slot is null"));
                }
                // SAFETY: non-null and writable by the caller's contract.
                unsafe { slot.write(self) };
                Ok(status::OK)
            }
        }
    )*};
}

one_slot!(bool, f64, Pose);

impl IntoSlots for Vec<f64> {
    type Slots = (*mut F64Buffer,);

    unsafe fn into_slots(self, (out,): Self::Slots) -> Result<Status, HostError> {
        // SAFETY: null or valid by the caller's contract.
        let Some(buffer) = (unsafe { out.as_mut() }) else {
            return Err(HostError::failed("the output buffer is null"));
        };
        buffer.len = self.len();
        if self.len() > buffer.capacity || (buffer.data.is_null() && !self.is_empty()) {
            return Ok(status::BUFFER_TOO_SMALL);
        }
        // SAFETY: `data` is writable for `capacity >= len` values (ABI rule for `F64Buffer`).
        unsafe { std::ptr::copy_nonoverlapping(self.as_ptr(), buffer.data, self.len()) };
        Ok(status::OK)
    }
}

/// Whether a configuration was found, and the configuration when it was.
impl IntoSlots for Option<Vec<f64>> {
    type Slots = (*mut bool, *mut F64Buffer);

    unsafe fn into_slots(self, (found, out): Self::Slots) -> Result<Status, HostError> {
        // SAFETY: forwarded contract.
        unsafe {
            self.is_some().into_slots((found,))?;
            match self {
                Some(configuration) => configuration.into_slots((out,)),
                None => Ok(status::OK),
            }
        }
    }
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

unsafe extern "C" fn report_progress(context: *mut c_void, fraction: f64, message: ByteSlice) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the context of this call and the plugin's message slice (ABI rules).
        let (host, message) = unsafe { (services(context), text(message, "message")) };
        host.report_progress(fraction, message.unwrap_or("(progress message is not UTF-8)"));
    }));
}

unsafe extern "C" fn is_cancelled(context: *mut c_void) -> bool {
    // SAFETY: the context of this call (ABI rule).
    let host = unsafe { services(context) };
    // A host whose cancellation check panics cannot be trusted to want the work: stop.
    catch_unwind(AssertUnwindSafe(|| host.is_cancelled())).unwrap_or(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Finds the seed itself for link `tool`, nothing for any other link.
    struct Echo;

    impl HostServices for Echo {
        fn solve_ik(
            &self,
            _robot: &str,
            link: &str,
            _target: &Pose,
            seed_q: &[f64],
        ) -> Result<Option<Vec<f64>>, HostError> {
            Ok((link == "tool").then(|| seed_q.to_vec()))
        }
    }

    /// Calls the table's `solve_ik` as a plugin would, with a buffer of `capacity` values.
    fn solve_ik(
        link: &str,
        target: *const Pose,
        capacity: usize,
    ) -> (Status, bool, Vec<f64>, String) {
        let host: &dyn HostServices = &Echo;
        let seed = [1.0, 2.0, 3.0];
        let mut values = vec![0.0; capacity];
        let mut out_q = F64Buffer { data: values.as_mut_ptr(), capacity, len: 0 };
        let mut message = [0_u8; 64];
        let mut error = ErrorBuffer { data: message.as_mut_ptr(), capacity: 64, len: 0 };
        let mut found = false;
        let callback = HOST_VTABLE.solve_ik.expect("the host offers IK");
        // SAFETY: every pointer is live and valid for the call, as the ABI asks of a plugin.
        let code = unsafe {
            callback(
                context_of(&host),
                ByteSlice::from_text("arm"),
                ByteSlice::from_text(link),
                target,
                F64Slice::new(&seed),
                &raw mut found,
                &raw mut out_q,
                &raw mut error,
            )
        };
        values.truncate(out_q.len.min(capacity));
        (code, found, values, String::from_utf8_lossy(&message[..error.len]).into_owned())
    }

    #[test]
    fn a_generated_callback_reads_its_arguments_and_writes_its_slots() {
        let target = [0.0; 7];
        assert_eq!(
            solve_ik("tool", &raw const target, 4),
            (status::OK, true, vec![1.0, 2.0, 3.0], String::new())
        );
        assert_eq!(
            solve_ik("elbow", &raw const target, 4),
            (status::OK, false, vec![], String::new())
        );
        // Too small: nothing written, the length needed reported.
        let (code, found, values, _) = solve_ik("tool", &raw const target, 2);
        assert_eq!((code, found, values), (status::BUFFER_TOO_SMALL, true, vec![0.0, 0.0]));
        let (code, _, _, message) = solve_ik("tool", std::ptr::null(), 4);
        assert_eq!((code, message.as_str()), (status::HOST_ERROR, "`target` is null"));
    }
}
