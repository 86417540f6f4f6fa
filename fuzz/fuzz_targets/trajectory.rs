//! The MCAP demonstration and trajectory reader, whole and streamed.
//! The body is `lamp_fuzz_entries::trajectory`, which the stable corpus replay test calls too.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lamp_fuzz_entries::trajectory(data));
