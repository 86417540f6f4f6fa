//! Abstraction: a low-level snapshot becomes the set of true facts of the vocabulary.
//!
//! A relative pose is in region k iff the region's held flag equals g and its classifier's margin is at least zero.
//! Relations of one pair exclude each other: if a pose passes several regions' tests (mixture tails can overlap),
//! the region with the largest margin wins, ties to the smaller k; if it passes none, `_0` holds.

use std::collections::BTreeSet;

use crate::demo::{Participant, Pose, Snapshot};
use crate::discretise::Grid;
use crate::error::LearnError;
use crate::pairs::{self, Instance};
use crate::regions::RegionCells;
use crate::relations::{PairVocabulary, Symbol, symbol_name};

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

/// The exact-cell membership test: a pose is in the region iff its (voxel, rotation) cell is.
///
/// This is the reference code's shortcut; the learner itself uses mixtures, this serves tests and comparisons.
#[derive(Debug, Clone)]
pub struct CellClassifier {
    /// The pair's grid.
    pub grid: Grid,
    /// The region's cells.
    pub cells: RegionCells,
}

impl RegionClassifier for CellClassifier {
    fn margin(&self, relative: &Pose) -> f64 {
        let inside = self.grid.voxel(relative).is_some_and(|voxel| {
            self.cells.contains(self.cells.g, voxel, self.grid.rotation_cell(relative))
        });
        if inside { 0.0 } else { -1.0 }
    }
}

/// A grounded fact over participant indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Fact {
    Relation { pair: usize, region: usize, primary: usize, secondary: usize },
    Clear { pair: usize, region: usize, object: usize },
    Nowhere { pair: usize, region: usize, object: usize },
}

impl Fact {
    pub(crate) fn symbol(self) -> Symbol {
        match self {
            Fact::Relation { pair, region, .. } => Symbol::Relation { pair, region },
            Fact::Clear { pair, region, .. } => Symbol::Clear { pair, region },
            Fact::Nowhere { pair, region, .. } => Symbol::Nowhere { pair, region },
        }
    }

