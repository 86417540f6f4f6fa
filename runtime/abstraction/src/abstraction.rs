//! Abstraction: a low-level snapshot becomes the set of true facts of the vocabulary.
//!
//! A relative pose is in region k iff the region's held flag equals g and its classifier's margin is at least zero.
//! Relations of one pair exclude each other: if a pose passes several regions' tests (mixture tails can overlap),
//! the region with the largest margin wins, ties to the smaller k; if it passes none, `_0` holds.
//!
//! A region whose clear relation exists holds one secondary per primary at a time: that is what
//! `clear_<t1>_<t2>_<k>(x)` assumes, and the actions learned with it say so (going to one object
//! leaves the last). Where several secondaries pass one such region of one primary (a base in
//! front of a place setting stands before all its markers; a gripper between two cans), only the
//! one with the largest margin is in it (ties: the first by name); each other one is in its
//! best remaining region, or in `_0`. Without this rule the abstraction would report states the
//! learned actions cannot leave: driving away from one marker deletes "at" that marker only.
//!
//! The atoms depend on the participants' names, types and poses and on what is held, never on
//! the order the participants come in nor on their roles: the build abstracts scenes in the
//! scene's order, the refiner its view of the world in name order, and both must agree on every
//! state, tied ones included.

use std::collections::{BTreeMap, BTreeSet};

use crate::error::AbstractionError;
use crate::instances::{self, Instance};
use crate::relations::{PairVocabulary, Symbol, symbol_name};
use crate::snapshot::{Participant, Pose, Snapshot};

/// The membership test of one region (its held flag is checked by the caller).
pub trait RegionClassifier {
    /// At least zero iff the relative pose is in the region; larger means deeper inside.
    fn margin(&self, relative: &Pose) -> f64;
}

impl<C: RegionClassifier + ?Sized> RegionClassifier for &C {
    fn margin(&self, relative: &Pose) -> f64 {
        (**self).margin(relative)
    }
}

/// A grounded fact over participant indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Fact {
    Relation { pair: usize, region: usize, primary: usize, secondary: usize },
    Clear { pair: usize, region: usize, object: usize },
    Nowhere { pair: usize, region: usize, object: usize },
}

impl Fact {
    pub fn symbol(self) -> Symbol {
        match self {
            Fact::Relation { pair, region, .. } => Symbol::Relation { pair, region },
            Fact::Clear { pair, region, .. } => Symbol::Clear { pair, region },
            Fact::Nowhere { pair, region, .. } => Symbol::Nowhere { pair, region },
        }
    }

    /// The fact of `symbol` about `arguments` (participant indices, in argument order); `None`
    /// when their number is not the symbol's.
    pub fn of(symbol: Symbol, arguments: &[usize]) -> Option<Fact> {
        match (symbol, arguments) {
            (Symbol::Relation { pair, region }, &[primary, secondary]) => {
                Some(Fact::Relation { pair, region, primary, secondary })
            }
            (Symbol::Clear { pair, region }, &[object]) => {
                Some(Fact::Clear { pair, region, object })
            }
            (Symbol::Nowhere { pair, region }, &[object]) => {
                Some(Fact::Nowhere { pair, region, object })
            }
            _ => None,
        }
    }

    /// The participants it is about, in argument order.
    pub fn arguments(self) -> Vec<usize> {
        match self {
            Fact::Relation { primary, secondary, .. } => vec![primary, secondary],
            Fact::Clear { object, .. } | Fact::Nowhere { object, .. } => vec![object],
        }
    }
}

/// A grounded atom with object names: a PDDL init or goal atom.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GroundAtom {
    /// The predicate name.
    pub predicate: String,
    /// The object names.
    pub arguments: Vec<String>,
}

impl std::fmt::Display for GroundAtom {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "({}", self.predicate)?;
        for argument in &self.arguments {
            write!(f, " {argument}")?;
        }
        write!(f, ")")
    }
}

pub fn ground_atom(
    pairs: &[PairVocabulary],
    participants: &[Participant],
    fact: Fact,
) -> GroundAtom {
    named_atom(symbol_name(pairs, fact.symbol()), participants, fact)
}

/// `fact` as the atom of `predicate`, its symbol's name, with the participants' names.
fn named_atom(predicate: String, participants: &[Participant], fact: Fact) -> GroundAtom {
    GroundAtom {
        predicate,
        arguments: fact
            .arguments()
            .into_iter()
            .map(|index| participants[index].name.clone())
            .collect(),
    }
}

/// The regions an instance passes (held flag and margin), deepest first, ties to the smaller k.
fn passed_regions<C: RegionClassifier>(
    vocabulary: &PairVocabulary,
    classifiers: &[C],
    relative: &Pose,
    g: u8,
) -> Vec<(usize, f64)> {
    let mut passed: Vec<(usize, f64)> = classifiers
        .iter()
        .zip(&vocabulary.region_flags)
        .enumerate()
        .filter(|(_, (_, flag))| **flag == g)
        .map(|(index, (classifier, _))| (index + 1, classifier.margin(relative)))
        .filter(|(_, margin)| *margin >= 0.0)
        .collect();
    // Stable: equal margins keep the smaller k first.
    passed.sort_by(|a, b| b.1.total_cmp(&a.1));
    passed
}

