//! The adapter from demonstration files to the learner's input: an MCAP trajectory read with
//! lamp-trajectory becomes a `lamp_learn::Demonstration`.
//!
//! Participants are, in this order: for every robot of the file (in file order) one participant per
//! spec part, named `<robot>_<part type>`, posed by forward kinematics of the part's link; then every
//! body whose type is not the static world, in file order, posed as recorded. A gripper listed in
//! the file maps to the robot part of the same type name, or, when the file lists a single gripper
//! under another name, to the spec robot's gripper part.

use std::collections::BTreeMap;
use std::sync::Arc;

use lamp_learn::{Demonstration, Participant, Pose, Role, Snapshot};
use lamp_robot::{LinkId, Robot};
use lamp_spec::{Mobility, Spec};
use lamp_trajectory::{RobotDescription, TrajectoryHeader, TrajectoryReader};
use lamp_world::WorldError;

use crate::error::BuildError;
use crate::input::DemoFile;

/// The participant name of a robot part.
pub fn part_participant_name(robot: &str, part_type: &str) -> String {
    format!("{robot}_{part_type}")
}

/// Turns demonstration files into demonstrations, checking them against the spec.
#[derive(Debug, Clone)]
pub struct Adapter {
    /// The spec's domain, which every demonstration's header must name.
    domain: String,
    robots: BTreeMap<String, RobotParts>,
    /// Object type → `None` for the static world, else whether it is movable.
    types: BTreeMap<String, Option<bool>>,
}

/// A spec robot with the links of its parts.
#[derive(Debug, Clone)]
pub struct RobotParts {
    pub(crate) model: Arc<Robot>,
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

impl RobotParts {
    /// The robot's parts of a spec robot whose model is loaded.
    pub(crate) fn new(
        spec_robot: &lamp_spec::Robot,
        model: &Arc<Robot>,
    ) -> Result<Self, BuildError> {
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
            .collect::<Result<Vec<_>, BuildError>>()?;
        Ok(RobotParts { model: Arc::clone(model), parts })
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
    pub(crate) fn part_poses(&self, q: &[f64], links: &mut [Pose], out: &mut Vec<Pose>) {
        self.model.forward_kinematics(q, links);
        out.extend(self.parts.iter().map(|part| links[part.link]));
    }
}

/// How one robot of a file maps to participants.
struct FileRobot<'a> {
    parts: &'a RobotParts,
    /// Per gripper of the file: the participant index of the gripper part.
    grippers: Vec<usize>,
    /// Per gripper of the file: its name, for messages.
    name: String,
}

impl Adapter {
    /// An adapter for `spec`, with the robot models loaded from it (`lamp_world::SpecWorld::robots`).
    pub fn new(spec: &Spec, models: &BTreeMap<String, Arc<Robot>>) -> Result<Self, BuildError> {
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
        Ok(Adapter { domain: spec.domain.clone(), robots, types })
    }

    /// The parts of a spec robot.
    pub fn robot_parts(&self, robot: &str) -> Option<&RobotParts> {
        self.robots.get(robot)
    }

    /// Reads one file and turns it into a demonstration whose id is the file's name; a file of
    /// another domain than the spec's, or without a step, is refused.
    pub fn demonstration(&self, file: &DemoFile) -> Result<Demonstration, BuildError> {
        let reader = TrajectoryReader::from_bytes(&file.bytes, file.name.as_str())?;
        let header = reader.header().clone();
        if header.domain != self.domain {
            return Err(BuildError::OtherDomain {
                file: file.name.clone(),
                found: header.domain,
                expected: self.domain.clone(),
            });
        }
        let mut participants = Vec::new();
        let mut robots = Vec::new();
        for description in &header.robots {
            robots.push(self.file_robot(&file.name, description, &mut participants)?);
        }
        let bodies = self.body_participants(&file.name, &header, &mut participants)?;
        let mut scratch: Vec<Vec<Pose>> = robots
            .iter()
            .map(|robot| vec![Pose::identity(); robot.parts.model.link_count()])
            .collect();
        let mut steps = Vec::new();
        for (index, step) in reader.enumerate() {
            let step = step?;
            let mut poses = Vec::with_capacity(participants.len());
            let mut held = Vec::new();
            for ((robot, state), links) in robots.iter().zip(&step.robots).zip(&mut scratch) {
                robot.parts.part_poses(&state.positions, links, &mut poses);
                for (gripper, body) in robot.grippers.iter().zip(&state.held) {
                    let Some(body) = *body else { continue };
                    let Some(participant) = bodies.get(body).copied().flatten() else {
                        return Err(BuildError::HeldWorldBody {
                            file: file.name.clone(),
                            step: index as u64,
                            robot: robot.name.clone(),
                            body: header
                                .bodies
                                .get(body)
                                .map(|b| b.name.clone())
                                .unwrap_or_default(),
                        });
                    };
                    held.push((*gripper, participant));
                }
            }
            poses.extend(
                step.body_poses
                    .iter()
                    .zip(&bodies)
                    .filter(|(_, slot)| slot.is_some())
                    .map(|(pose, _)| *pose),
            );
            steps.push(Snapshot { poses, held });
        }
        if steps.is_empty() {
            return Err(BuildError::EmptyDemonstration { file: file.name.clone() });
        }
        Ok(Demonstration { id: file.name.clone(), participants, steps })
    }

    fn file_robot<'a>(
        &'a self,
        file: &str,
        description: &RobotDescription,
        participants: &mut Vec<Participant>,
    ) -> Result<FileRobot<'a>, BuildError> {
        let parts = self.robots.get(&description.name).ok_or_else(|| {
            BuildError::UndeclaredRobot { file: file.to_string(), robot: description.name.clone() }
        })?;
        let expected = parts.model.coordinate_names();
        if description.coordinates.as_slice() != expected {
            return Err(BuildError::Coordinates {
                file: file.to_string(),
                robot: description.name.clone(),
                expected: expected.join(" "),
                found: description.coordinates.join(" "),
            });
        }
        let first = participants.len();
        participants.extend(parts.participants(&description.name));
        let grippers = description
            .grippers
            .iter()
            .map(|gripper| {
                let by_name = parts.parts.iter().position(|part| &part.type_name == gripper);
                let sole = (description.grippers.len() == 1)
                    .then(|| parts.parts.iter().position(|part| part.gripper))
                    .flatten();
                by_name.or(sole).map(|part| first + part).ok_or_else(|| {
                    BuildError::UnknownGripper {
                        file: file.to_string(),
                        robot: description.name.clone(),
                        gripper: gripper.clone(),
                        parts: parts
                            .parts
                            .iter()
                            .map(|part| part.type_name.as_str())
                            .collect::<Vec<_>>()
                            .join(", "),
                    }
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(FileRobot { parts, grippers, name: description.name.clone() })
    }

    /// Adds the bodies that take part in relations; returns, per body of the file, its participant index.
    fn body_participants(
        &self,
        file: &str,
        header: &TrajectoryHeader,
        participants: &mut Vec<Participant>,
    ) -> Result<Vec<Option<usize>>, BuildError> {
        header
            .bodies
            .iter()
            .map(|body| {
                let role =
                    self.types.get(&body.type_name).ok_or_else(|| BuildError::UndeclaredType {
                        file: file.to_string(),
                        body: body.name.clone(),
                        type_name: body.type_name.clone(),
                    })?;
                Ok(role.map(|movable| {
                    participants.push(Participant {
                        name: body.name.clone(),
                        type_name: body.type_name.clone(),
                        role: Role::Object { movable },
                    });
                    participants.len() - 1
                }))
            })
            .collect()
    }
}
