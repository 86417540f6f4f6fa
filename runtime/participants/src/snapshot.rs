//! A scene as the learner sees it: the participants (robot parts named `<robot>_<part type>`,
//! then every body that is not the static world) and their snapshot (part poses by forward
//! kinematics, body poses as placed, which gripper part holds which body).
//!
//! Problem initial states are abstracted from this, and so is every state the solver reaches, so
//! the two always agree on names and order.

use lamp_abstraction::{Participant, Role, Snapshot};
use lamp_world::Scene;

use crate::map::ParticipantMap;

/// The participants of `scene` and their snapshot; `Err` names a robot the spec does not declare.
pub fn scene_snapshot(
    map: &ParticipantMap,
    scene: &Scene,
) -> Result<(Vec<Participant>, Snapshot), String> {
    let mut participants = Vec::new();
    let mut poses = Vec::new();
    // (gripper participant, scene body) pairs, mapped once every body has its participant index.
    let mut holds = Vec::new();
    for robot in scene.robots() {
        let parts = map
            .robot_parts(&robot.name)
            .ok_or_else(|| format!("robot `{}` is not declared", robot.name))?;
        let first = participants.len();
        participants.extend(parts.participants(&robot.name));
        let mut links = vec![lamp_abstraction::Pose::identity(); robot.robot().link_count()];
        parts.part_poses(robot.configuration(), &mut links, &mut poses);
        if let Some(gripper) = robot.gripper()
            && let Some(held) = gripper.held
            && let Some(part) =
                parts.parts.iter().position(|part| part.type_name == gripper.part_type)
        {
            holds.push((first + part, held.body));
        }
    }
    let mut body_participants = Vec::new();
    for (index, body) in scene.bodies().iter().enumerate() {
        if body.world {
            body_participants.push(None);
            continue;
        }
        body_participants.push(Some(participants.len()));
        participants.push(Participant {
            name: body.name.clone(),
            type_name: body.type_name.clone(),
            role: Role::Object { movable: body.movable },
        });
        poses.push(scene.body_pose(index));
    }
    let held = holds
        .into_iter()
        .filter_map(|(gripper, body)| {
            body_participants.get(body).copied().flatten().map(|object| (gripper, object))
        })
        .collect();
    Ok((participants, Snapshot { poses, held }))
}
