//! The adapter from demonstration files to the learner's input: an MCAP trajectory read with
//! lamp-trajectory becomes a `lamp_learn::Demonstration`, its participants named and ordered as
//! lamp-participants names and orders a scene's.
//!
//! Participants are, in this order: for every robot of the file (in file order) one participant per
//! spec part, named `<robot>_<part type>`, posed by forward kinematics of the part's link; then every
//! body whose type is not the static world, in file order, posed as recorded. A gripper listed in
//! the file maps to the robot part of the same type name, or, when the file lists a single gripper
//! under another name, to the spec robot's gripper part.

use std::collections::BTreeMap;
use std::sync::Arc;

use lamp_abstraction::{Participant, Pose, Role, Snapshot};
use lamp_learn::Demonstration;
use lamp_participants::{ParticipantMap, RobotParts};
use lamp_robot::Robot;
use lamp_spec::Spec;
use lamp_trajectory::{RobotDescription, TrajectoryHeader, TrajectoryReader};

use crate::error::BuildError;
use crate::input::DemoFile;
use crate::ros2::{Ros2Bag, Ros2Error, Ros2Mapping, mapped_robot, ros2_bag};

/// Turns demonstration files into demonstrations, checking them against the spec.
#[derive(Debug, Clone)]
pub struct Adapter {
    /// The spec's domain, which every demonstration's header must name.
    domain: String,
    participants: ParticipantMap,
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
        Ok(Adapter {
            domain: spec.domain.clone(),
            participants: ParticipantMap::new(spec, models)?,
        })
    }

    /// Which robot links and bodies take part in relations, shared with problem writing and the
    /// solver's abstraction of the scenes it reaches.
    pub fn participants(&self) -> &ParticipantMap {
        &self.participants
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
            .map(|robot| vec![Pose::identity(); robot.parts.model().link_count()])
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
        let parts = self.participants.robot_parts(&description.name).ok_or_else(|| {
            BuildError::UndeclaredRobot { file: file.to_string(), robot: description.name.clone() }
        })?;
        let expected = parts.model().coordinate_names();
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
                let role = self.participants.object_role(&body.type_name).ok_or_else(|| {
                    BuildError::UndeclaredType {
                        file: file.to_string(),
                        body: body.name.clone(),
                        type_name: body.type_name.clone(),
                    }
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

/// A demonstration file of a `files … as ros2 { … }` source read with `mapping` against
/// `world`'s robot: its trajectory, and the indices of the mapped objects the bag lacks
/// ([`crate::ros2::Ros2Bag::absent`]).
pub fn ros2_demonstration(
    world: &lamp_world::SpecWorld,
    mapping: &Ros2Mapping,
    file: &DemoFile,
) -> Result<Ros2Bag, BuildError> {
    let robot = mapped_robot(world, mapping)?;
    Ok(ros2_bag(&file.bytes, &file.name, &world.spec().domain, mapping, robot.as_ref())
        .map_err(Box::new)?)
}

/// [`ros2_demonstration`] as the lamp trajectory file the adapter reads (its name unchanged),
/// with the indices of the mapped objects the bag lacks.
pub fn ros2_demo_file(
    world: &lamp_world::SpecWorld,
    mapping: &Ros2Mapping,
    file: &DemoFile,
) -> Result<(DemoFile, Vec<usize>), BuildError> {
    let bag = ros2_demonstration(world, mapping, file)?;
    let bytes = bag.trajectory.to_bytes().map_err(|error| Box::new(Ros2Error::Read(error)))?;
    Ok((DemoFile { name: file.name.clone(), bytes }, bag.absent))
}
