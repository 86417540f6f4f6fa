//! Which participant pairs instantiate the learned type pairs, and their relative poses.
//!
//! Same-type pairs relate every ordered pair of distinct participants, so "b on a" and "a on b"
//! are different facts.

use crate::snapshot::{Participant, Pose, Snapshot};
use crate::type_pair::TypePair;

/// One ordered pair of participants instantiating a type pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Instance {
    /// Index of the type pair in the learner's pair list.
    pub pair: usize,
    /// Participant index of the primary.
    pub primary: usize,
    /// Participant index of the secondary.
    pub secondary: usize,
}

/// Every participant pair of every learned type pair, sorted by (pair, primary, secondary).
pub fn instances(pairs: &[TypePair], participants: &[Participant]) -> Vec<Instance> {
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
pub fn relative_pose(snapshot: &Snapshot, instance: Instance) -> Pose {
    snapshot.poses[instance.primary].inv_mul(&snapshot.poses[instance.secondary])
}

/// The held flag g: 1 iff the primary is a gripper that holds the secondary in this snapshot.
pub fn held_flag(snapshot: &Snapshot, instance: Instance) -> u8 {
    u8::from(snapshot.held.contains(&(instance.primary, instance.secondary)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::snapshot::Role;
    use nalgebra::{Translation3, UnitQuaternion};

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
