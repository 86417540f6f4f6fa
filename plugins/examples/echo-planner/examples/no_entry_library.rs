//! Test fixture: a shared library that is not a lamp plugin (it exports no entry table).

/// Something for the library to contain.
#[must_use]
pub fn answer() -> u32 {
    42
}
