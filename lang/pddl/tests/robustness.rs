//! Arbitrary and mutated input never panics the reader; it either parses or returns diagnostics.

use lamp_pddl::{parse_domain, parse_problem};
use proptest::prelude::*;

const PACKING: &str = include_str!("fixtures/paper_packing.pddl");

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,200}") {
        let _ = parse_domain(&text);
    }

    #[test]
    fn s_expressions_never_panic(text in "[()a-z?: =\\-;\n]{0,300}") {
        if let Ok(domain) = parse_domain(&text) {
            let _ = parse_problem(&text, &domain);
        }
    }

    #[test]
    fn truncated_or_spliced_domains_never_panic(cut in 0..PACKING.len(), insert in "[()?a-z \\-]{0,8}") {
        let cut = (0..=cut).rev().find(|&index| PACKING.is_char_boundary(index)).unwrap_or(0);
        let truncated = &PACKING[..cut];
        let _ = parse_domain(truncated);
        let spliced = format!("{}{insert}{}", &PACKING[..cut], &PACKING[cut..]);
        let _ = parse_domain(&spliced);
    }
}

#[test]
fn deep_nesting_is_parsed_or_rejected_without_overflow() {
    for depth in [1_000_usize, 20_000, 100_000] {
        let nested = format!(
            "(define (domain d) (:action a :precondition {}{}))",
            "(and ".repeat(depth),
            ")".repeat(depth)
        );
        let result = parse_domain(&nested);
        if depth == 1_000 {
            assert!(result.is_ok(), "nested conjunctions are valid PDDL");
        }
        let unbalanced = format!("(define (domain d) (:functions {}))", "(".repeat(depth));
        assert!(parse_domain(&unbalanced).is_err());
    }
}
