//! The host's services as seen by a plugin: [`HostServices`] implemented over the host's callback
//! vtable.

// Calls the host's `extern "C"` callbacks with pointers to plugin-owned buffers; each `unsafe`
// block states the ABI rule it relies on.
#![allow(unsafe_code)]

use std::cell::Cell;
use std::ffi::c_void;
use std::mem::MaybeUninit;

use lamp_plugin_abi::{
    ByteSlice, ErrorBuffer, F64Buffer, F64Slice, HostVtable, Pose, Status, for_each_host_service,
    status, v1_0_sizes,
};
use lamp_plugin_api::{HostError, HostServices, PluginError};

use crate::boundary::sized_struct;

/// Longest host error message kept, in bytes.
const ERROR_CAPACITY: usize = 1024;

/// First buffer size for a configuration the host writes, whose length a plugin cannot always
/// know in advance; large enough for a mobile manipulator's base, torso and arm.
const VALUES_CAPACITY_HINT: usize = 16;

/// The host's services for the duration of one plugin call.
#[derive(Debug)]
pub(crate) struct HostProxy<'a> {
    vtable: &'a HostVtable,
    context: *mut c_void,
    /// The length of the longest configuration the host wrote, so that a longer one makes the
    /// buffer grow once per call rather than once per answer.
    values_capacity: Cell<usize>,
}

impl HostProxy<'_> {
    /// Wraps the host table and context of one call.
    ///
    /// # Safety
    /// `vtable` must be null or point to a valid host table whose callbacks accept `context`,
    /// for as long as the proxy lives.
    pub(crate) unsafe fn new(
        vtable: *const HostVtable,
        context: *mut c_void,
    ) -> Result<Self, PluginError> {
        // SAFETY: forwarded contract.
        let vtable = unsafe {
            sized_struct(vtable, |table| table.struct_size, v1_0_sizes::HOST, "the host table")
        }?;
        Ok(Self { vtable, context, values_capacity: Cell::new(VALUES_CAPACITY_HINT) })
    }

    /// Whether the host's table holds the function pointer at `offset`: a field beyond the
    /// host's `struct_size` is not there, whatever its bytes say.
    fn host_offers(&self, offset: usize) -> bool {
        self.vtable.struct_size >= offset + size_of::<Option<unsafe extern "C" fn()>>()
    }

    /// Calls a fallible callback with a fresh error buffer and maps its status.
    fn call(
        &self,
        service: &str,
        body: impl FnOnce(*mut ErrorBuffer) -> Option<Status>,
    ) -> Result<(), HostError> {
        // Left uninitialised: zeroing a kilobyte on every collision check would cost more than
        // the call itself, and only the bytes the host reports as written are ever read.
        let mut message = [MaybeUninit::<u8>::uninit(); ERROR_CAPACITY];
        let mut error = ErrorBuffer {
            data: message.as_mut_ptr().cast::<u8>(),
            capacity: ERROR_CAPACITY,
            len: 0,
        };
        let Some(code) = body(&raw mut error) else {
            return Err(HostError::unsupported(service));
        };
        match code {
            status::OK => Ok(()),
            status::UNSUPPORTED => Err(HostError::unsupported(service)),
            _ => {
                let written_len = error.len.min(ERROR_CAPACITY);
                // SAFETY: the host initialised the first `len` bytes it reports (ABI rule for
                // `ErrorBuffer`), and `written_len` never exceeds the buffer.
                let written = unsafe {
                    std::slice::from_raw_parts(message.as_ptr().cast::<u8>(), written_len)
                };
                let text = String::from_utf8_lossy(written);
                Err(HostError::failed(if text.is_empty() {
                    format!("host service `{service}` failed with status {code}")
                } else {
                    text.into_owned()
                }))
            }
        }
    }

    /// Calls a callback that writes `f64` values, growing the buffer once if the host asks.
    fn call_with_values(
        &self,
        service: &str,
        mut body: impl FnMut(*mut ErrorBuffer, *mut F64Buffer) -> Option<Status>,
    ) -> Result<Vec<f64>, HostError> {
        let mut capacity = self.values_capacity.get();
        for _attempt in 0..2 {
            let mut values = vec![0.0; capacity];
            let mut buffer = F64Buffer { data: values.as_mut_ptr(), capacity, len: 0 };
            let mut too_small = false;
            self.call(service, |error| {
                let code = body(error, &raw mut buffer)?;
                too_small = code == status::BUFFER_TOO_SMALL;
                Some(if too_small { status::OK } else { code })
            })?;
            if too_small {
                capacity = buffer.len;
                self.values_capacity.set(capacity.max(self.values_capacity.get()));
                continue;
            }
            if buffer.len > capacity {
                return Err(HostError::failed(format!(
                    "host service `{service}` wrote {} values into a buffer of {capacity}",
                    buffer.len
                )));
            }
            values.truncate(buffer.len);
            return Ok(values);
        }
        Err(HostError::failed(format!("host service `{service}` kept asking for a larger buffer")))
    }
}

