//! The refiner's reading of a world state: which objects are robot parts, where everything is,
//! what is held, and the learned abstraction of a (possibly hypothetical) state.

use std::collections::{BTreeMap, BTreeSet};

use lamp_abstraction::{GroundAtom, Participant, Pose, Role, SamplerArtifact, Snapshot};
use lamp_plugin_api::{HostServices, PluginError, WorldState};
use nalgebra::{Quaternion, Translation3, UnitQuaternion};

/// A robot link that takes part in relations.
#[derive(Clone, Debug)]
pub(crate) struct Part {
    pub(crate) robot: String,
    pub(crate) link: String,
    pub(crate) gripper: bool,
}

/// A hypothetical state: configurations per robot and what each gripper link holds.
#[derive(Clone, Debug)]
pub(crate) struct Hypothesis {
    /// Robot name → configuration.
    pub(crate) configurations: BTreeMap<String, Vec<f64>>,
    /// Held object → (robot, link, grasp: the object's pose in the link's frame).
    pub(crate) held: BTreeMap<String, (String, String, Pose)>,
    /// Objects let go of, at the pose where they were released.
    pub(crate) placed: BTreeMap<String, Pose>,
}

/// The world as the refiner sees it.
pub(crate) struct WorldView {
    /// Part object name → part.
    pub(crate) parts: BTreeMap<String, Part>,
    /// Every participant: parts first (in name order), then objects (in name order).
    participants: Vec<Participant>,
    /// Static world poses of objects that are not held.
    object_poses: BTreeMap<String, Pose>,
    /// The state as it is.
    pub(crate) current: Hypothesis,
}

impl WorldView {
    pub(crate) fn new(world: &WorldState) -> Result<WorldView, PluginError> {
        let mut parts = BTreeMap::new();
        let mut participants = Vec::new();
        let mut configurations = BTreeMap::new();
        let mut held = BTreeMap::new();
        let mut object_poses = BTreeMap::new();
        for object in &world.objects {
            object_poses.insert(object.name.clone(), to_pose(&object.pose)?);
        }
        for robot in &world.robots {
            configurations.insert(robot.name.clone(), robot.configuration.clone());
            for part in &robot.parts {
                parts.insert(
                    part.object.clone(),
                    Part {
                        robot: robot.name.clone(),
                        link: part.link.clone(),
                        gripper: part.gripper,
                    },
                );
                participants.push(Participant {
                    name: part.object.clone(),
                    type_name: part.object_type.clone(),
                    role: Role::RobotPart { gripper: part.gripper },
                });
            }
            for object in &robot.held {
                held.insert(
                    object.object.clone(),
                    (robot.name.clone(), object.link.clone(), to_pose(&object.grasp)?),
                );
            }
        }
        participants.sort();
        // The wire does not say which objects are movable, and need not: the abstraction reads
        // names, types, poses and holds, never roles or the participants' order (lamp-abstraction
        // breaks ties by name), so this view abstracts every state as the build and the solver do.
        let mut objects: Vec<Participant> = world
            .objects
            .iter()
            .map(|object| Participant {
                name: object.name.clone(),
                type_name: object.object_type.clone(),
                role: Role::Object { movable: true },
            })
            .collect();
        objects.sort();
        participants.extend(objects);
        Ok(WorldView {
            parts,
            participants,
            object_poses,
            current: Hypothesis { configurations, held, placed: BTreeMap::new() },
        })
    }

    /// The world pose of `object` (a part or an object) in `state`.
    pub(crate) fn pose_in(
        &self,
        state: &Hypothesis,
        object: &str,
        host: &dyn HostServices,
    ) -> Result<Pose, PluginError> {
        if let Some(part) = self.parts.get(object) {
            return link_pose(state, &part.robot, &part.link, host);
        }
        if let Some((robot, link, grasp)) = state.held.get(object) {
            return Ok(link_pose(state, robot, link, host)? * grasp);
        }
        if let Some(pose) = state.placed.get(object) {
            return Ok(*pose);
        }
        self.object_poses.get(object).copied().ok_or_else(|| {
            PluginError::invalid_request(format!("no object `{object}` in the world"))
        })
    }

    /// Whether, in the learned abstraction of `state`, every atom of `adds` holds and none of
    /// `deletes` does.
    pub(crate) fn effects_hold(
        &self,
        artifact: &SamplerArtifact,
        state: &Hypothesis,
        host: &dyn HostServices,
        adds: &BTreeSet<GroundAtom>,
        deletes: &BTreeSet<GroundAtom>,
    ) -> Result<bool, PluginError> {
        artifact
            .effects_hold(&self.participants, &self.snapshot(state, host)?, adds, deletes)
            .map_err(|error| PluginError::failed(format!("abstracting the state: {error}")))
    }

    /// `state` as the abstraction reads it: every participant's pose and who holds what.
    fn snapshot(
        &self,
        state: &Hypothesis,
        host: &dyn HostServices,
    ) -> Result<Snapshot, PluginError> {
        let poses = self
            .participants
            .iter()
            .map(|participant| self.pose_in(state, &participant.name, host))
            .collect::<Result<Vec<_>, _>>()?;
        let index = |name: &str| self.participants.iter().position(|p| p.name == name);
        let mut held = Vec::new();
        for (object, (robot, link, _)) in &state.held {
            let gripper = self
                .parts
                .iter()
                .find(|(_, part)| part.gripper && &part.robot == robot && &part.link == link)
                .and_then(|(name, _)| index(name));
            if let (Some(gripper), Some(object)) = (gripper, index(object)) {
                held.push((gripper, object));
            }
        }
        Ok(Snapshot { poses, held })
    }
}

/// The world pose of a robot's link in `state`.
pub(crate) fn link_pose(
    state: &Hypothesis,
    robot: &str,
    link: &str,
    host: &dyn HostServices,
) -> Result<Pose, PluginError> {
    let q = state
        .configurations
        .get(robot)
        .ok_or_else(|| PluginError::invalid_request(format!("no robot `{robot}` in the world")))?;
    to_pose(&host.forward_kinematics(robot, q, link)?)
}

/// A wire pose as an isometry; the quaternion must be of unit length (within 1e-6).
pub(crate) fn to_pose(pose: &[f64; 7]) -> Result<Pose, PluginError> {
    let [x, y, z, qx, qy, qz, qw] = *pose;
    let quaternion = Quaternion::new(qw, qx, qy, qz);
    let norm = quaternion.norm();
    if !pose.iter().all(|value| value.is_finite()) || (norm - 1.0).abs() > 1e-6 {
        return Err(PluginError::invalid_request(format!("not a pose: {pose:?}")));
    }
    Ok(Pose::from_parts(Translation3::new(x, y, z), UnitQuaternion::new_normalize(quaternion)))
}

/// An isometry as a wire pose.
pub(crate) fn to_wire(pose: &Pose) -> [f64; 7] {
    let t = pose.translation.vector;
    let q = pose.rotation.quaternion();
    [t.x, t.y, t.z, q.i, q.j, q.k, q.w]
}
