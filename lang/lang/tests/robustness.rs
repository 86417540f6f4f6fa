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
