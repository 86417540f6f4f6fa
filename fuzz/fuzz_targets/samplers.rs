//! The sampler file reader (`lamp_build::SamplersFile::from_json`) and the use of what it accepts.
//! The body is `lamp_fuzz_entries::samplers`, which the stable corpus replay test calls too.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lamp_fuzz_entries::samplers(data));
