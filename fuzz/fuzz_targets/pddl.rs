//! The PDDL reader: a domain (and, after a NUL byte, a problem) through `lamp_pddl`.
//! The body is `lamp_fuzz_entries::pddl`, which the stable corpus replay test calls too.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lamp_fuzz_entries::pddl(data));
