//! Which ordered type pairs are related, which participant pairs instantiate them, and their relative poses.
//!
//! The primary of a pair is chosen by role (robot part, then static object, then movable object), ties by type name.
//! Same-type pairs relate every ordered pair of distinct participants, so "b on a" and "a on b" are different facts.
//! Pairs of two static types are skipped: their relative pose never changes, so it cannot drive an action.

use std::collections::BTreeMap;

use crate::config::{LearnConfig, TypePair};
use crate::demo::{Participant, Pose, Role, Snapshot};

/// The ordered type pairs to learn, sorted by (primary, secondary).
pub(crate) fn type_pairs(roles: &BTreeMap<String, Role>, config: &LearnConfig) -> Vec<TypePair> {
    let mut pairs = Vec::new();
    for (first, first_role) in roles {
        for (second, second_role) in roles {
            let both_static = *first_role == Role::Object { movable: false }
                && *second_role == Role::Object { movable: false };
            if both_static || !is_primary_first((first, *first_role), (second, *second_role)) {
                continue;
            }
            let pair = TypePair::new(first.clone(), second.clone());
            if !config.is_ignored(&pair) {
                pairs.push(pair);
            }
        }
    }
    pairs.sort();
    pairs
}

/// Whether `first` is the primary of the pair {first, second} (true for a type paired with itself).
fn is_primary_first(first: (&str, Role), second: (&str, Role)) -> bool {
    (first.1.primary_rank(), first.0) <= (second.1.primary_rank(), second.0)
}

/// One ordered pair of participants instantiating a type pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Instance {
    /// Index of the type pair in the learner's pair list.
    pub pair: usize,
    /// Participant index of the primary.
    pub primary: usize,
    /// Participant index of the secondary.
    pub secondary: usize,
}

/// Every participant pair of every learned type pair, sorted by (pair, primary, secondary).
pub(crate) fn instances(pairs: &[TypePair], participants: &[Participant]) -> Vec<Instance> {
    let mut found = Vec::new();
    for (pair_index, pair) in pairs.iter().enumerate() {
        for (primary, a) in participants.iter().enumerate() {
            for (secondary, b) in participants.iter().enumerate() {
                if primary != secondary
                    && a.type_name == pair.primary
                    && b.type_name == pair.secondary
                {
                    found.push(Instance { pair: pair_index, primary, secondary });
                }
            }
        }
    }
    found
}

/// The pose of the secondary in the primary's frame, `primary⁻¹ · secondary`.
pub(crate) fn relative_pose(snapshot: &Snapshot, instance: Instance) -> Pose {
    snapshot.poses[instance.primary].inv_mul(&snapshot.poses[instance.secondary])
}

/// The held flag g: 1 iff the primary is a gripper that holds the secondary in this snapshot.
pub(crate) fn held_flag(snapshot: &Snapshot, instance: Instance) -> u8 {
    u8::from(snapshot.held.contains(&(instance.primary, instance.secondary)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    fn roles() -> BTreeMap<String, Role> {
        BTreeMap::from([
            ("gripper".to_string(), Role::RobotPart { gripper: true }),
            ("can".to_string(), Role::Object { movable: true }),
            ("surface".to_string(), Role::Object { movable: false }),
            ("table".to_string(), Role::Object { movable: false }),
        ])
    }

    #[test]
    fn robot_parts_then_static_then_movable_are_primary() {
        let pairs = type_pairs(&roles(), &LearnConfig::default());
        let names: Vec<String> = pairs.iter().map(TypePair::stem).collect();
        assert_eq!(
            names,
            [
                "can_can",
                "gripper_can",
                "gripper_gripper",
                "gripper_surface",
                "gripper_table",
                "surface_can",
                "table_can"
            ]
        );
    }

    #[test]
    fn ignored_pairs_are_left_out_in_either_order() {
        let mut config = LearnConfig::default();
        config.ignored.insert(TypePair::new("can", "table"));
        let pairs = type_pairs(&roles(), &config);
        assert!(!pairs.contains(&TypePair::new("table", "can")));
    }

    #[test]
    fn same_type_pairs_use_both_orders_and_never_self() {
        let can = |name: &str| Participant {
            name: name.into(),
            type_name: "can".into(),
            role: Role::Object { movable: true },
        };
        let pairs = vec![TypePair::new("can", "can")];
        let found = instances(&pairs, &[can("a"), can("b"), can("c")]);
        assert_eq!(found.len(), 6);
        assert!(found.iter().all(|i| i.primary != i.secondary));
    }

    #[test]
    fn relative_pose_is_secondary_in_primary_frame() {
        let a = Pose::from_parts(
            Translation3::new(1.0, 0.0, 0.0),
            UnitQuaternion::from_euler_angles(0.0, 0.0, 1.0),
        );
        let b = Pose::translation(1.0, 1.0, 0.0);
        let snapshot = Snapshot { poses: vec![a, b], held: vec![(0, 1)] };
        let instance = Instance { pair: 0, primary: 0, secondary: 1 };
        let relative = relative_pose(&snapshot, instance);
        approx::assert_relative_eq!(a * relative, b, epsilon = 1e-12);
        assert_eq!(held_flag(&snapshot, instance), 1);
        assert_eq!(held_flag(&snapshot, Instance { pair: 0, primary: 1, secondary: 0 }), 0);
    }
}
