//! `noise D A` in a `simulate` block: a length and an angle, both with units, each within its
//! range (`lamp_spec::limits::NOISE_POSITION`, `NOISE_ROTATION`), refused at the number that is
//! wrong with the code that says why.

mod common;

use common::{
    SIMULATE, VALID, check, codes, refused_simulate_option, render, simulated_source,
    with_simulate_option,
};
use lamp_spec::{DemoSource, TrackingNoise};

/// The tracking noise of the checked spec's simulated source.
fn noise_of(source: &str) -> TrackingNoise {
    match simulated_source(source) {
        DemoSource::Simulated { noise, .. } => noise,
        other => panic!("not simulated: {other:?}"),
    }
}

#[test]
fn without_the_option_there_is_no_noise() {
    assert_eq!(noise_of(VALID), TrackingNoise::NONE);
}

#[test]
fn the_distance_and_the_angle_are_read_in_si_units() {
    let noise = noise_of(&with_simulate_option("noise 2 mm 1 deg"));
    assert!((noise.position - 0.002).abs() < 1e-15, "{noise:?}");
    assert!((noise.rotation - 1f64.to_radians()).abs() < 1e-15, "{noise:?}");
    let noise = noise_of(&with_simulate_option("noise 0.5 cm 0.01 rad"));
    assert!((noise.position - 0.005).abs() < 1e-15, "{noise:?}");
    assert!((noise.rotation - 0.01).abs() < 1e-15, "{noise:?}");
    // Anywhere in the block, and zero is no noise.
    let first = SIMULATE.replace("count 20", "noise 0 m 0 deg  count 20");
    assert_eq!(noise_of(&VALID.replacen(SIMULATE, &first, 1)), TrackingNoise::NONE);
    // The bounds themselves are taken.
    let noise = noise_of(&with_simulate_option("noise 10 cm 45 deg"));
    assert!((noise.position - 0.1).abs() < 1e-15 && noise.rotation <= 45f64.to_radians());
}

#[test]
fn negative_or_absurd_values_are_refused_at_the_number_with_the_range() {
    let range = "lamp::check::out_of_range";
    let rendered = refused_simulate_option("noise -2 mm 1 deg", &[(range, "-2 mm")]);
    assert!(rendered.contains("from 0 m to 0.1 m (10 cm)"), "{rendered}");
    let rendered = refused_simulate_option("noise 2 mm -1 deg", &[(range, "-1 deg")]);
    assert!(rendered.contains("(45°)"), "{rendered}");
    refused_simulate_option("noise 11 cm 1 deg", &[(range, "11 cm")]);
    refused_simulate_option("noise 2 mm 46 deg", &[(range, "46 deg")]);
    refused_simulate_option("noise 1e400 m 1 deg", &[(range, "1e400 m")]);
    // Both wrong: both reported in one run.
    refused_simulate_option("noise 1 m 90 deg", &[(range, "1 m"), (range, "90 deg")]);
}

#[test]
fn units_are_required_and_of_the_right_kind() {
    refused_simulate_option(
        "noise 2 1",
        &[("lamp::check::unit_required", "2"), ("lamp::check::unit_required", "1")],
    );
    refused_simulate_option(
        "noise 2 deg 1 mm",
        &[("lamp::check::wrong_unit", "deg"), ("lamp::check::wrong_unit", "mm")],
    );
    refused_simulate_option("noise 2 s 1 deg", &[("lamp::check::wrong_unit", "s")]);
}

#[test]
fn a_noise_without_its_angle_names_the_form_to_write() {
    let rendered =
        refused_simulate_option("noise 2 mm", &[("lamp::check::missing_declaration", "noise")]);
    assert!(rendered.contains("`noise 2 mm 1 deg`"), "{rendered}");
    refused_simulate_option("noise high", &[("lamp::check::missing_declaration", "noise")]);
}

#[test]
fn noise_is_given_once() {
    let source = with_simulate_option("noise 2 mm 1 deg  noise 3 mm 1 deg");
    let outcome = check(&source);
    assert_eq!(codes(&outcome), ["lamp::resolve::duplicate_name"], "{}", render(&outcome));
    // A misspelt keyword is not the option, however it continues.
    let source = with_simulate_option("noise2 mm 1 deg");
    assert_eq!(codes(&check(&source)), ["lamp::parse::syntax"]);
}

#[test]
fn the_noise_diagnostics_read_as_users_see_them() {
    let cases = [("negative", "noise -2 mm 1 deg"), ("missing_angle", "noise 2 mm")];
    for (name, extra) in cases {
        let outcome = check(&with_simulate_option(extra));
        insta::assert_snapshot!(
            format!("tracking_noise_{name}"),
            format!("----- SOURCE (excerpt)\n{extra}\n----- DIAGNOSTICS\n{}", render(&outcome))
        );
    }
}

#[test]
fn dropped_poses_are_a_share_from_zero_to_nine_tenths() {
    let noise = noise_of(&with_simulate_option("noise 2 mm 1 deg  dropped 0.05"));
    assert!((noise.position - 0.002).abs() < 1e-15, "{noise:?}");
    assert_eq!(noise.dropped, 0.05);
    // On its own: poses missed, none perturbed.
    let noise = noise_of(&with_simulate_option("dropped 0.1"));
    assert_eq!((noise.position, noise.rotation, noise.dropped), (0.0, 0.0, 0.1));
    assert!(!noise.is_none());
    assert_eq!(noise_of(&with_simulate_option("dropped 0")), TrackingNoise::NONE);
    let range = "lamp::check::out_of_range";
    let rendered = refused_simulate_option("dropped 0.95", &[(range, "0.95")]);
    assert!(rendered.contains("from 0 to 0.9"), "{rendered}");
    refused_simulate_option("dropped -0.1", &[(range, "-0.1")]);
    refused_simulate_option("dropped 5 %", &[("lamp::parse::syntax", "%")]);
    refused_simulate_option("dropped 0.1 s", &[("lamp::check::unexpected_unit", "s")]);
}
