//! The invented vocabulary: one relation per region, a "in no region" relation per pair, and "clear" relations.
//!
//! For a pair (t1, t2) with K ≥ 1 regions, numbered 1..K in region order (g, then smallest voxel):
//! `<t1>_<t2>_<k>(x, y)` holds iff y's pose in x's frame is in region k, `<t1>_<t2>_0(x, y)` iff it is in none,
//! `clear_<t1>_<t2>_<k>(x)` iff no object of type t2 is in region k of x, and `nowhere_<t1>_<t2>_<k>(y)` iff y is in
//! region k of no object of type t1 (each only for the regions where its side is on, as the learner decided).
//! A pair without regions gets no relations at all: `_0` would always hold and tell the planner nothing.

use std::fmt;

use crate::type_pair::TypePair;

/// The relations of one type pair.
#[derive(Debug, Clone, PartialEq)]
pub struct PairVocabulary {
    /// The ordered type pair.
    pub pair: TypePair,
    /// The held flag of each region, in relation order (region k is at index k − 1).
    pub region_flags: Vec<u8>,
    /// Whether region k has `clear_<t1>_<t2>_<k>`, in relation order.
    pub clear: Vec<bool>,
    /// Whether region k has `nowhere_<t1>_<t2>_<k>`, in relation order.
    pub nowhere: Vec<bool>,
}

impl PairVocabulary {
    /// The number of regions K.
    pub fn region_count(&self) -> usize {
        self.region_flags.len()
    }

    /// Whether region k (≥ 1) has a clear relation.
    pub fn has_clear(&self, region: usize) -> bool {
        region >= 1 && self.clear.get(region - 1).copied().unwrap_or(false)
    }

    /// Whether region k (≥ 1) has a nowhere relation.
    pub fn has_nowhere(&self, region: usize) -> bool {
        region >= 1 && self.nowhere.get(region - 1).copied().unwrap_or(false)
    }
}

/// A relation symbol of the vocabulary.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Symbol {
    /// `<t1>_<t2>_<k>` with k ≥ 1, or `_0` ("in no region") when `region` is 0.
    Relation { pair: usize, region: usize },
    /// `clear_<t1>_<t2>_<k>`.
    Clear { pair: usize, region: usize },
    /// `nowhere_<t1>_<t2>_<k>`.
    Nowhere { pair: usize, region: usize },
}

/// A named predicate with its parameter types.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct PredicateSignature {
    /// The predicate name.
    pub name: String,
    /// The types of its arguments.
    pub argument_types: Vec<String>,
}

impl fmt::Display for PredicateSignature {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}({})", self.name, self.argument_types.join(", "))
    }
}

/// The name of a symbol.
pub fn symbol_name(pairs: &[PairVocabulary], symbol: Symbol) -> String {
    match symbol {
        Symbol::Relation { pair, region } => format!("{}_{}", pairs[pair].pair.stem(), region),
        Symbol::Clear { pair, region } => format!("clear_{}_{}", pairs[pair].pair.stem(), region),
        Symbol::Nowhere { pair, region } => {
            format!("nowhere_{}_{}", pairs[pair].pair.stem(), region)
        }
    }
}

/// Every symbol, in declaration order: per pair (in pair order) `_0`, `_1` … `_K`, then its clear relations, then
/// its nowhere relations.
pub fn symbols(pairs: &[PairVocabulary]) -> Vec<Symbol> {
    let mut all = Vec::new();
    for (index, vocabulary) in pairs.iter().enumerate() {
        for region in 0..=vocabulary.region_count() {
            all.push(Symbol::Relation { pair: index, region });
        }
        for region in 1..=vocabulary.region_count() {
            if vocabulary.has_clear(region) {
                all.push(Symbol::Clear { pair: index, region });
            }
        }
        for region in 1..=vocabulary.region_count() {
            if vocabulary.has_nowhere(region) {
                all.push(Symbol::Nowhere { pair: index, region });
            }
        }
    }
    all
}

/// The signature of a symbol.
pub fn signature(pairs: &[PairVocabulary], symbol: Symbol) -> PredicateSignature {
    let name = symbol_name(pairs, symbol);
    let argument_types = match symbol {
        Symbol::Relation { pair, .. } => {
            vec![pairs[pair].pair.primary.clone(), pairs[pair].pair.secondary.clone()]
        }
        Symbol::Clear { pair, .. } => vec![pairs[pair].pair.primary.clone()],
        Symbol::Nowhere { pair, .. } => vec![pairs[pair].pair.secondary.clone()],
    };
    PredicateSignature { name, argument_types }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_declaration_order() {
        let pairs = vec![
            PairVocabulary {
                pair: TypePair::new("gripper", "can"),
                region_flags: vec![0, 1],
                clear: vec![true, true],
                nowhere: vec![false, true],
            },
            PairVocabulary {
                pair: TypePair::new("surface", "can"),
                region_flags: vec![0],
                clear: vec![false],
                nowhere: vec![true],
            },
        ];
        let names: Vec<String> =
            symbols(&pairs).into_iter().map(|s| symbol_name(&pairs, s)).collect();
        assert_eq!(
            names,
            [
                "gripper_can_0",
                "gripper_can_1",
                "gripper_can_2",
                "clear_gripper_can_1",
                "clear_gripper_can_2",
                "nowhere_gripper_can_2",
                "surface_can_0",
                "surface_can_1",
                "nowhere_surface_can_1"
            ]
        );
        let clear = signature(&pairs, Symbol::Clear { pair: 0, region: 2 });
        assert_eq!(clear.to_string(), "clear_gripper_can_2(gripper)");
        let nowhere = signature(&pairs, Symbol::Nowhere { pair: 1, region: 1 });
        assert_eq!(nowhere.to_string(), "nowhere_surface_can_1(can)");
    }
}
