//! The `.lamp` front end: a spec (and, after a NUL byte, a scene file) through `lamp_lang::check`.
//! The body is `lamp_fuzz_entries::check`, which the stable corpus replay test calls too.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lamp_fuzz_entries::check(data));
