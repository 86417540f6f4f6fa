//! Arbitrary input never panics the parser or the checker.

mod common;

use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,300}") {
        let _ = common::check(&text);
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let _ = common::check(&String::from_utf8_lossy(&bytes));
    }

    /// Cutting, deleting or duplicating pieces of a valid spec gives diagnostics, not panics.
    #[test]
    fn mutated_valid_specs_never_panic(start in 0usize..2000, length in 0usize..40, insert in "[a-z0-9(){},.\" ]{0,12}") {
        let valid = common::VALID;
        let start = start.min(valid.len());
        let end = (start + length).min(valid.len());
        if valid.is_char_boundary(start) && valid.is_char_boundary(end) {
            let mutated = format!("{}{insert}{}", &valid[..start], &valid[end..]);
            let outcome = common::check(&mutated);
            // Rendering must not panic either, whatever the spans.
            let _ = common::render(&outcome);
            prop_assert_eq!(outcome.spec.is_some(), outcome.diagnostics.is_empty());
        }
    }
}

/// A label never splits a character, also where the offending character is a multi-byte space
/// (found by the `check` fuzz target: the label took one byte of a thin space).
#[test]
fn a_syntax_error_at_a_multibyte_space_labels_the_whole_character() {
    for space in ['\u{2009}', '\u{a0}', '\u{3000}'] {
        let outcome = common::check(&format!("domain x\nseed{space} 1\n"));
        let diagnostic = outcome.diagnostics.first().expect("a syntax error");
        assert_eq!(diagnostic.code(), "lamp::parse::syntax");
        let text = outcome.sources.text(diagnostic.file);
        let range = diagnostic.range();
        assert!(text.is_char_boundary(range.start) && text.is_char_boundary(range.end));
        assert_eq!(&text[range], space.to_string());
        let _ = common::render(&outcome);
    }
}
