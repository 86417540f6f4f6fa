//! Every number a user writes in a plugin block or as a demonstration count is range-checked by
//! `lampc check`, with a span and the allowed range, by the same rules `lampc`'s flags use
//! (`lamp_spec::limits`); built-in plugins' options are known by name, a library's pass through.

mod common;

use std::path::Path;

use common::{VALID, check, codes, render};
use lamp_lang::{CheckOutcome, MemoryLoader};

/// `VALID` with a `plugins` block holding `block`.
fn with_plugins(block: &str) -> String {
    format!("{VALID}\nplugins {{\n{block}\n}}\n")
}

/// The codes and the text each diagnostic points at.
fn found(source: &str, outcome: &CheckOutcome) -> Vec<(String, String)> {
    outcome.diagnostics.iter().map(|d| (d.code(), source[d.range()].to_string())).collect()
}

/// Checks `block`, asserts that it is accepted, and returns the spec.
fn accepted(block: &str) -> lamp_spec::Spec {
    let outcome = check(&with_plugins(block));
    assert!(outcome.diagnostics.is_empty(), "{block}: {}", render(&outcome));
    outcome.spec.expect("a spec without diagnostics")
}

/// Checks `block` and asserts one diagnostic with `code` at `text`; returns the rendering.
fn refused(block: &str, code: &str, text: &str) -> String {
    let source = with_plugins(block);
    let outcome = check(&source);
    assert_eq!(
        found(&source, &outcome),
        [(code.to_string(), text.to_string())],
        "{block}:\n{}",
        render(&outcome)
    );
    assert!(outcome.spec.is_none());
    render(&outcome)
}

#[test]
fn time_limits_are_at_least_a_millisecond_and_at_most_a_week() {
    let rendered =
        refused("  planner gbfs-ff { timeout -30 s }", "lamp::check::out_of_range", "-30 s");
    assert!(rendered.contains("`timeout` of the planner is out of range"), "{rendered}");
    assert!(
        rendered.contains("from 0.001 s to 604800 s (one week)"),
        "the help names the range: {rendered}"
    );
    refused("  planner gbfs-ff { timeout 1e308 s }", "lamp::check::out_of_range", "1e308 s");
    refused("  planner gbfs-ff { timeout 1e400 s }", "lamp::check::out_of_range", "1e400 s");
    refused("  planner gbfs-ff { timeout 0 ms }", "lamp::check::out_of_range", "0 ms");
    let rendered =
        refused("  planner gbfs-ff { timeout 1e-300 s }", "lamp::check::out_of_range", "1e-300 s");
    assert!(rendered.contains("from 0.001 s to 604800 s"), "{rendered}");
    refused("  motion rrt-connect { timeout 0.5 ms }", "lamp::check::out_of_range", "0.5 ms");
    refused("  motion rrt-connect { timeout -1 s }", "lamp::check::out_of_range", "-1 s");
    refused("  motion rrt-connect { timeout 30 }", "lamp::check::unit_required", "30");
    refused("  planner topk { timeout 3 m }", "lamp::check::wrong_unit", "m");
    refused("  planner topk { timeout \"long\" }", "lamp::check::out_of_range", "timeout");
    let spec = accepted("  planner topk { timeout 500 ms }");
    assert_eq!(
        spec.plugins.planner.options.get("timeout"),
        Some(&lamp_spec::OptionValue::Duration(0.5))
    );
}

#[test]
fn resolutions_are_lengths_or_angles_within_their_ranges() {
    let rendered =
        refused("  motion rrt-connect { resolution 0 rad }", "lamp::check::out_of_range", "0 rad");
    assert!(rendered.contains("from 0.001 rad to 0.1 rad"), "{rendered}");
    refused("  motion rrt-connect { resolution -0.01 m }", "lamp::check::out_of_range", "-0.01 m");
    refused(
        "  motion rrt-connect { resolution 0.001 mm }",
        "lamp::check::out_of_range",
        "0.001 mm",
    );
    refused(
        "  motion rrt-connect { resolution 1e308 deg }",
        "lamp::check::out_of_range",
        "1e308 deg",
    );
    refused("  motion rrt-connect { resolution 0.01 }", "lamp::check::unit_required", "0.01");
    refused("  motion rrt-connect { resolution 2 s }", "lamp::check::wrong_unit", "s");
    for fine in ["resolution 0.01 rad", "resolution 5 mm", "resolution 0.5 deg"] {
        accepted(&format!("  motion rrt-connect {{ {fine} }}"));
    }
}

