//! Loading the bundled specs from disk for the demonstrators' tests and benches.

#![allow(dead_code)]

pub use lamp_test_support::domain;
