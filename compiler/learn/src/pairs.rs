//! Which ordered type pairs are related, which participant pairs instantiate them, and their relative poses.
//!
//! The primary of a pair is chosen by role (robot part, then static object, then movable object), ties by type name.
//! Same-type pairs relate every ordered pair of distinct participants, so "b on a" and "a on b" are different facts.
//! Pairs of two static types are skipped: their relative pose never changes, so it cannot drive an action.

use std::collections::BTreeMap;

use crate::config::{LearnConfig, TypePair};
use crate::demo::Role;
pub(crate) use lamp_abstraction::instances::{held_flag, instances, relative_pose};

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

#[cfg(test)]
mod tests {
    use super::*;

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
}