#[test]
fn counts_are_whole_plain_numbers_within_their_ranges() {
    refused("  planner topk { plans 0 }", "lamp::check::out_of_range", "0");
    refused("  planner topk { plans 1001 }", "lamp::check::out_of_range", "1001");
    refused("  refiner gmm { samples 0 }", "lamp::check::out_of_range", "0");
    refused("  refiner gmm { samples 2.5 }", "lamp::check::not_integer", "2.5");
    refused("  refiner gmm { samples 4 s }", "lamp::check::unexpected_unit", "s");
    refused("  refiner gmm { draws -5 }", "lamp::check::out_of_range", "-5");
    refused("  motion rrt-connect { iterations 0 }", "lamp::check::out_of_range", "0");
    refused("  motion rrt-connect { step 0 }", "lamp::check::out_of_range", "0");
    let spec = accepted(
        "  planner topk { plans 50  timeout 30 s }\n  refiner gmm { samples 4  draws 300  displacement 25 cm }\n  motion rrt-connect { step 0.3  shortcuts 0  iterations 2000 }",
    );
    assert_eq!(
        spec.plugins.refiner.options.get("displacement"),
        Some(&lamp_spec::OptionValue::Length(0.25))
    );
}

#[test]
fn lengths_have_their_unit_and_range() {
    refused("  refiner gmm { displacement -1 m }", "lamp::check::out_of_range", "-1 m");
    refused("  refiner gmm { displacement 1 }", "lamp::check::unit_required", "1");
    refused("  refiner gmm { displacement 1 rad }", "lamp::check::wrong_unit", "rad");
}

#[test]
fn an_option_a_built_in_plugin_does_not_read_is_named_with_a_suggestion() {
    let rendered = refused("  refiner gmm { sample 4 }", "lamp::check::unknown_word", "sample");
    assert!(rendered.contains("unknown plugin option `sample`"), "{rendered}");
    assert!(rendered.contains("Did you mean `samples`?"), "{rendered}");
    assert!(rendered.contains("samples, draws, displacement"), "{rendered}");
    let rendered = refused("  planner topk { k 50 }", "lamp::check::unknown_word", "k");
    assert!(rendered.contains("timeout, plans"), "{rendered}");
    refused("  motion rrt-connect { shortcut 5 }", "lamp::check::unknown_word", "shortcut");
}

/// A spec whose planner is a library in the loader's files.
fn check_library(block: &str) -> (String, CheckOutcome) {
    let source = with_plugins(block);
    let loader = MemoryLoader::new([
        ("robots/gripper.urdf", "<robot name=\"g\"/>"),
        ("demos/a.mcap", ""),
        ("plugins/libmine.so", ""),
    ]);
    let outcome = lamp_lang::check_source("spec.lamp", &source, Path::new(""), &loader);
    (source, outcome)
}

#[test]
fn a_library_plugin_gets_any_option_but_the_runtimes_are_checked() {
    let (_, outcome) = check_library("  planner \"plugins/libmine.so\" { k 10  beam \"wide\" }");
    assert!(outcome.diagnostics.is_empty(), "{}", render(&outcome));
    let (source, outcome) =
        check_library("  planner \"plugins/libmine.so\" { k 10  timeout -1 s }");
    assert_eq!(
        found(&source, &outcome),
        [("lamp::check::out_of_range".to_string(), "-1 s".to_string())],
        "{}",
        render(&outcome)
    );
    let (source, outcome) = check_library("  motion \"plugins/libmine.so\" { resolution 0 rad }");
    assert_eq!(codes(&outcome), ["lamp::check::out_of_range"], "{source}");
}

#[test]
fn numbers_too_large_for_a_float_are_refused_wherever_they_stand() {
    let source = VALID.replacen("can c1 at (-0.2, 0, 0) m", "can c1 at (-0.2, 1e999, 0) m", 1);
    let outcome = check(&source);
    assert_eq!(
        found(&source, &outcome),
        [("lamp::check::out_of_range".to_string(), "1e999".to_string())],
        "{}",
        render(&outcome)
    );
    let source = VALID.replacen("rpy (0, 0, 30) deg", "rpy (0, 0, -1e999) deg", 1);
    assert_eq!(codes(&check(&source)), ["lamp::check::out_of_range"]);
}

