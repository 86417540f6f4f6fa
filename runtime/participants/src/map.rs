//! Which links of a spec's robots and which of its object types take part in relations, and
//! under which names.
//!
//! A robot part's participant is named `<robot>_<part type>`; a body's is the body's own name.

use std::collections::BTreeMap;
use std::sync::Arc;

use lamp_abstraction::{Participant, Pose, Role};
use lamp_robot::{LinkId, Robot};
use lamp_spec::{Mobility, Spec};
use lamp_world::WorldError;

/// The participant name of a robot part.
pub fn part_participant_name(robot: &str, part_type: &str) -> String {
    format!("{robot}_{part_type}")
}

/// A spec's robots with the links of their parts, and its object types with their roles.
#[derive(Debug, Clone)]
pub struct ParticipantMap {
    robots: BTreeMap<String, RobotParts>,
    /// Object type → `None` for the static world, else whether it is movable.
    types: BTreeMap<String, Option<bool>>,
}

/// A spec robot with the links of its parts.
#[derive(Debug, Clone)]
pub struct RobotParts {
    model: Arc<Robot>,
    /// In spec part order.
    pub parts: Vec<Part>,
}

/// A robot link that takes part in relations.
#[derive(Debug, Clone)]
pub struct Part {
    /// The part's type (and the suffix of its participant name).
    pub type_name: String,
    /// Its link in the robot model.
    pub link: LinkId,
    /// Whether it is the robot's gripper.
    pub gripper: bool,
}

impl ParticipantMap {
    /// The map of `spec`, with the robot models loaded from it (`lamp_world::SpecWorld::robots`).
    pub fn new(spec: &Spec, models: &BTreeMap<String, Arc<Robot>>) -> Result<Self, WorldError> {
        let mut robots = BTreeMap::new();
        for robot in &spec.robots {
            let model = models.get(&robot.name).ok_or_else(|| WorldError::UnknownName {
                what: "robot model",
                name: robot.name.clone(),
            })?;
            robots.insert(robot.name.clone(), RobotParts::new(robot, model)?);
        }
        let types = spec
            .object_types
            .iter()
            .map(|ty| {
                let role = (!ty.world).then_some(ty.mobility == Mobility::Movable);
                (ty.name.clone(), role)
            })
            .collect();
        Ok(ParticipantMap { robots, types })
    }

    /// The parts of a spec robot.
    pub fn robot_parts(&self, robot: &str) -> Option<&RobotParts> {
        self.robots.get(robot)
    }

    /// The role of a spec object type: `None` when the spec does not declare it, `Some(None)` for
    /// the static world (no participant), else `Some(Some(movable))`.
    pub fn object_role(&self, type_name: &str) -> Option<Option<bool>> {
        self.types.get(type_name).copied()
    }
}

impl RobotParts {
    /// The robot's parts of a spec robot whose model is loaded.
    fn new(spec_robot: &lamp_spec::Robot, model: &Arc<Robot>) -> Result<Self, WorldError> {
        let gripper_type = spec_robot.gripper_part().map(|part| part.type_name.as_str());
        let parts = spec_robot
            .parts
            .iter()
            .map(|part| {
                let link = model.link_id(&part.link).ok_or_else(|| WorldError::UnknownName {
                    what: "link",
                    name: format!("{}/{} (part `{}`)", spec_robot.name, part.link, part.type_name),
                })?;
                Ok(Part {
                    type_name: part.type_name.clone(),
                    link,
                    gripper: Some(part.type_name.as_str()) == gripper_type,
                })
            })
            .collect::<Result<Vec<_>, WorldError>>()?;
        Ok(RobotParts { model: Arc::clone(model), parts })
    }

    /// The robot's model.
    pub fn model(&self) -> &Robot {
        &self.model
    }

    /// The participants of this robot's parts.
    pub fn participants(&self, robot: &str) -> Vec<Participant> {
        self.parts
            .iter()
            .map(|part| Participant {
                name: part_participant_name(robot, &part.type_name),
                type_name: part.type_name.clone(),
                role: Role::RobotPart { gripper: part.gripper },
            })
            .collect()
    }

    /// World poses of the parts' links at configuration `q`, using `links` as scratch space.
    pub fn part_poses(&self, q: &[f64], links: &mut [Pose], out: &mut Vec<Pose>) {
        self.model.forward_kinematics(q, links);
        out.extend(self.parts.iter().map(|part| links[part.link]));
    }
}