/// The region of every instance (0 for none, else k), with one secondary per primary in each
/// region that has a clear relation (see the module's documentation).
fn assign_regions(
    vocabulary: &[PairVocabulary],
    instances: &[Instance],
    participants: &[Participant],
    passed: &mut [Vec<(usize, f64)>],
) -> Vec<usize> {
    loop {
        let best = |index: usize| passed[index].first().copied();
        // The instances whose best region holds one secondary per primary, with that key.
        let contested: Vec<(usize, (usize, usize, usize))> = (0..instances.len())
            .filter_map(|index| {
                let (region, _) = best(index)?;
                let Instance { pair, primary, .. } = instances[index];
                vocabulary[pair].has_clear(region).then_some((index, (pair, primary, region)))
            })
            .collect();
        // The deeper of two instances: the larger margin, ties to the secondary first by name
        // (names are unique), whatever order the participants come in.
        let deeper = |a: usize, b: usize| {
            let margin = |index: usize| best(index).map_or(f64::NEG_INFINITY, |(_, m)| m);
            let name = |index: usize| &participants[instances[index].secondary].name;
            margin(a) > margin(b) || (margin(a) == margin(b) && name(a) < name(b))
        };
        let mut holder: BTreeMap<(usize, usize, usize), usize> = BTreeMap::new();
        for &(index, key) in &contested {
            let held = holder.entry(key).or_insert(index);
            if deeper(index, *held) {
                *held = index;
            }
        }
        let evicted: Vec<usize> = contested
            .iter()
            .filter(|(index, key)| holder[key] != *index)
            .map(|(index, _)| *index)
            .collect();
        if evicted.is_empty() {
            return (0..instances.len()).map(|index| best(index).map_or(0, |(k, _)| k)).collect();
        }
        // Each pass takes at least one region from one instance's list, so this ends.
        for index in evicted {
            passed[index].remove(0);
        }
    }
}

/// Every true fact of a snapshot. `classifiers[p][k − 1]` tests region k of pair p.
pub fn abstract_facts<C: RegionClassifier>(
    vocabulary: &[PairVocabulary],
    classifiers: &[Vec<C>],
    participants: &[Participant],
    snapshot: &Snapshot,
) -> BTreeSet<Fact> {
    // Built from sorted facts in one pass, not fact by fact.
    facts_of_groups(vocabulary, classifiers, participants, snapshot, |_, _| true)
        .into_iter()
        .collect()
}

/// The true facts of a snapshot about the groups `kept(pair, primary)` accepts, exactly as
/// [`abstract_facts`] has them: a group is one primary's instances of one pair, and the regions
/// of its instances depend on nothing else (one secondary per primary and region is decided
/// among them). Relations and clear relations of other groups are left out, and so are a pair's
/// nowhere relations unless all its groups are kept (whether an object is in a region of no
/// primary asks every primary). Sorted; each fact comes once, from its one instance, primary or
/// secondary.
fn facts_of_groups<C: RegionClassifier>(
    vocabulary: &[PairVocabulary],
    classifiers: &[Vec<C>],
    participants: &[Participant],
    snapshot: &Snapshot,
    kept: impl Fn(usize, usize) -> bool,
) -> Vec<Fact> {
    let type_pairs: Vec<_> = vocabulary.iter().map(|v| v.pair.clone()).collect();
    let mut facts = Vec::new();
    let instances: Vec<Instance> = instances::instances(&type_pairs, participants)
        .into_iter()
        .filter(|instance| kept(instance.pair, instance.primary))
        .collect();
    let mut passed: Vec<Vec<(usize, f64)>> = instances
        .iter()
        .map(|&instance| {
            let relative = instances::relative_pose(snapshot, instance);
            let g = instances::held_flag(snapshot, instance);
            passed_regions(&vocabulary[instance.pair], &classifiers[instance.pair], &relative, g)
        })
        .collect();
    let regions = assign_regions(vocabulary, &instances, participants, &mut passed);
    // (pair, region, primary) and (pair, region, secondary) of every instance in a region,
    // sorted for lookups.
    let mut occupied: Vec<(usize, usize, usize)> = Vec::with_capacity(instances.len());
    let mut placed: Vec<(usize, usize, usize)> = Vec::with_capacity(instances.len());
    for (&instance, region) in instances.iter().zip(regions) {
        let Instance { pair, primary, secondary } = instance;
        facts.push(Fact::Relation { pair, region, primary, secondary });
        occupied.push((pair, region, primary));
        placed.push((pair, region, secondary));
    }
    occupied.sort_unstable();
    placed.sort_unstable();
    for (pair, pair_vocabulary) in vocabulary.iter().enumerate() {
        let is_primary =
            |participant: &Participant| participant.type_name == pair_vocabulary.pair.primary;
        let whole_pair = participants
            .iter()
            .enumerate()
            .all(|(object, participant)| !is_primary(participant) || kept(pair, object));
        for (object, participant) in participants.iter().enumerate() {
            for region in 1..=pair_vocabulary.region_count() {
                if is_primary(participant)
                    && kept(pair, object)
                    && pair_vocabulary.has_clear(region)
                    && occupied.binary_search(&(pair, region, object)).is_err()
                {
                    facts.push(Fact::Clear { pair, region, object });
                }
                if whole_pair
                    && participant.type_name == pair_vocabulary.pair.secondary
                    && pair_vocabulary.has_nowhere(region)
                    && placed.binary_search(&(pair, region, object)).is_err()
                {
                    facts.push(Fact::Nowhere { pair, region, object });
                }
            }
        }
    }
    facts.sort_unstable();
    facts
}

