//! A spec with several mistakes reports every one of them, each at the right place.

mod common;

use common::{VALID, check, codes, render};

#[test]
fn five_mistakes_give_five_diagnostics_at_their_spans() {
    let source = VALID
        .replacen("kind free_flying", "kind flying", 1)
        .replacen("radius 0.0325 m", "radius 0.0325", 1)
        .replacen("  threshold 0.5\n", "  threshold 0\n", 1)
        .replacen(
            "    can c1 at (-0.2, 0, 0) m",
            "    can c1 at (-0.2, 0, 0) m\n    can c1 at (0.3, 0, 0) m",
            1,
        )
        .replacen("surface_can_1(box1, c1)", "surface_can_1(box1)", 1);
    let outcome = check(&source);
    let expected = [
        ("lamp::check::unknown_word", "flying"),
        ("lamp::check::unit_required", "0.0325"),
        ("lamp::check::out_of_range", "0"),
        ("lamp::resolve::duplicate_name", "c1"),
        ("lamp::goal::arity", "surface_can_1(box1)"),
    ];
    let found: Vec<(String, String)> =
        outcome.diagnostics.iter().map(|d| (d.code(), source[d.range()].to_string())).collect();
    let expected: Vec<(String, String)> =
        expected.iter().map(|(code, text)| (code.to_string(), text.to_string())).collect();
    assert_eq!(found, expected, "{}", render(&outcome));
    assert_eq!(codes(&outcome).len(), 5);
    assert!(outcome.spec.is_none());
}
