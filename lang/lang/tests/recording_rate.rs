//! `rate R Hz` in a `simulate` block: a frequency with its unit, within
//! `lamp_spec::limits::RECORDING_RATE`, refused at the number that is wrong with the code that
//! says why.

mod common;

use common::{VALID, check, render};
use lamp_lang::CheckOutcome;
use lamp_spec::DemoSource;

/// The `simulate` line of the valid spec, where the option goes.
const SIMULATE: &str = "simulate packing { count 20  cut 0.5  objects 1  seed 3 }";

/// The valid spec with `extra` written inside the `simulate` block, after the other options.
fn with_option(extra: &str) -> String {
    assert!(VALID.contains(SIMULATE), "the valid spec simulates packing");
    let simulate = SIMULATE.replace(" }", &format!("  {extra} }}"));
    VALID.replacen(SIMULATE, &simulate, 1)
}

/// The codes and the text each diagnostic points at.
fn found(source: &str, outcome: &CheckOutcome) -> Vec<(String, String)> {
    outcome.diagnostics.iter().map(|d| (d.code(), source[d.range()].to_string())).collect()
}

/// The recording rate of the checked spec's simulated source.
fn rate_of(source: &str) -> Option<f64> {
    let outcome = check(source);
    let rendered = render(&outcome);
    let spec = outcome.spec.unwrap_or_else(|| panic!("accepted:\n{rendered}"));
    match spec.demonstrations.as_slice() {
        [DemoSource::Simulated { rate, .. }] => *rate,
        other => panic!("one simulated source, not {other:?}"),
    }
}

/// Checks `extra` in the block and asserts one diagnostic per `(code, text)`; returns the
/// rendering.
fn refused(extra: &str, expected: &[(&str, &str)]) -> String {
    let source = with_option(extra);
    let outcome = check(&source);
    let expected: Vec<(String, String)> =
        expected.iter().map(|(code, text)| (code.to_string(), text.to_string())).collect();
    assert_eq!(found(&source, &outcome), expected, "{extra}:\n{}", render(&outcome));
    assert!(outcome.spec.is_none(), "{extra}: a spec with errors has no Spec");
    render(&outcome)
}

#[test]
fn without_the_option_steps_are_recorded_as_the_script_goes() {
    assert_eq!(rate_of(VALID), None);
}

#[test]
fn the_rate_is_read_in_hertz_with_its_bounds() {
    assert_eq!(rate_of(&with_option("rate 50 Hz")), Some(50.0));
    assert_eq!(rate_of(&with_option("rate 1 Hz")), Some(1.0));
    assert_eq!(rate_of(&with_option("rate 1000 Hz")), Some(1000.0));
    let first = SIMULATE.replace("count 20", "rate 62.5 Hz  count 20");
    assert_eq!(rate_of(&VALID.replacen(SIMULATE, &first, 1)), Some(62.5));
}

#[test]
fn a_rate_out_of_range_or_without_its_unit_is_refused_at_the_number() {
    let range = "lamp::check::out_of_range";
    let rendered = refused("rate 0.5 Hz", &[(range, "0.5 Hz")]);
    assert!(rendered.contains("from 1 Hz to 1000 Hz"), "{rendered}");
    refused("rate 2000 Hz", &[(range, "2000 Hz")]);
    refused("rate -50 Hz", &[(range, "-50 Hz")]);
    refused("rate 1e400 Hz", &[("lamp::check::out_of_range", "1e400 Hz")]);
    refused("rate 50", &[("lamp::check::unit_required", "50")]);
    refused("rate 50 s", &[("lamp::check::wrong_unit", "s")]);
    refused("rate fast", &[(range, "rate")]);
}

#[test]
fn the_rate_diagnostic_reads_as_users_see_it() {
    let extra = "rate 5000 Hz";
    let outcome = check(&with_option(extra));
    insta::assert_snapshot!(
        "recording_rate_out_of_range",
        format!("----- SOURCE (excerpt)\n{extra}\n----- DIAGNOSTICS\n{}", render(&outcome))
    );
}
