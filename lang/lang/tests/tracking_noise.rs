//! `noise D A` in a `simulate` block: a length and an angle, both with units, each within its
//! range (`lamp_spec::limits::NOISE_POSITION`, `NOISE_ROTATION`), refused at the number that is
//! wrong with the code that says why.

mod common;

use common::{VALID, check, codes, render};
use lamp_lang::CheckOutcome;
use lamp_spec::{DemoSource, TrackingNoise};

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

/// The tracking noise of the checked spec's simulated source.
fn noise_of(source: &str) -> TrackingNoise {
    let outcome = check(source);
    let rendered = render(&outcome);
    let spec = outcome.spec.unwrap_or_else(|| panic!("accepted:\n{rendered}"));
    match spec.demonstrations.as_slice() {
        [DemoSource::Simulated { noise, .. }] => *noise,
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
fn without_the_option_there_is_no_noise() {
    assert_eq!(noise_of(VALID), TrackingNoise::NONE);
}

#[test]
fn the_distance_and_the_angle_are_read_in_si_units() {
    let noise = noise_of(&with_option("noise 2 mm 1 deg"));
    assert!((noise.position - 0.002).abs() < 1e-15, "{noise:?}");
    assert!((noise.rotation - 1f64.to_radians()).abs() < 1e-15, "{noise:?}");
    let noise = noise_of(&with_option("noise 0.5 cm 0.01 rad"));
    assert!((noise.position - 0.005).abs() < 1e-15, "{noise:?}");
    assert!((noise.rotation - 0.01).abs() < 1e-15, "{noise:?}");
    // Anywhere in the block, and zero is no noise.
    let first = SIMULATE.replace("count 20", "noise 0 m 0 deg  count 20");
    assert_eq!(noise_of(&VALID.replacen(SIMULATE, &first, 1)), TrackingNoise::NONE);
    // The bounds themselves are taken.
    let noise = noise_of(&with_option("noise 10 cm 45 deg"));
    assert!((noise.position - 0.1).abs() < 1e-15 && noise.rotation <= 45f64.to_radians());
}

#[test]
fn negative_or_absurd_values_are_refused_at_the_number_with_the_range() {
    let range = "lamp::check::out_of_range";
    let rendered = refused("noise -2 mm 1 deg", &[(range, "-2 mm")]);
    assert!(rendered.contains("from 0 m to 0.1 m (10 cm)"), "{rendered}");
    let rendered = refused("noise 2 mm -1 deg", &[(range, "-1 deg")]);
    assert!(rendered.contains("(45°)"), "{rendered}");
    refused("noise 11 cm 1 deg", &[(range, "11 cm")]);
    refused("noise 2 mm 46 deg", &[(range, "46 deg")]);
    refused("noise 1e400 m 1 deg", &[(range, "1e400 m")]);
    // Both wrong: both reported in one run.
    refused("noise 1 m 90 deg", &[(range, "1 m"), (range, "90 deg")]);
}

#[test]
fn units_are_required_and_of_the_right_kind() {
    refused(
        "noise 2 1",
        &[("lamp::check::unit_required", "2"), ("lamp::check::unit_required", "1")],
    );
    refused(
        "noise 2 deg 1 mm",
        &[("lamp::check::wrong_unit", "deg"), ("lamp::check::wrong_unit", "mm")],
    );
    refused("noise 2 s 1 deg", &[("lamp::check::wrong_unit", "s")]);
}

#[test]
fn a_noise_without_its_angle_names_the_form_to_write() {
    let rendered = refused("noise 2 mm", &[("lamp::check::missing_declaration", "noise")]);
    assert!(rendered.contains("`noise 2 mm 1 deg`"), "{rendered}");
    refused("noise high", &[("lamp::check::missing_declaration", "noise")]);
}

#[test]
fn noise_is_given_once() {
    let source = with_option("noise 2 mm 1 deg  noise 3 mm 1 deg");
    let outcome = check(&source);
    assert_eq!(codes(&outcome), ["lamp::resolve::duplicate_name"], "{}", render(&outcome));
    // A misspelt keyword is not the option, however it continues.
    let source = with_option("noise2 mm 1 deg");
    assert_eq!(codes(&check(&source)), ["lamp::parse::syntax"]);
}

#[test]
fn the_noise_diagnostics_read_as_users_see_them() {
    let cases = [("negative", "noise -2 mm 1 deg"), ("missing_angle", "noise 2 mm")];
    for (name, extra) in cases {
        let outcome = check(&with_option(extra));
        insta::assert_snapshot!(
            format!("tracking_noise_{name}"),
            format!("----- SOURCE (excerpt)\n{extra}\n----- DIAGNOSTICS\n{}", render(&outcome))
        );
    }
}
