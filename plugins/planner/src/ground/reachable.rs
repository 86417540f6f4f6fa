//! The reachable ground atoms of a grounding, and the indexes its joins look atoms up in.

use std::collections::{HashMap, HashSet};

use super::{Key, LiftedAction, LiftedAtom, Slot};

/// Which argument positions of an atom are meant: bit i for argument i (positions past 63 are
/// never indexed, only compared).
pub(super) type ArgumentMask = u64;

/// The positions of each atom of `positive` (in join order) that are known before it is joined.
pub(super) fn known_before(positive: &[LiftedAtom]) -> Vec<ArgumentMask> {
    let mut bound: HashSet<usize> = HashSet::new();
    positive
        .iter()
        .map(|atom| {
            let mut mask = 0;
            for (position, slot) in atom.slots.iter().enumerate().take(64) {
                let known = match slot {
                    Slot::Object(_) => true,
                    Slot::Parameter(index) => bound.contains(index),
                };
                if known {
                    mask |= 1 << position;
                }
            }
            for slot in &atom.slots {
                if let Slot::Parameter(index) = slot {
                    bound.insert(*index);
                }
            }
            mask
        })
        .collect()
}

/// An index of one predicate's atoms by their values at the positions of its mask: their
/// positions in [`Reachable::all`], in insertion order.
type AtomIndex = (ArgumentMask, HashMap<Vec<u32>, Vec<usize>>);

/// The values at the positions of `mask` among `arguments`.
pub(super) fn masked(mask: ArgumentMask, arguments: impl Iterator<Item = u32>) -> Vec<u32> {
    arguments.take(64).enumerate().filter(|(i, _)| mask & (1 << i) != 0).map(|(_, v)| v).collect()
}

/// The reachable ground atoms: a membership set, per predicate the argument tuples in insertion
/// order, and the indexes the joins look atoms up in.
pub(super) struct Reachable {
    set: HashSet<Key>,
    pub(super) all: Vec<Key>,
    pub(super) by_predicate: Vec<Vec<Key>>,
    /// Per predicate, an index for each set of known positions a join asks about: the atoms'
    /// positions in `all` by their values there, in insertion order. A lookup therefore meets
    /// the atoms a scan of `by_predicate` would accept, in the same order.
    indexes: Vec<Vec<AtomIndex>>,
}

impl Reachable {
    pub(super) fn new(predicates: usize, actions: &[LiftedAction]) -> Self {
        let mut indexes: Vec<Vec<AtomIndex>> = vec![Vec::new(); predicates];
        for action in actions {
            for (atom, &mask) in action.positive.iter().zip(&action.known_before) {
                let Some(masks) = indexes.get_mut(atom.predicate as usize) else { continue };
                if mask != 0 && !masks.iter().any(|(known, _)| *known == mask) {
                    masks.push((mask, HashMap::new()));
                }
            }
        }
        Self {
            set: HashSet::new(),
            all: Vec::new(),
            by_predicate: vec![Vec::new(); predicates],
            indexes,
        }
    }

    pub(super) fn contains(&self, key: &Key) -> bool {
        self.set.contains(key)
    }

    pub(super) fn insert(&mut self, key: Key) {
        if self.set.insert(key.clone()) {
            let position = self.all.len();
            if let Some(list) = self.by_predicate.get_mut(key[0] as usize) {
                list.push(key.clone());
            }
            if let Some(indexes) = self.indexes.get_mut(key[0] as usize) {
                for (mask, index) in indexes {
                    let values = masked(*mask, key[1..].iter().copied());
                    index.entry(values).or_default().push(position);
                }
            }
            self.all.push(key);
        }
    }

    /// The positions in `all` of the atoms of `predicate` with `values` at the positions of
    /// `mask`; `None` when no join asked for that index.
    pub(super) fn lookup(
        &self,
        predicate: u32,
        mask: ArgumentMask,
        values: &[u32],
    ) -> Option<&[usize]> {
        let (_, index) =
            self.indexes.get(predicate as usize)?.iter().find(|(known, _)| *known == mask)?;
        Some(index.get(values).map_or(&[][..], Vec::as_slice))
    }
}
