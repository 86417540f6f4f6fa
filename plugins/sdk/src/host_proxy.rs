//! The host's services as seen by a plugin: [`HostServices`] implemented over the host's callback
//! vtable.

// Calls the host's `extern "C"` callbacks with pointers to plugin-owned buffers; each `unsafe`
// block states the ABI rule it relies on.
#![allow(unsafe_code)]

use std::ffi::c_void;
use std::mem::MaybeUninit;

use lamp_plugin_abi::{
    ByteSlice, ErrorBuffer, F64Buffer, F64Slice, HostVtable, Pose, Status, status, v1_0_sizes,
};
use lamp_plugin_api::{HostError, HostServices, PluginError};

use crate::boundary::sized_struct;

/// Longest host error message kept, in bytes.
const ERROR_CAPACITY: usize = 1024;

/// The host's services for the duration of one plugin call.
#[derive(Debug)]
pub(crate) struct HostProxy<'a> {
    vtable: &'a HostVtable,
    context: *mut c_void,
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
        Ok(Self { vtable, context })
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
}