/// A service argument as the plugin lends it to the host for one call.
trait Lend {
    /// Its type in the C signature.
    type Raw;

    fn lend(self) -> Self::Raw;
}

impl Lend for &str {
    type Raw = ByteSlice;

    fn lend(self) -> ByteSlice {
        ByteSlice::from_text(self)
    }
}

impl Lend for &[f64] {
    type Raw = F64Slice;

    fn lend(self) -> F64Slice {
        F64Slice::new(self)
    }
}

impl Lend for &Pose {
    type Raw = *const Pose;

    fn lend(self) -> *const Pose {
        self
    }
}

/// Arguments passed by value.
macro_rules! by_value {
    ($($value:ty),*) => {$(
        impl Lend for $value {
            type Raw = $value;

            fn lend(self) -> $value {
                self
            }
        }
    )*};
}

by_value!(f64, u64);

/// A service's answer as the plugin reads it from the output slots it lends the host.
trait FromSlots: Sized {
    /// The output parameters of the C signature.
    type Slots;

    /// Calls `callback` with fresh slots and reads the answer from them; `None` from the callback
    /// means the host does not offer the service.
    fn from_slots(
        proxy: &HostProxy<'_>,
        service: &str,
        callback: impl FnMut(Self::Slots, *mut ErrorBuffer) -> Option<Status>,
    ) -> Result<Self, HostError>;
}

/// Answers read whole from one slot, which starts at the type's default.
macro_rules! one_slot {
    ($($value:ty),*) => {$(
        impl FromSlots for $value {
            type Slots = (*mut $value,);

            fn from_slots(
                proxy: &HostProxy<'_>,
                service: &str,
                mut callback: impl FnMut(Self::Slots, *mut ErrorBuffer) -> Option<Status>,
            ) -> Result<Self, HostError> {
                let mut value = <$value>::default();
                proxy.call(service, |error| callback((&raw mut value,), error))?;
                Ok(value)
            }
        }
    )*};
}

one_slot!(bool, f64, Pose);

impl FromSlots for Vec<f64> {
    type Slots = (*mut F64Buffer,);

    fn from_slots(
        proxy: &HostProxy<'_>,
        service: &str,
        mut callback: impl FnMut(Self::Slots, *mut ErrorBuffer) -> Option<Status>,
    ) -> Result<Self, HostError> {
        proxy.call_with_values(service, |error, out| callback((out,), error))
    }
}

impl FromSlots for Option<Vec<f64>> {
    type Slots = (*mut bool, *mut F64Buffer);

    fn from_slots(
        proxy: &HostProxy<'_>,
        service: &str,
        mut callback: impl FnMut(Self::Slots, *mut ErrorBuffer) -> Option<Status>,
    ) -> Result<Self, HostError> {
        let mut found = false;
        let values =
            proxy.call_with_values(service, |error, out| callback((&raw mut found, out), error))?;
        Ok(found.then_some(values))
    }
}

/// Generates the [`HostServices`] implementation from the ABI's description: each service lends
/// its arguments ([`Lend`]), calls the host's function pointer when the host's table holds it,
/// and reads the answer from the slots ([`FromSlots`]).
macro_rules! host_proxy {
    ($(
        $(#[$doc:meta])*
        fn $name:ident($($argument:ident: $raw:ty as $rust:ty),* $(,)?)
            writes ($($output:ident: $slot:ty),*) as $answer:ty;
    )*) => {
        impl HostServices for HostProxy<'_> {
            fn report_progress(&self, fraction: f64, message: &str) {
                if let Some(report) = self.vtable.report_progress {
                    // SAFETY: a host callback called with its own context and a slice valid for
                    // the call.
                    unsafe { report(self.context, fraction, ByteSlice::from_text(message)) };
                }
            }

            fn is_cancelled(&self) -> bool {
                // SAFETY: a host callback called with its own context.
                self.vtable
                    .is_cancelled
                    .is_some_and(|is_cancelled| unsafe { is_cancelled(self.context) })
            }

            $(
                fn $name(&self, $($argument: $rust),*) -> Result<$answer, HostError> {
                    // A field the host's table does not hold (a v1.0 host has no sampling) is
                    // never read: the service is unsupported.
                    let offered = self.host_offers(std::mem::offset_of!(HostVtable, $name));
                    let callback = if offered { self.vtable.$name } else { None };
                    <$answer>::from_slots(self, stringify!($name), |($($output,)*), error| {
                        let callback = callback?;
                        // SAFETY: a host callback called with its own context; the arguments
                        // are borrowed and the slots and error buffer owned by this frame for
                        // the call.
                        Some(unsafe { callback(self.context, $($argument.lend(),)* $($output,)* error) })
                    })
                }
            )*
        }
    };
}

