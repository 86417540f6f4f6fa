//! The entry functions of lamp's fuzz targets: one per reader of untrusted input.
//!
//! `fuzz/` (cargo fuzz, nightly) calls them on generated inputs and the corpus replay test of
//! `lamp-tests` (stable) calls them on every committed corpus file and crash reproducer, so the two
//! cannot drift. Each takes raw bytes, runs them through the product's real entry point, and
//! panics when a reader breaks its contract: a panic inside the reader, a diagnostic whose span
//! lies outside its file, or a value accepted by a reader that later code cannot use. A panic is
//! what a fuzzer detects; an error value returned for bad input is the expected outcome.

mod pddl;
mod samplers;
mod spec;
mod trajectory;

pub use pddl::pddl;
pub use samplers::samplers;
pub use spec::check;
pub use trajectory::trajectory;

/// An entry function: bytes in, a panic when the reader breaks its contract.
pub type Entry = fn(&[u8]);

/// Every fuzz target by name (the name of its `fuzz/fuzz_targets/*.rs` file and of its corpus and
/// regression folders), in the order the docs list them.
pub const TARGETS: &[(&str, Entry)] =
    &[("check", check), ("pddl", pddl), ("trajectory", trajectory), ("samplers", samplers)];

/// Splits an input into two files at its first NUL byte (the second is empty without one), both
/// as text with invalid UTF-8 replaced, as a file that reaches the reader could only be text.
fn two_texts(data: &[u8]) -> (String, Option<String>) {
    match data.iter().position(|&byte| byte == 0) {
        Some(at) => (
            String::from_utf8_lossy(&data[..at]).into_owned(),
            Some(String::from_utf8_lossy(&data[at + 1..]).into_owned()),
        ),
        None => (String::from_utf8_lossy(data).into_owned(), None),
    }
}

/// Diagnostics rendered per input: rendering reads the source around every label, so rendering
/// hundreds of them on a large input would slow the fuzzer without reaching new code.
const RENDERED_DIAGNOSTICS: usize = 16;

/// Checks that every label of a diagnostic (and of its related diagnostics) lies inside `text` on
/// character boundaries, then, for the first [`RENDERED_DIAGNOSTICS`] of an input (`index`),
/// renders it as a screen reader would; `what` names it in the panic.
fn check_diagnostic(diagnostic: &dyn miette::Diagnostic, text: &str, what: &str, index: usize) {
    check_labels(diagnostic, text, what);
    if index >= RENDERED_DIAGNOSTICS {
        return;
    }
    let mut rendered = String::new();
    let outcome = miette::NarratableReportHandler::new().render_report(&mut rendered, diagnostic);
    assert!(outcome.is_ok(), "{what}: the diagnostic does not render: {diagnostic}");
    assert!(!rendered.trim().is_empty(), "{what}: the diagnostic renders as nothing");
}

fn check_labels(diagnostic: &dyn miette::Diagnostic, text: &str, what: &str) {
    for label in diagnostic.labels().into_iter().flatten() {
        let start = label.offset();
        let end = start.checked_add(label.len());
        let inside = end.is_some_and(|end| {
            end <= text.len() && text.is_char_boundary(start) && text.is_char_boundary(end)
        });
        assert!(
            inside,
            "{what}: a label of `{diagnostic}` spans {start}+{} in a text of {} bytes, or splits a character",
            label.len(),
            text.len()
        );
    }
    for related in diagnostic.related().into_iter().flatten() {
        check_labels(related, text, what);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inputs_split_at_the_first_nul() {
        assert_eq!(two_texts(b"a\0b\0c"), ("a".to_string(), Some("b\0c".to_string())));
        assert_eq!(two_texts(b"a"), ("a".to_string(), None));
        assert_eq!(two_texts(b"\xff\0"), ("\u{fffd}".to_string(), Some(String::new())));
    }

    #[test]
    fn every_target_takes_empty_and_binary_input() {
        for (_, entry) in TARGETS {
            entry(b"");
            entry(&[0xff, 0x00, 0x89, b'M', b'C', b'A', b'P', 0x30, b'\r', b'\n']);
        }
    }
}
