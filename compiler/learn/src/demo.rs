//! The learner's input: demonstrations as participants and their world poses per time step.
//!
//! Static world bodies that never move and never relate to anything are simply not participants.

use std::collections::{BTreeMap, BTreeSet};

use crate::error::LearnError;
pub(crate) use lamp_abstraction::{Participant, Pose, Role, Snapshot};

/// One recorded demonstration.
#[derive(Debug, Clone, PartialEq)]
pub struct Demonstration {
    /// A stable identifier, used in provenance.
    pub id: String,
    /// The bodies that take part; snapshots list poses in this order.
    pub participants: Vec<Participant>,
    /// One snapshot per time step, in time order.
    pub steps: Vec<Snapshot>,
}

/// Checks demonstrations and returns the role of every type (the same everywhere).
pub(crate) fn validate(
    demonstrations: &[Demonstration],
) -> Result<BTreeMap<String, Role>, LearnError> {
    if demonstrations.is_empty() {
        return Err(LearnError::NoDemonstrations);
    }
    let mut roles: BTreeMap<String, Role> = BTreeMap::new();
    for demonstration in demonstrations {
        let mut names = BTreeSet::new();
        for participant in &demonstration.participants {
            check_name(&participant.name)?;
            check_name(&participant.type_name)?;
            if !names.insert(participant.name.as_str()) {
                return Err(LearnError::DuplicateParticipant {
                    demonstration: demonstration.id.clone(),
                    name: participant.name.clone(),
                });
            }
            let role = *roles.entry(participant.type_name.clone()).or_insert(participant.role);
            if role != participant.role {
                return Err(LearnError::ConflictingRole {
                    type_name: participant.type_name.clone(),
                    first: role.describe().to_string(),
                    second: participant.role.describe().to_string(),
                });
            }
        }
        for (step, snapshot) in demonstration.steps.iter().enumerate() {
            validate_snapshot(demonstration, step, snapshot)?;
        }
    }
    Ok(roles)
}

fn validate_snapshot(
    demonstration: &Demonstration,
    step: usize,
    snapshot: &Snapshot,
) -> Result<(), LearnError> {
    let participants = &demonstration.participants;
    if snapshot.poses.len() != participants.len() {
        return Err(LearnError::PoseCount {
            demonstration: demonstration.id.clone(),
            step,
            expected: participants.len(),
            found: snapshot.poses.len(),
        });
    }
    for (pose, participant) in snapshot.poses.iter().zip(participants) {
        let finite = pose
            .translation
            .vector
            .iter()
            .chain(pose.rotation.coords.iter())
            .all(|v| v.is_finite());
        if !finite {
            return Err(LearnError::NonFinitePose {
                demonstration: demonstration.id.clone(),
                step,
                participant: participant.name.clone(),
            });
        }
    }
    for &(gripper, held) in &snapshot.held {
        let (Some(holder), Some(object)) = (participants.get(gripper), participants.get(held))
        else {
            return Err(LearnError::HeldOutOfRange {
                demonstration: demonstration.id.clone(),
                step,
                gripper,
                held,
            });
        };
        let can_hold = holder.role == Role::RobotPart { gripper: true };
        let can_be_held = object.role == Role::Object { movable: true };
        if !can_hold || !can_be_held {
            return Err(LearnError::BadHeld {
                demonstration: demonstration.id.clone(),
                step,
                gripper: holder.name.clone(),
                held: object.name.clone(),
            });
        }
    }
    Ok(())
}

/// Names become PDDL identifiers and parts of predicate names, so they are kept simple.
pub(crate) fn check_name(name: &str) -> Result<(), LearnError> {
    let mut chars = name.chars();
    let starts_with_letter = chars.next().is_some_and(|c| c.is_ascii_alphabetic());
    let rest_ok = chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if starts_with_letter && rest_ok {
        Ok(())
    } else {
        Err(LearnError::BadName { name: name.to_string() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn demo(held: Vec<(usize, usize)>) -> Demonstration {
        Demonstration {
            id: "d".into(),
            participants: vec![
                Participant {
                    name: "g".into(),
                    type_name: "gripper".into(),
                    role: Role::RobotPart { gripper: true },
                },
                Participant {
                    name: "c".into(),
                    type_name: "can".into(),
                    role: Role::Object { movable: true },
                },
            ],
            steps: vec![Snapshot { poses: vec![Pose::identity(); 2], held }],
        }
    }

    #[test]
    fn valid_demonstration_reports_roles() {
        let roles = validate(&[demo(vec![(0, 1)])]).expect("valid");
        assert_eq!(roles["can"], Role::Object { movable: true });
    }

    #[test]
    fn objects_cannot_hold_and_indices_are_checked() {
        assert!(matches!(validate(&[demo(vec![(1, 0)])]), Err(LearnError::BadHeld { .. })));
        assert!(matches!(validate(&[demo(vec![(0, 7)])]), Err(LearnError::HeldOutOfRange { .. })));
        assert_eq!(validate(&[]), Err(LearnError::NoDemonstrations));
    }

    #[test]
    fn pose_count_and_names_are_checked() {
        let mut short = demo(vec![]);
        short.steps[0].poses.pop();
        assert!(matches!(validate(&[short]), Err(LearnError::PoseCount { .. })));
        let mut bad = demo(vec![]);
        bad.participants[0].name = "1g".into();
        assert!(matches!(validate(&[bad]), Err(LearnError::BadName { .. })));
    }

    #[test]
    fn a_type_keeps_one_role() {
        let mut other = demo(vec![]);
        other.participants[1].role = Role::Object { movable: false };
        assert!(matches!(
            validate(&[demo(vec![]), other]),
            Err(LearnError::ConflictingRole { .. })
        ));
    }
}
