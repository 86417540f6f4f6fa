//! The learned domains printed in the LAMP paper parse cleanly and survive a write/parse round trip.

use lamp_pddl::{Condition, Domain, parse_domain, write_domain};

fn fixture(name: &str) -> String {
    let path = format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|error| panic!("reading {path}: {error}"))
}

fn parse(name: &str) -> Domain {
    parse_domain(&fixture(name)).unwrap_or_else(|errors| panic!("{name}: {errors:#?}"))
}

#[test]
fn packing_domain_parses_with_five_actions() {
    let domain = parse("paper_packing.pddl");
    assert_eq!(domain.name, "packing");
    assert_eq!(domain.types.len(), 3);
    assert_eq!(domain.predicates.len(), 7);
    assert_eq!(domain.actions.len(), 5);
    let a3 = domain.action("a3").expect("a3 is printed in the paper");
    assert_eq!(a3.parameters.len(), 3);
    assert_eq!(a3.precondition.len(), 3);
    assert_eq!((a3.add.len(), a3.delete.len()), (2, 2));
}

#[test]
fn cafe_domain_parses_with_twelve_actions() {
    let domain = parse("paper_cafeworld.pddl");
    assert_eq!(domain.name, "cafeworld");
    assert_eq!(domain.types.len(), 4);
    assert!(domain.constants.is_empty());
    assert_eq!(domain.predicates.len(), 17);
    assert_eq!(domain.actions.len(), 12);
    let a2 = domain.action("a2").expect("a2 is printed in the paper");
    let inequalities =
        a2.precondition.iter().filter(|c| matches!(c, Condition::Equality { positive: false, .. }));
    assert_eq!(inequalities.count(), 1);
    assert_eq!(a2.precondition.len(), 9);
}

#[test]
fn jenga_domain_parses_with_lowered_constant() {
    let domain = parse("paper_jenga.pddl");
    assert_eq!(domain.actions.len(), 14);
    assert_eq!(domain.predicates.len(), 25);
    assert_eq!(domain.constants.len(), 1);
    // PDDL names are case-insensitive; the reader lowers them.
    assert_eq!(domain.constants[0].name, "loc_jengatarget_const");
    let a3 = domain.action("a3").expect("a3 is printed in the paper");
    assert_eq!(a3.delete.len(), 20);
    assert_eq!(a3.add.len(), 3);
}

#[test]
fn paper_domains_round_trip_through_the_writer() {
    for name in ["paper_packing.pddl", "paper_cafeworld.pddl", "paper_jenga.pddl"] {
        let domain = parse(name);
        let written = write_domain(&domain);
        let reparsed =
            parse_domain(&written).unwrap_or_else(|errors| panic!("{name}: {errors:#?}"));
        // Declared-but-unused requirements are not written back; everything else is identical.
        let mut expected = domain.clone();
        expected.requirements = reparsed.requirements.clone();
        assert_eq!(reparsed, expected, "{name}");
        assert_eq!(write_domain(&reparsed), written, "{name}: writing is a fixed point");
    }
}

#[test]
fn writer_declares_only_used_requirements() {
    let packing = write_domain(&parse("paper_packing.pddl"));
    assert!(packing.contains("(:requirements :strips :typing)\n"), "{packing}");
    let cafe = write_domain(&parse("paper_cafeworld.pddl"));
    assert!(cafe.contains("(:requirements :strips :typing :equality)\n"), "{cafe}");
}
