//! The `clear` and `nowhere` switches of the `learn` block, and goals over the relations they invent.

mod common;

use common::{VALID, check, codes, render};
use lamp_spec::Switch;

fn with(from: &str, to: &str) -> String {
    assert!(VALID.contains(from), "`{from}` is not in the valid spec");
    VALID.replacen(from, to, 1)
}

#[test]
fn switches_left_out_are_not_given_and_take_on_off_and_auto_per_block() {
    let outcome = check(VALID);
    let spec = outcome.spec.expect("the valid spec checks");
    assert_eq!((spec.learning.defaults.clear, spec.learning.defaults.nowhere), (None, None));

    let source = with(
        "  threshold 0.5\n  pair gripper can { position bins (9, 9, 9) range (0.3, 0.3, 0.3) m }",
        "  threshold 0.5\n  clear off\n  pair gripper can { position bins (9, 9, 9) range (0.3, 0.3, 0.3) m  clear auto  nowhere on }\n  pair surface can { nowhere off }",
    );
    let outcome = check(&source);
    let spec = outcome.spec.unwrap_or_else(|| panic!("{}", render(&check(&source))));
    let learning = &spec.learning;
    assert_eq!((learning.defaults.clear, learning.defaults.nowhere), (Some(Switch::Off), None));
    let gripper_can = learning.settings("gripper", "can");
    assert_eq!((gripper_can.clear, gripper_can.nowhere), (Some(Switch::Auto), Some(Switch::On)));
    // An override inherits the block-level settings for what it does not say.
    let surface_can = learning.settings("can", "surface");
    assert_eq!((surface_can.clear, surface_can.nowhere), (Some(Switch::Off), Some(Switch::Off)));
}

#[test]
fn a_repeated_switch_and_an_unknown_word_are_reported() {
    let repeated = with("  threshold 0.5\n", "  threshold 0.5\n  nowhere on\n  nowhere off\n");
    assert_eq!(codes(&check(&repeated)), ["lamp::check::duplicate_setting"]);
    let unknown = with("  threshold 0.5\n", "  threshold 0.5\n  nowhere maybe\n");
    let outcome = check(&unknown);
    assert_eq!(codes(&outcome), ["lamp::parse::syntax"]);
    assert!(render(&outcome).contains("`on`, `off` or `auto`"), "{}", render(&outcome));
}

#[test]
fn goals_may_name_clear_and_nowhere_relations_with_their_argument_types() {
    let goal = |atom: &str| check(&with("    surface_can_1(box1, c1)", atom));
    for good in ["    nowhere_surface_can_1(c1)", "    clear_surface_can_1(box1)"] {
        let outcome = goal(good);
        assert!(outcome.diagnostics.is_empty(), "{good}: {}", render(&outcome));
    }
    // `nowhere_…` is about the secondary (a can), `clear_…` about the primary (a surface).
    assert_eq!(codes(&goal("    nowhere_surface_can_1(box1)")), ["lamp::goal::argument_type"]);
    assert_eq!(codes(&goal("    clear_surface_can_1(c1)")), ["lamp::goal::argument_type"]);
}

#[test]
fn symmetry_is_a_setting_of_the_whole_block_given_once() {
    let outcome = check(VALID);
    assert_eq!(outcome.spec.expect("the valid spec checks").learning.symmetry, None);
    let on = with("  threshold 0.5\n", "  threshold 0.5\n  symmetry on\n");
    let spec = check(&on).spec.unwrap_or_else(|| panic!("{}", render(&check(&on))));
    assert_eq!(spec.learning.symmetry, Some(Switch::On));

    let repeated = with("  threshold 0.5\n", "  threshold 0.5\n  symmetry on\n  symmetry off\n");
    assert_eq!(codes(&check(&repeated)), ["lamp::check::duplicate_setting"]);
    let in_pair = with(
        "pair gripper can { position bins (9, 9, 9) range (0.3, 0.3, 0.3) m }",
        "pair gripper can { position bins (9, 9, 9) range (0.3, 0.3, 0.3) m  symmetry on }",
    );
    let outcome = check(&in_pair);
    assert_eq!(codes(&outcome), ["lamp::check::conflict"]);
    let rendered = render(&outcome);
    assert!(rendered.contains("`symmetry` is a setting of the whole `learn` block"), "{rendered}");
    assert!(rendered.contains("symmetry on }"), "points at the setting: {rendered}");
}
