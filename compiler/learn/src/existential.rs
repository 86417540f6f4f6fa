//! Extra parameters that only say "some object is in this region" become negated clear or nowhere
//! atoms.
//!
//! An extra object linked to the changed ones by a single precondition atom `R_k(?e, ?x)`, and
//! mentioned by no effect, contributes only its existence: `?x` is in region k of *some* object of
//! `?e`'s type. That is exactly `(not (nowhere_R_k ?x))`; `R_k(?x, ?e)` is `(not (clear_R_k ?x))`.
//! Keeping `?e` as a parameter multiplies the action's groundings by the number of such objects
//! for nothing: Jenga's "across two blocks" has one for each block below ("on some marker"), which
//! turns n⁴ groundings of a tower of n blocks into n⁶. An extra that appears in two atoms joins
//! them (the base at the surface the can is on) and stays; so do robot parts, which are few
//! whatever the task's size (the caller passes only the extras that are objects).

use std::collections::{BTreeMap, BTreeSet};

use crate::lifted::LiftedAtom;
use crate::relations::{PairVocabulary, Symbol, symbol_name, symbols};

/// The clear and nowhere relations that say "in region k of no object", by the region relation's
/// name: `(nowhere, clear)`, each when the vocabulary has it.
pub(crate) struct Complements {
    by_relation: BTreeMap<String, (Option<String>, Option<String>)>,
}

impl Complements {
    pub(crate) fn new(vocabulary: &[PairVocabulary]) -> Self {
        let mut by_relation = BTreeMap::new();
        for symbol in symbols(vocabulary) {
            let Symbol::Relation { pair, region } = symbol else { continue };
            let pair_vocabulary = &vocabulary[pair];
            let named =
                |present: bool, symbol: Symbol| present.then(|| symbol_name(vocabulary, symbol));
            let nowhere =
                named(pair_vocabulary.has_nowhere(region), Symbol::Nowhere { pair, region });
            let clear = named(pair_vocabulary.has_clear(region), Symbol::Clear { pair, region });
            if nowhere.is_some() || clear.is_some() {
                by_relation.insert(symbol_name(vocabulary, symbol), (nowhere, clear));
            }
        }
        Self { by_relation }
    }

    /// The negated atom that says what `atom` says of `extra` without naming it.
    fn without(&self, atom: &LiftedAtom, extra: &str) -> Option<LiftedAtom> {
        let (nowhere, clear) = self.by_relation.get(&atom.predicate)?;
        let [primary, secondary] = atom.arguments.as_slice() else { return None };
        let (predicate, kept) = if primary == extra && secondary != extra {
            (nowhere.as_ref()?, secondary)
        } else if secondary == extra && primary != extra {
            (clear.as_ref()?, primary)
        } else {
            return None;
        };
        Some(LiftedAtom { predicate: predicate.clone(), arguments: vec![kept.clone()] })
    }
}

/// Replaces, in `preconditions`, every lone extra's atom by its negated complement in `negative`.
/// `effects` are the action's add and delete atoms: an extra they mention stays.
pub(crate) fn quantify_lone_extras(
    complements: &Complements,
    extras: &BTreeSet<String>,
    effects: &[&LiftedAtom],
    preconditions: &mut BTreeSet<LiftedAtom>,
    negative: &mut BTreeSet<LiftedAtom>,
) {
    let mentions = |atom: &LiftedAtom, name: &str| atom.arguments.iter().any(|a| a == name);
    for extra in extras {
        if effects.iter().any(|atom| mentions(atom, extra)) {
            continue;
        }
        let mut linking = preconditions.iter().filter(|atom| mentions(atom, extra));
        let (Some(only), None) = (linking.next(), linking.next()) else { continue };
        let Some(replacement) = complements.without(only, extra) else { continue };
        let only = only.clone();
        preconditions.remove(&only);
        negative.insert(replacement);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::TypePair;

    fn atom(predicate: &str, arguments: &[&str]) -> LiftedAtom {
        LiftedAtom {
            predicate: predicate.into(),
            arguments: arguments.iter().map(ToString::to_string).collect(),
        }
    }

    fn vocabulary() -> Vec<PairVocabulary> {
        vec![
            PairVocabulary {
                pair: TypePair::new("block", "block"),
                region_flags: vec![0],
                clear: vec![false],
                nowhere: vec![false],
            },
            PairVocabulary {
                pair: TypePair::new("loc", "block"),
                region_flags: vec![0],
                clear: vec![true],
                nowhere: vec![true],
            },
        ]
    }

    /// Jenga's "across two blocks": each block below is "on some marker"; the marker of the
    /// placed block is named by an effect and stays.
    #[test]
    fn a_marker_named_once_becomes_on_no_marker_negated() {
        let complements = Complements::new(&vocabulary());
        let extras: BTreeSet<String> = ["?loc_extra_p1", "?loc_extra_p2"].map(String::from).into();
        let placed = atom("loc_block_1", &["?loc_p1", "?block_p1"]);
        let mut preconditions: BTreeSet<LiftedAtom> = [
            atom("loc_block_1", &["?loc_extra_p1", "?block_p2"]),
            atom("loc_block_1", &["?loc_extra_p2", "?block_p3"]),
            atom("block_block_0", &["?block_p1", "?block_p2"]),
        ]
        .into();
        let mut negative = BTreeSet::new();
        quantify_lone_extras(&complements, &extras, &[&placed], &mut preconditions, &mut negative);
        assert_eq!(preconditions, [atom("block_block_0", &["?block_p1", "?block_p2"])].into());
        assert_eq!(
            negative,
            [
                atom("nowhere_loc_block_1", &["?block_p2"]),
                atom("nowhere_loc_block_1", &["?block_p3"])
            ]
            .into()
        );
    }

    /// An extra in its secondary place becomes a negated clear atom; one in two atoms, or in an
    /// effect, or in a relation with no complement, stays.
    #[test]
    fn only_lone_extras_with_a_complement_are_quantified() {
        let complements = Complements::new(&vocabulary());
        let extras: BTreeSet<String> =
            ["?block_extra_p1", "?loc_extra_p1", "?loc_extra_p2"].map(String::from).into();
        let joined = [
            atom("loc_block_1", &["?loc_extra_p1", "?block_p1"]),
            atom("loc_block_1", &["?loc_extra_p1", "?block_p2"]),
        ];
        let in_effect = atom("loc_block_1", &["?loc_extra_p2", "?block_p3"]);
        let no_complement = atom("block_block_1", &["?block_extra_p1", "?block_p1"]);
        let mut preconditions: BTreeSet<LiftedAtom> =
            joined.iter().cloned().chain([in_effect.clone(), no_complement]).collect();
        let before = preconditions.clone();
        let mut negative = BTreeSet::new();
        quantify_lone_extras(
            &complements,
            &extras,
            &[&in_effect],
            &mut preconditions,
            &mut negative,
        );
        assert_eq!(preconditions, before);
        assert!(negative.is_empty());

        let secondary: BTreeSet<String> = ["?block_extra_p1"].map(String::from).into();
        let mut preconditions: BTreeSet<LiftedAtom> =
            [atom("loc_block_1", &["?loc_p1", "?block_extra_p1"])].into();
        quantify_lone_extras(&complements, &secondary, &[], &mut preconditions, &mut negative);
        assert!(preconditions.is_empty());
        assert_eq!(negative, [atom("clear_loc_block_1", &["?loc_p1"])].into());
    }
}
