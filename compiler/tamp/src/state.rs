//! The solver's view of a scene: the plugin contract's world state, and the learned abstraction.

use std::collections::BTreeSet;

use lamp_abstraction::{GroundAtom, SamplerArtifact};
use lamp_participants::{ParticipantMap, part_participant_name, scene_snapshot};
use lamp_plugin_api::{HeldObject, ObjectState, RobotPart, RobotState, WorldState};
use lamp_world::Scene;

use crate::error::SolveError;
use crate::poses::to_wire;

/// The world state a refiner sees: every robot with its parts and what it holds, every body that
/// is not the static world.
pub fn world_state(participants: &ParticipantMap, scene: &Scene) -> Result<WorldState, SolveError> {
    let mut robots = Vec::new();
    for robot in scene.robots() {
        let model = robot.robot();
        let parts = participants
            .robot_parts(&robot.name)
            .ok_or_else(|| SolveError::internal(format!("robot `{}` has no parts", robot.name)))?;
        let mut held = Vec::new();
        if let Some(gripper) = robot.gripper()
            && let Some(grasp) = gripper.held
        {
            held.push(HeldObject {
                object: scene.bodies()[grasp.body].name.clone(),
                link: model.link_name(gripper.link).to_string(),
                grasp: to_wire(&grasp.grasp),
            });
        }
        robots.push(RobotState {
            name: robot.name.clone(),
            configuration: robot.configuration().to_vec(),
            held,
            parts: parts
                .parts
                .iter()
                .map(|part| RobotPart {
                    object: part_participant_name(&robot.name, &part.type_name),
                    object_type: part.type_name.clone(),
                    link: model.link_name(part.link).to_string(),
                    gripper: part.gripper,
                })
                .collect(),
        });
    }
    robots.sort_by(|a, b| a.name.cmp(&b.name));
    let mut objects: Vec<ObjectState> = scene
        .bodies()
        .iter()
        .enumerate()
        .filter(|(_, body)| !body.world)
        .map(|(index, body)| ObjectState {
            name: body.name.clone(),
            object_type: body.type_name.clone(),
            pose: to_wire(&scene.body_pose(index)),
        })
        .collect();
    objects.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(WorldState { robots, objects })
}

/// The learned abstraction of a scene.
pub fn abstraction(
    artifact: &SamplerArtifact,
    map: &ParticipantMap,
    scene: &Scene,
) -> Result<BTreeSet<GroundAtom>, SolveError> {
    let (participants, snapshot) = scene_snapshot(map, scene).map_err(SolveError::internal)?;
    artifact
        .abstract_state(&participants, &snapshot)
        .map_err(|error| SolveError::internal(format!("abstracting a state: {error}")))
}
