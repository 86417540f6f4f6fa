//! The host's services as seen by a plugin: [`HostServices`] implemented over the host's callback
//! vtable.

// Calls the host's `extern "C"` callbacks with pointers to plugin-owned buffers; each `unsafe`
// block states the ABI rule it relies on.
#![allow(unsafe_code)]

use std::cell::Cell;
use std::ffi::c_void;
use std::mem::MaybeUninit;

use lamp_plugin_abi::{
    ByteSlice, ErrorBuffer, F64Buffer, F64Slice, HostVtable, Pose, Status, status, v1_0_sizes,
    v1_1_sizes,
};
use lamp_plugin_api::{HostError, HostServices, PluginError};

use crate::boundary::sized_struct;

/// Longest host error message kept, in bytes.
const ERROR_CAPACITY: usize = 1024;

/// First buffer size for a sampled configuration, whose length the plugin cannot know in
/// advance; large enough for a mobile manipulator's base, torso and arm.
const SAMPLE_CAPACITY_HINT: usize = 16;

/// The host's services for the duration of one plugin call.
#[derive(Debug)]
pub(crate) struct HostProxy<'a> {
    vtable: &'a HostVtable,
    context: *mut c_void,
    /// The length of the last sampled configuration, so that a longer one makes the buffer grow
    /// once per call rather than once per sample.
    sample_capacity: Cell<usize>,
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
        Ok(Self { vtable, context, sample_capacity: Cell::new(SAMPLE_CAPACITY_HINT) })
    }

    /// Whether the host's table is large enough to hold fields up to `end` (a `v1_x_sizes`
    /// constant): a field beyond the host's `struct_size` is not there, whatever its bytes say.
    fn host_offers(&self, end: usize) -> bool {
        self.vtable.struct_size >= end
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
        capacity_hint: usize,
        mut body: impl FnMut(*mut ErrorBuffer, *mut F64Buffer) -> Option<Status>,
    ) -> Result<Vec<f64>, HostError> {
        let mut capacity = capacity_hint.max(1);
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

impl HostServices for HostProxy<'_> {
    fn report_progress(&self, fraction: f64, message: &str) {
        if let Some(report) = self.vtable.report_progress {
            // SAFETY: a host callback called with its own context and a slice valid for the call.
            unsafe { report(self.context, fraction, ByteSlice::from_text(message)) };
        }
    }

    fn is_cancelled(&self) -> bool {
        // SAFETY: a host callback called with its own context.
        self.vtable.is_cancelled.is_some_and(|is_cancelled| unsafe { is_cancelled(self.context) })
    }

    fn configuration_is_valid(&self, robot: &str, q: &[f64]) -> Result<bool, HostError> {
        let mut valid = false;
        self.call("configuration_is_valid", |error| {
            let callback = self.vtable.configuration_is_valid?;
            let (robot, q) = (ByteSlice::from_text(robot), F64Slice::new(q));
            // SAFETY: host callback, own context; inputs and outputs valid for the call.
            Some(unsafe { callback(self.context, robot, q, &raw mut valid, error) })
        })?;
        Ok(valid)
    }

    fn edge_is_valid(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<bool, HostError> {
        let mut valid = false;
        self.call("edge_is_valid", |error| {
            let callback = self.vtable.edge_is_valid?;
            let robot = ByteSlice::from_text(robot);
            let (a, b) = (F64Slice::new(a), F64Slice::new(b));
            // SAFETY: host callback, own context; inputs and outputs valid for the call.
            Some(unsafe { callback(self.context, robot, a, b, &raw mut valid, error) })
        })?;
        Ok(valid)
    }

    fn solve_ik(
        &self,
        robot: &str,
        link: &str,
        target: &Pose,
        seed_q: &[f64],
    ) -> Result<Option<Vec<f64>>, HostError> {
        let mut found = false;
        let configuration = self.call_with_values("solve_ik", seed_q.len(), |error, out_q| {
            let callback = self.vtable.solve_ik?;
            let (robot, link) = (ByteSlice::from_text(robot), ByteSlice::from_text(link));
            let seed = F64Slice::new(seed_q);
            // SAFETY: host callback, own context; inputs and outputs valid for the call.
            Some(unsafe {
                callback(self.context, robot, link, target, seed, &raw mut found, out_q, error)
            })
        })?;
        Ok(found.then_some(configuration))
    }

    fn forward_kinematics(&self, robot: &str, q: &[f64], link: &str) -> Result<Pose, HostError> {
        let mut pose = [0.0; 7];
        self.call("forward_kinematics", |error| {
            let callback = self.vtable.forward_kinematics?;
            let (robot, link) = (ByteSlice::from_text(robot), ByteSlice::from_text(link));
            // SAFETY: host callback, own context; inputs and outputs valid for the call.
            Some(unsafe {
                callback(self.context, robot, F64Slice::new(q), link, &raw mut pose, error)
            })
        })?;
        Ok(pose)
    }

    fn distance(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<f64, HostError> {
        let mut distance = 0.0;
        self.call("distance", |error| {
            let callback = self.vtable.distance?;
            let robot = ByteSlice::from_text(robot);
            let (a, b) = (F64Slice::new(a), F64Slice::new(b));
            // SAFETY: host callback, own context; inputs and outputs valid for the call.
            Some(unsafe { callback(self.context, robot, a, b, &raw mut distance, error) })
        })?;
        Ok(distance)
    }

    fn interpolate(
        &self,
        robot: &str,
        a: &[f64],
        b: &[f64],
        t: f64,
    ) -> Result<Vec<f64>, HostError> {
        self.call_with_values("interpolate", a.len(), |error, out_q| {
            let callback = self.vtable.interpolate?;
            let robot = ByteSlice::from_text(robot);
            let (a, b) = (F64Slice::new(a), F64Slice::new(b));
            // SAFETY: host callback, own context; inputs and outputs valid for the call.
            Some(unsafe { callback(self.context, robot, a, b, t, out_q, error) })
        })
    }

    fn sample_configuration(&self, robot: &str, seed: u64) -> Result<Vec<f64>, HostError> {
        // A v1.0 host has no such field: degrade to `Unsupported` without reading past its table.
        if !self.host_offers(v1_1_sizes::HOST) {
            return Err(HostError::unsupported("sample_configuration"));
        }
        let capacity = self.sample_capacity.get();
        let q = self.call_with_values("sample_configuration", capacity, |error, out_q| {
            let callback = self.vtable.sample_configuration?;
            let robot = ByteSlice::from_text(robot);
            // SAFETY: host callback, own context; inputs and outputs valid for the call; the
            // field is covered by the host's `struct_size` (checked above).
            Some(unsafe { callback(self.context, robot, seed, out_q, error) })
        })?;
        self.sample_capacity.set(capacity.max(q.len()));
        Ok(q)
    }
}

#[cfg(test)]
mod tests {
    use std::cell::Cell;

    use super::*;

    /// Length of the configurations the test host samples: more than the first buffer holds.
    const SAMPLE_LENGTH: usize = SAMPLE_CAPACITY_HINT + 4;

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
        const { assert!(v1_0_sizes::HOST < v1_1_sizes::HOST) };
        const { assert!(v1_1_sizes::HOST == size_of::<HostVtable>()) };
    }
}