#[test]
fn the_component_cap_is_a_whole_number_up_to_sixty_four() {
    let source =
        VALID.replacen("  threshold 0.5\n", "  threshold 0.5\n  components max 100000\n", 1);
    let outcome = check(&source);
    assert_eq!(
        found(&source, &outcome),
        [("lamp::check::out_of_range".to_string(), "100000".to_string())],
        "{}",
        render(&outcome)
    );
    assert!(render(&outcome).contains("a whole number from 1 to 64"));
    let source = VALID.replacen("  threshold 0.5\n", "  threshold 0.5\n  components max 64\n", 1);
    assert!(check(&source).diagnostics.is_empty());
}

#[test]
fn the_demonstration_count_is_at_least_one_and_at_most_ten_thousand() {
    for (count, code) in [
        ("0", "lamp::check::out_of_range"),
        ("10001", "lamp::check::out_of_range"),
        ("2.5", "lamp::check::not_integer"),
    ] {
        let source = VALID.replacen("count 20", &format!("count {count}"), 1);
        let outcome = check(&source);
        assert_eq!(
            found(&source, &outcome),
            [(code.to_string(), count.to_string())],
            "{}",
            render(&outcome)
        );
    }
    let rendered = render(&check(&VALID.replacen("count 20", "count 0", 1)));
    assert!(rendered.contains("a whole number from 1 to 10000"), "{rendered}");
}

/// The seed is read exactly: 2^53 + 1 is refused, not rounded to 2^53 (which is another seed).
#[test]
fn a_seed_beyond_2_to_the_53_is_refused_not_rounded() {
    for seed in ["9007199254740993", "18446744073709551615", "1e300", "-1"] {
        let source = VALID.replacen("seed 7", &format!("seed {seed}"), 1);
        let outcome = check(&source);
        assert!(outcome.spec.is_none(), "seed {seed}: {}", render(&outcome));
        assert!(render(&outcome).contains("a whole number from 0 to 2^53"), "seed {seed}");
    }
    for (seed, value) in [("9007199254740992", 1u64 << 53), ("7.0", 7), ("1e3", 1000)] {
        let source = VALID.replacen("seed 7", &format!("seed {seed}"), 1);
        let spec = check(&source).spec.unwrap_or_else(|| panic!("seed {seed} is accepted"));
        assert_eq!(spec.seed, value, "seed {seed}");
    }
}

/// A demonstrator's seed or object count past what it takes is refused with both bounds, not as
/// "must be zero or more" for a value that is.
#[test]
fn a_demonstrator_seed_or_object_count_too_large_names_the_range() {
    for (from, to, expected) in [
        ("seed 3 }", "seed 9007199254740993 }", "a whole number from 0 to 4294967295 (2^32 - 1)"),
        ("seed 3 }", "seed -1 }", "a whole number from 0 to 4294967295 (2^32 - 1)"),
        ("objects 1", "objects 0", "a whole number from 1 to 4294967295 (2^32 - 1)"),
        ("objects 1", "objects 5000000000", "a whole number from 1 to 4294967295 (2^32 - 1)"),
    ] {
        let source = VALID.replacen(from, to, 1);
        let outcome = check(&source);
        assert_eq!(codes(&outcome), ["lamp::check::out_of_range"], "{to}: {}", render(&outcome));
        assert!(render(&outcome).contains(expected), "{to}: {}", render(&outcome));
    }
    let source = VALID.replacen("seed 3 }", "seed 4294967295 }", 1);
    assert!(check(&source).spec.is_some(), "the largest seed is taken");
}

/// A grab distance past 10 m is a slip of the unit or the exponent: `1e300 m` let a magnet pick
/// up a can anywhere and the solve succeed. It is refused at the clause with the bound.
#[test]
fn a_grab_distance_beyond_ten_metres_is_refused() {
    for (range, taken) in
        [("0.0 m .. 1e300 m", false), ("0.0 m .. 10.5 m", false), ("0.0 m .. 10 m", true)]
    {
        let written = "grab distance 0.19 m .. 0.22 m";
        assert!(VALID.contains(written), "the valid spec has a grab distance");
        let source = VALID.replacen(written, &format!("grab distance {range}"), 1);
        let outcome = check(&source);
        assert_eq!(outcome.spec.is_some(), taken, "{range}: {}", render(&outcome));
        if !taken {
            assert_eq!(codes(&outcome), ["lamp::check::out_of_range"], "{range}");
            assert!(render(&outcome).contains("0 ≤ MIN ≤ MAX ≤ 10 m"), "{}", render(&outcome));
        }
    }
}