    /// The participants it is about, in argument order.
    pub(crate) fn arguments(self) -> Vec<usize> {
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

pub(crate) fn ground_atom(
    pairs: &[PairVocabulary],
    participants: &[Participant],
    fact: Fact,
) -> GroundAtom {
    GroundAtom {
        predicate: symbol_name(pairs, fact.symbol()),
        arguments: fact
            .arguments()
            .into_iter()
            .map(|index| participants[index].name.clone())
            .collect(),
    }
}

/// The region of one instance: 0 for none, else k.
fn region_of<C: RegionClassifier>(
    vocabulary: &PairVocabulary,
    classifiers: &[C],
    relative: &Pose,
    g: u8,
) -> usize {
    let mut best: Option<(usize, f64)> = None;
    for (index, (classifier, flag)) in classifiers.iter().zip(&vocabulary.region_flags).enumerate()
    {
        if *flag != g {
            continue;
        }
        let margin = classifier.margin(relative);
        if margin >= 0.0 && best.is_none_or(|(_, best_margin)| margin > best_margin) {
            best = Some((index + 1, margin));
        }
    }
    best.map_or(0, |(region, _)| region)
}

/// Every true fact of a snapshot. `classifiers[p][k − 1]` tests region k of pair p.
pub(crate) fn abstract_facts<C: RegionClassifier>(
    vocabulary: &[PairVocabulary],
    classifiers: &[Vec<C>],
    participants: &[Participant],
    snapshot: &Snapshot,
) -> BTreeSet<Fact> {
    let type_pairs: Vec<_> = vocabulary.iter().map(|v| v.pair.clone()).collect();
    let mut facts = BTreeSet::new();
    // (pair, region, primary) and (pair, region, secondary) of every instance in a region.
    let mut occupied: BTreeSet<(usize, usize, usize)> = BTreeSet::new();
    let mut placed: BTreeSet<(usize, usize, usize)> = BTreeSet::new();
    for instance in pairs::instances(&type_pairs, participants) {
        let Instance { pair, primary, secondary } = instance;
        let relative = pairs::relative_pose(snapshot, instance);
        let g = pairs::held_flag(snapshot, instance);
        let region = region_of(&vocabulary[pair], &classifiers[pair], &relative, g);
        facts.insert(Fact::Relation { pair, region, primary, secondary });
        occupied.insert((pair, region, primary));
        placed.insert((pair, region, secondary));
    }
    for (pair, pair_vocabulary) in vocabulary.iter().enumerate() {
        for (object, participant) in participants.iter().enumerate() {
            for region in 1..=pair_vocabulary.region_count() {
                if participant.type_name == pair_vocabulary.pair.primary
                    && pair_vocabulary.has_clear(region)
                    && !occupied.contains(&(pair, region, object))
                {
                    facts.insert(Fact::Clear { pair, region, object });
                }
                if participant.type_name == pair_vocabulary.pair.secondary
                    && pair_vocabulary.has_nowhere(region)
                    && !placed.contains(&(pair, region, object))
                {
                    facts.insert(Fact::Nowhere { pair, region, object });
                }
            }
        }
    }
    facts
}

/// Every true atom of a snapshot, with object names; checks the snapshot's shape first.
pub(crate) fn abstract_atoms<C: RegionClassifier>(
    vocabulary: &[PairVocabulary],
    classifiers: &[Vec<C>],
    participants: &[Participant],
    snapshot: &Snapshot,
) -> Result<BTreeSet<GroundAtom>, LearnError> {
    if snapshot.poses.len() != participants.len() {
        return Err(LearnError::SnapshotShape {
            expected: participants.len(),
            found: snapshot.poses.len(),
        });
    }
    let facts = abstract_facts(vocabulary, classifiers, participants, snapshot);
    Ok(facts.into_iter().map(|fact| ground_atom(vocabulary, participants, fact)).collect())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::config::TypePair;
    use crate::demo::Role;

    /// A classifier that accepts poses within a radius of a point, with margin growing toward it.
    pub(crate) struct Ball {
        pub centre: [f64; 3],
        pub radius: f64,
    }

    impl RegionClassifier for Ball {
        fn margin(&self, relative: &Pose) -> f64 {
            let centre = nalgebra::Vector3::from(self.centre);
            self.radius - (relative.translation.vector - centre).norm()
        }
    }

    pub(crate) fn participants() -> Vec<Participant> {
        vec![
            Participant {
                name: "g".into(),
                type_name: "gripper".into(),
                role: Role::RobotPart { gripper: true },
            },
            Participant {
                name: "c1".into(),
                type_name: "can".into(),
                role: Role::Object { movable: true },
            },
            Participant {
                name: "c2".into(),
                type_name: "can".into(),
                role: Role::Object { movable: true },
            },
        ]
    }

    fn vocabulary() -> Vec<PairVocabulary> {
        vec![PairVocabulary {
            pair: TypePair::new("gripper", "can"),
            region_flags: vec![0, 0, 1],
            clear: vec![true; 3],
            nowhere: vec![false, true, true],
        }]
    }

    fn classifiers() -> Vec<Vec<Ball>> {
        vec![vec![
            Ball { centre: [0.0, 0.0, -0.2], radius: 0.05 },
            Ball { centre: [0.0, 0.0, -0.25], radius: 0.05 },
            Ball { centre: [0.0, 0.0, -0.2], radius: 0.05 },
        ]]
    }

    fn names(facts: &BTreeSet<Fact>) -> Vec<String> {
        facts.iter().map(|f| ground_atom(&vocabulary(), &participants(), *f).to_string()).collect()
    }

    #[test]
    fn held_flag_selects_the_slice_and_overlaps_go_to_the_largest_margin() {
        let snapshot = Snapshot {
            poses: vec![
                Pose::identity(),
                Pose::translation(0.0, 0.0, -0.21),
                Pose::translation(0.0, 0.0, -0.24),
            ],
            held: vec![(0, 1)],
        };
        let facts = abstract_facts(&vocabulary(), &classifiers(), &participants(), &snapshot);
        assert_eq!(
            names(&facts),
            [
                "(gripper_can_2 g c2)",
                "(gripper_can_3 g c1)",
                "(clear_gripper_can_1 g)",
                "(nowhere_gripper_can_2 c1)",
                "(nowhere_gripper_can_3 c2)"
            ]
        );
    }

    #[test]
    fn far_objects_are_in_no_region_and_every_region_is_clear() {
        let snapshot = Snapshot {
            poses: vec![
                Pose::identity(),
                Pose::translation(1.0, 0.0, 0.0),
                Pose::translation(0.0, 1.0, 0.0),
            ],
            held: vec![],
        };
        let facts = abstract_facts(&vocabulary(), &classifiers(), &participants(), &snapshot);
        assert_eq!(
            names(&facts),
            [
                "(gripper_can_0 g c1)",
                "(gripper_can_0 g c2)",
                "(clear_gripper_can_1 g)",
                "(clear_gripper_can_2 g)",
                "(clear_gripper_can_3 g)",
                "(nowhere_gripper_can_2 c1)",
                "(nowhere_gripper_can_2 c2)",
                "(nowhere_gripper_can_3 c1)",
                "(nowhere_gripper_can_3 c2)"
            ]
        );
    }
}