for_each_host_service!(host_proxy);

#[cfg(test)]
mod tests {
    use std::cell::Cell;

    use super::*;

    /// Length of the configurations the test host samples: more than the first buffer holds.
    const SAMPLE_LENGTH: usize = VALUES_CAPACITY_HINT + 4;

    /// Writes `seed, seed + 1, ...` and counts its calls in the `Cell<usize>` behind `context`.
    unsafe extern "C" fn counting_sampler(
        context: *mut c_void,
        _robot: ByteSlice,
        seed: u64,
        out_q: *mut F64Buffer,
        _error: *mut ErrorBuffer,
    ) -> Status {
        // SAFETY: the tests pass a live `Cell<usize>` as the context and a valid buffer.
        let (calls, buffer) = unsafe { (&*context.cast::<Cell<usize>>(), &mut *out_q) };
        calls.set(calls.get() + 1);
        buffer.len = SAMPLE_LENGTH;
        if buffer.capacity < SAMPLE_LENGTH {
            return status::BUFFER_TOO_SMALL;
        }
        for index in 0..SAMPLE_LENGTH {
            // SAFETY: `index` is below the capacity checked above.
            unsafe { buffer.data.add(index).write(seed as f64 + index as f64) };
        }
        status::OK
    }

    fn host_table(struct_size: usize) -> HostVtable {
        HostVtable {
            struct_size,
            report_progress: None,
            is_cancelled: None,
            configuration_is_valid: None,
            edge_is_valid: None,
            solve_ik: None,
            forward_kinematics: None,
            distance: None,
            interpolate: None,
            sample_configuration: Some(counting_sampler),
        }
    }

    #[test]
    fn a_v1_1_host_samples_and_the_buffer_grows_once_per_call() {
        let calls = Cell::new(0_usize);
        let table = host_table(size_of::<HostVtable>());
        let context = std::ptr::from_ref(&calls).cast_mut().cast::<c_void>();
        // SAFETY: the table and the counter outlive the proxy.
        let proxy = unsafe { HostProxy::new(&raw const table, context) }.unwrap();
        let expected: Vec<f64> = (0..SAMPLE_LENGTH).map(|index| 7.0 + index as f64).collect();
        assert_eq!(proxy.sample_configuration("arm", 7), Ok(expected));
        assert_eq!(calls.get(), 2, "one call found the buffer too small, one filled it");
        assert_eq!(proxy.sample_configuration("arm", 8).unwrap()[0], 8.0);
        assert_eq!(calls.get(), 3, "the second sample fits the remembered length");
    }

    #[test]
    fn a_v1_0_host_is_unsupported_without_reading_past_its_table() {
        let calls = Cell::new(0_usize);
        // The field is set, but a v1.0 host's `struct_size` does not cover it.
        let table = host_table(v1_0_sizes::HOST);
        let context = std::ptr::from_ref(&calls).cast_mut().cast::<c_void>();
        // SAFETY: the table and the counter outlive the proxy.
        let proxy = unsafe { HostProxy::new(&raw const table, context) }.unwrap();
        assert_eq!(
            proxy.sample_configuration("arm", 7),
            Err(HostError::unsupported("sample_configuration"))
        );
        assert_eq!(calls.get(), 0);
        // The v1.1 table ends at its sampling field, after everything v1.0 had.
        const { assert!(v1_0_sizes::HOST < lamp_plugin_abi::v1_1_sizes::HOST) };
        const { assert!(lamp_plugin_abi::v1_1_sizes::HOST == size_of::<HostVtable>()) };
    }
}
