//! The exact-cell membership test, and the tests of the abstraction (which lamp-abstraction
//! carries out) on hand-made classifiers.

use crate::demo::Pose;
use crate::discretise::Grid;
use crate::regions::RegionCells;
pub(crate) use lamp_abstraction::abstraction::{Fact, abstract_atoms, abstract_facts};
pub(crate) use lamp_abstraction::abstraction::{GroundAtom, RegionClassifier};

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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::config::TypePair;
    use crate::demo::{Participant, Role, Snapshot};
    use crate::relations::PairVocabulary;
    use lamp_abstraction::abstraction::ground_atom;
    use std::collections::BTreeSet;

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

    fn both_near(offset: f64) -> Snapshot {
        // Both cans pass region 1 (centred 0.2 m below the gripper, 5 cm radius); c2 also passes
        // region 2 (centred 0.25 m below) when it is low enough.
        Snapshot {
            poses: vec![
                Pose::identity(),
                Pose::translation(0.0, 0.0, -0.2),
                Pose::translation(0.0, 0.0, -0.2 - offset),
            ],
            held: vec![],
        }
    }

    #[test]
    fn a_region_with_a_clear_relation_holds_the_deepest_secondary_only() {
        // c2 at 0.18 m passes region 1 only, less deep than c1 at its centre: c1 holds it, c2 is
        // in no region.
        let facts =
            abstract_facts(&vocabulary(), &classifiers(), &participants(), &both_near(-0.02));
        let names = names(&facts);
        assert!(names.contains(&"(gripper_can_1 g c1)".to_string()), "{names:?}");
        assert!(names.contains(&"(gripper_can_0 g c2)".to_string()), "{names:?}");
        assert!(!names.contains(&"(clear_gripper_can_1 g)".to_string()), "{names:?}");
    }

    #[test]
    fn an_evicted_secondary_falls_back_to_its_next_region() {
        // c2 at 0.22 m passes region 1 (2 cm from its centre) and region 2 (3 cm): region 1 is its
        // deepest, but c1 sits at region 1's centre and holds it, so c2 is in region 2.
        let facts =
            abstract_facts(&vocabulary(), &classifiers(), &participants(), &both_near(0.02));
        let names = names(&facts);
        assert!(names.contains(&"(gripper_can_1 g c1)".to_string()), "{names:?}");
        assert!(names.contains(&"(gripper_can_2 g c2)".to_string()), "{names:?}");
    }

    /// Both cans exactly at region 1's centre: a tie, which goes to the can first by name.
    fn tied() -> Snapshot {
        Snapshot {
            poses: vec![
                Pose::identity(),
                Pose::translation(0.0, 0.0, -0.2),
                Pose::translation(0.0, 0.0, -0.2),
            ],
            held: vec![],
        }
    }

    /// The atoms of `snapshot` with the participants (and the snapshot's rows) in the order of
    /// `order`, with every object's role replaced by `role`.
    fn atoms_in_order(
        snapshot: &Snapshot,
        order: &[usize],
        role: Option<Role>,
    ) -> BTreeSet<GroundAtom> {
        let all = participants();
        let participants: Vec<Participant> = order
            .iter()
            .map(|&index| {
                let participant = all[index].clone();
                match (role, participant.role) {
                    (Some(role), Role::Object { .. }) => Participant { role, ..participant },
                    _ => participant,
                }
            })
            .collect();
        let position = |index: usize| order.iter().position(|&i| i == index).expect("permuted");
        let permuted = Snapshot {
            poses: order.iter().map(|&index| snapshot.poses[index]).collect(),
            held: snapshot.held.iter().map(|&(a, b)| (position(a), position(b))).collect(),
        };
        abstract_atoms(&vocabulary(), &classifiers(), &participants, &permuted).expect("fits")
    }

    #[test]
    fn the_atoms_of_a_tied_state_depend_on_names_never_on_order_or_roles() {
        let orders = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
        let expected = atoms_in_order(&tied(), &[0, 1, 2], None);
        let texts: Vec<String> = expected.iter().map(ToString::to_string).collect();
        assert!(texts.contains(&"(gripper_can_1 g c1)".to_string()), "{texts:?}");
        assert!(!texts.contains(&"(gripper_can_1 g c2)".to_string()), "{texts:?}");
        for order in orders {
            for role in [None, Some(Role::Object { movable: false })] {
                assert_eq!(atoms_in_order(&tied(), &order, role), expected, "{order:?} {role:?}");
            }
        }
        let held = Snapshot { held: vec![(0, 2)], ..tied() };
        let expected = atoms_in_order(&held, &[0, 1, 2], None);
        for order in orders {
            assert_eq!(atoms_in_order(&held, &order, None), expected, "{order:?}");
        }
    }

    #[test]
    fn asked_about_one_atom_the_abstraction_answers_as_the_whole_state_does() {
        use lamp_abstraction::abstraction::effects_hold;
        use lamp_abstraction::relations::{symbol_name, symbols};
        // A second gripper, g2, for which c2 and c1 contest region 1 while g's regions are
        // decided among g's own instances: asking about one gripper's atoms must not change them.
        let mut participants = participants();
        participants.push(Participant {
            name: "g2".into(),
            type_name: "gripper".into(),
            role: Role::RobotPart { gripper: true },
        });
        let scenes = [both_near(-0.02), both_near(0.02), tied()].map(|mut snapshot| {
            snapshot.poses.push(Pose::translation(0.0, 0.0, 0.005));
            snapshot
        });
        let (mut true_answers, mut false_answers) = (0, 0);
        for snapshot in &scenes {
            let state = abstract_atoms(&vocabulary(), &classifiers(), &participants, snapshot)
                .expect("fits");
            let names: Vec<&str> = participants.iter().map(|p| p.name.as_str()).collect();
            for symbol in symbols(&vocabulary()) {
                let predicate = symbol_name(&vocabulary(), symbol);
                for first in &names {
                    for second in [None].into_iter().chain(names.iter().map(Some)) {
                        let arguments: Vec<String> = [Some(first), second]
                            .into_iter()
                            .flatten()
                            .map(|n| n.to_string())
                            .collect();
                        let atom = GroundAtom { predicate: predicate.clone(), arguments };
                        let one: BTreeSet<GroundAtom> = [atom.clone()].into();
                        let none = BTreeSet::new();
                        let holds =
                            |adds: &BTreeSet<GroundAtom>, deletes: &BTreeSet<GroundAtom>| {
                                effects_hold(
                                    &vocabulary(),
                                    &classifiers(),
                                    &participants,
                                    snapshot,
                                    adds,
                                    deletes,
                                )
                                .expect("fits")
                            };
                        let is_true = state.contains(&atom);
                        assert_eq!(holds(&one, &none), is_true, "{atom}");
                        assert_eq!(holds(&none, &one), !is_true, "{atom}");
                        if is_true { true_answers += 1 } else { false_answers += 1 }
                    }
                }
            }
        }
        assert!(
            true_answers > 20 && false_answers > 20,
            "{true_answers} true, {false_answers} false"
        );
    }

    #[test]
    fn a_region_without_a_clear_relation_holds_every_secondary_that_passes() {
        let mut vocabulary = vocabulary();
        vocabulary[0].clear = vec![false; 3];
        let facts = abstract_facts(&vocabulary, &classifiers(), &participants(), &both_near(-0.02));
        let atoms: Vec<String> = facts
            .iter()
            .map(|f| ground_atom(&vocabulary, &participants(), *f).to_string())
            .collect();
        assert!(atoms.contains(&"(gripper_can_1 g c1)".to_string()), "{atoms:?}");
        assert!(atoms.contains(&"(gripper_can_1 g c2)".to_string()), "{atoms:?}");
    }
}
