//! `rate R Hz` in a `simulate` block: a frequency with its unit, within
//! `lamp_spec::limits::RECORDING_RATE`, refused at the number that is wrong with the code that
//! says why.

mod common;

use common::{
    SIMULATE, VALID, check, refused_simulate_option, render, simulated_source, with_simulate_option,
};
use lamp_spec::DemoSource;

/// The recording rate of the checked spec's simulated source.
fn rate_of(source: &str) -> Option<f64> {
    match simulated_source(source) {
        DemoSource::Simulated { rate, .. } => rate,
        other => panic!("not simulated: {other:?}"),
    }
}

#[test]
fn without_the_option_steps_are_recorded_as_the_script_goes() {
    assert_eq!(rate_of(VALID), None);
}

#[test]
fn the_rate_is_read_in_hertz_with_its_bounds() {
    assert_eq!(rate_of(&with_simulate_option("rate 50 Hz")), Some(50.0));
    assert_eq!(rate_of(&with_simulate_option("rate 1 Hz")), Some(1.0));
    assert_eq!(rate_of(&with_simulate_option("rate 1000 Hz")), Some(1000.0));
    let first = SIMULATE.replace("count 20", "rate 62.5 Hz  count 20");
    assert_eq!(rate_of(&VALID.replacen(SIMULATE, &first, 1)), Some(62.5));
}

#[test]
fn a_rate_out_of_range_or_without_its_unit_is_refused_at_the_number() {
    let range = "lamp::check::out_of_range";
    let rendered = refused_simulate_option("rate 0.5 Hz", &[(range, "0.5 Hz")]);
    assert!(rendered.contains("from 1 Hz to 1000 Hz"), "{rendered}");
    refused_simulate_option("rate 2000 Hz", &[(range, "2000 Hz")]);
    refused_simulate_option("rate -50 Hz", &[(range, "-50 Hz")]);
    refused_simulate_option("rate 1e400 Hz", &[("lamp::check::out_of_range", "1e400 Hz")]);
    refused_simulate_option("rate 50", &[("lamp::check::unit_required", "50")]);
    refused_simulate_option("rate 50 s", &[("lamp::check::wrong_unit", "s")]);
    refused_simulate_option("rate fast", &[(range, "rate")]);
}

#[test]
fn the_rate_diagnostic_reads_as_users_see_it() {
    let extra = "rate 5000 Hz";
    let outcome = check(&with_simulate_option(extra));
    insta::assert_snapshot!(
        "recording_rate_out_of_range",
        format!("----- SOURCE (excerpt)\n{extra}\n----- DIAGNOSTICS\n{}", render(&outcome))
    );
}