/// Refuses a snapshot that does not pose every participant.
fn check_shape(participants: &[Participant], snapshot: &Snapshot) -> Result<(), AbstractionError> {
    if snapshot.poses.len() != participants.len() {
        return Err(AbstractionError::SnapshotShape {
            expected: participants.len(),
            found: snapshot.poses.len(),
        });
    }
    Ok(())
}

/// Whether every atom of `adds` is true in the snapshot and no atom of `deletes` is, as
/// [`abstract_atoms`] would say, with only these atoms named: each is read back as the facts
/// whose symbol has its predicate's name and whose participants have its arguments' names
/// (an atom no fact can name is never true). Only the groups the atoms are about are
/// abstracted (see [`facts_of_groups`]): an action's effects name a few objects of a scene.
pub fn effects_hold<C: RegionClassifier>(
    vocabulary: &[PairVocabulary],
    classifiers: &[Vec<C>],
    participants: &[Participant],
    snapshot: &Snapshot,
    adds: &BTreeSet<GroundAtom>,
    deletes: &BTreeSet<GroundAtom>,
) -> Result<bool, AbstractionError> {
    check_shape(participants, snapshot)?;
    let mut symbols: BTreeMap<String, Vec<Symbol>> = BTreeMap::new();
    for symbol in crate::relations::symbols(vocabulary) {
        symbols.entry(symbol_name(vocabulary, symbol)).or_default().push(symbol);
    }
    // Each atom as the facts that would make it true.
    let named = |atom: &GroundAtom| -> Vec<Fact> {
        let Some(arguments) = atom
            .arguments
            .iter()
            .map(|name| participants.iter().position(|p| &p.name == name))
            .collect::<Option<Vec<usize>>>()
        else {
            return Vec::new();
        };
        symbols
            .get(&atom.predicate)
            .map_or(&[][..], Vec::as_slice)
            .iter()
            .filter_map(|&symbol| Fact::of(symbol, &arguments))
            .collect()
    };
    let adds: Vec<Vec<Fact>> = adds.iter().map(named).collect();
    let deletes: Vec<Vec<Fact>> = deletes.iter().map(named).collect();
    let mut groups: BTreeSet<(usize, usize)> = BTreeSet::new();
    let mut whole_pairs: BTreeSet<usize> = BTreeSet::new();
    for &fact in adds.iter().chain(&deletes).flatten() {
        match fact {
            Fact::Relation { pair, primary, .. } => groups.insert((pair, primary)),
            Fact::Clear { pair, object, .. } => groups.insert((pair, object)),
            Fact::Nowhere { pair, .. } => whole_pairs.insert(pair),
        };
    }
    let facts =
        facts_of_groups(vocabulary, classifiers, participants, snapshot, |pair, primary| {
            whole_pairs.contains(&pair) || groups.contains(&(pair, primary))
        });
    let is_true = |facts_of_atom: &Vec<Fact>| {
        facts_of_atom.iter().any(|fact| facts.binary_search(fact).is_ok())
    };
    Ok(adds.iter().all(is_true) && !deletes.iter().any(is_true))
}

/// Every true atom of a snapshot, with object names; checks the snapshot's shape first.
pub fn abstract_atoms<C: RegionClassifier>(
    vocabulary: &[PairVocabulary],
    classifiers: &[Vec<C>],
    participants: &[Participant],
    snapshot: &Snapshot,
) -> Result<BTreeSet<GroundAtom>, AbstractionError> {
    check_shape(participants, snapshot)?;
    let facts = abstract_facts(vocabulary, classifiers, participants, snapshot);
    // A scene has far more atoms than the vocabulary has symbols, and a refiner abstracts a
    // scene per candidate: each symbol's name is written once.
    let mut names: BTreeMap<Symbol, String> = BTreeMap::new();
    Ok(facts
        .into_iter()
        .map(|fact| {
            let name = names
                .entry(fact.symbol())
                .or_insert_with(|| symbol_name(vocabulary, fact.symbol()));
            named_atom(name.clone(), participants, fact)
        })
        .collect())
}