/// A learning grid whose range is not a length a relation could span (`1e300 m` passed the check
/// and failed in learning as a covariance that is not positive definite), or whose bins are finer
/// than anything a robot repeats, is refused at its number with the allowed range.
#[test]
fn a_learning_grid_is_at_most_a_kilometre_wide_and_ten_thousand_bins_fine() {
    let grid = "position bins (9, 9, 9) range (0.3, 0.3, 0.3) m";
    let refused_grids = [
        ("position bins (9, 9, 9) range (1e300, 0.3, 0.3) m", "1e300"),
        ("position bins (9, 9, 9) range (0.3, 1001, 0.3) m", "1001"),
        ("position bins (9, 9, 9) range (0.3, 0.3, -0.3) m", "-0.3"),
        ("position bins (9, 9, 9) range (0.3, 0.3, 0) m", "0"),
        ("position bins (9, 1e9, 9) range (0.3, 0.3, 0.3) m", "1e9"),
        ("position bins (9, 9, 9) range (0.3, 0.3, 0.3) m  rotation bins 1e6", "1e6"),
    ];
    for (written, number) in refused_grids {
        let source = VALID.replacen(grid, written, 1);
        let outcome = check(&source);
        assert_eq!(
            found(&source, &outcome),
            [("lamp::check::out_of_range".to_string(), number.to_string())],
            "{written}:\n{}",
            render(&outcome)
        );
        assert!(outcome.spec.is_none());
    }
    let rendered = render(&check(&VALID.replacen(grid, refused_grids[0].0, 1)));
    assert!(rendered.contains("the position range is out of range"), "{rendered}");
    assert!(rendered.contains("greater than 0 m and at most 1000 m (one kilometre)"), "{rendered}");
    let rendered = render(&check(&VALID.replacen(grid, refused_grids[4].0, 1)));
    assert!(rendered.contains("a whole number from 1 to 10000"), "{rendered}");
    let rendered = render(&check(&VALID.replacen(grid, refused_grids[5].0, 1)));
    assert!(rendered.contains("a whole number from 1 to 3600"), "{rendered}");
    let widest = "position bins (10000, 9, 9) range (1000, 0.3, 0.3) m  rotation bins 3600";
    let outcome = check(&VALID.replacen(grid, widest, 1));
    assert!(outcome.diagnostics.is_empty(), "{}", render(&outcome));
}

/// `VALID` with a structure of two cans whose second stands at `place`, and a goal building it
/// at `c1` with `offset`.
fn with_structure(place: &str, offset: &str) -> String {
    VALID
        .replacen(
            "relation in_box",
            &format!("structure stack {{\n  can c2 at {place}\n}}\n\nrelation in_box"),
            1,
        )
        .replacen(
            "    in_box(c1, box1)\n    surface_can_1(box1, c1)\n",
            &format!("    structure stack at box1{offset}\n"),
            1,
        )
        .replacen("    can c1 at (-0.2, 0, 0) m\n", "    can c2 at (-0.2, 0, 0) m\n", 1)
}

/// A structure object placed `1e300 m` from its anchor was reported by the build as a structure
/// that intersects itself; an offset beyond a kilometre is refused where it is written.
#[test]
fn a_structure_offset_beyond_a_kilometre_is_refused_at_its_number() {
    let accepted = with_structure("(0, 0, 0.011) m", "");
    let outcome = check(&accepted);
    assert!(outcome.diagnostics.is_empty(), "{accepted}\n{}", render(&outcome));
    let source = with_structure("(1e300, 0, 0.011) m", "");
    let outcome = check(&source);
    assert_eq!(
        found(&source, &outcome),
        [("lamp::check::out_of_range".to_string(), "1e300".to_string())],
        "{}",
        render(&outcome)
    );
    let rendered = render(&outcome);
    assert!(
        rendered.contains("the place of `c2` in structure `stack` is out of range"),
        "{rendered}"
    );
    assert!(rendered.contains("from -1000 m to 1000 m (one kilometre)"), "{rendered}");
    let source = with_structure("(0, 0, 0.011) m", " offset (0, -2e5, 0) cm");
    let outcome = check(&source);
    assert_eq!(
        found(&source, &outcome),
        [("lamp::check::out_of_range".to_string(), "-2e5".to_string())],
        "{}",
        render(&outcome)
    );
    assert!(render(&outcome).contains("the offset of structure `stack` is out of range"));
    assert!(check(&with_structure("(0, 0, 0.011) m", " offset (0, 0.5, 0) m")).spec.is_some());
}
