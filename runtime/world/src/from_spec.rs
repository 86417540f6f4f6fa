//! Building robots and scenes from a checked spec: URDF files, mounts, groups, object types and
//! the initial scene of a problem.
//!
//! Paths in a spec are relative to the spec's folder, which the caller passes in.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use lamp_geometry::{Pose, Shape, Vec3};
use lamp_robot::{Mount, Robot};
use lamp_spec::{
    AtGoal, MeshMode, Mobility, ObjectType, Problem, RobotKind, RobotNames, ShapeSpec, Spec,
};

use crate::error::WorldError;
use crate::scene::{Body, Scene};

/// Everything of a spec that scenes are built from, loaded once.
#[derive(Clone, Debug)]
pub struct SpecWorld {
    /// Robot models by spec robot name.
    pub robots: BTreeMap<String, Arc<Robot>>,
    /// The shapes of each object type, placed in the type's frame.
    pub type_parts: BTreeMap<String, Vec<(Pose, Shape)>>,
    /// The URDF text of each robot by spec robot name, for viewers (`/robot_description`).
    urdf_texts: BTreeMap<String, String>,
    spec: Spec,
}

impl SpecWorld {
    /// Loads every robot and object type of `spec`; `spec_dir` is the spec file's folder.
    pub fn load(spec_dir: &Path, spec: &Spec) -> Result<SpecWorld, WorldError> {
        let mut robots = BTreeMap::new();
        let mut urdf_texts = BTreeMap::new();
        for robot in &spec.robots {
            robots.insert(robot.name.clone(), Arc::new(load_robot(spec_dir, robot)?));
            // Loading checked the file's size, so reading it whole is safe.
            let path = spec_dir.join(&robot.urdf);
            let text = std::fs::read_to_string(&path).map_err(|source| {
                robot_error(robot, lamp_robot::RobotError::Read { file: path.clone(), source })
            })?;
            urdf_texts.insert(robot.name.clone(), text);
        }
        let mut type_parts = BTreeMap::new();
        for object_type in &spec.object_types {
            type_parts.insert(object_type.name.clone(), type_parts_of(spec_dir, object_type)?);
        }
        Ok(SpecWorld { robots, type_parts, urdf_texts, spec: spec.clone() })
    }

    /// The URDF text of robot `name`, as its file holds it.
    pub fn urdf_text(&self, name: &str) -> Option<&str> {
        self.urdf_texts.get(name).map(String::as_str)
    }

    /// The spec this world was loaded from.
    pub fn spec(&self) -> &Spec {
        &self.spec
    }

    /// A body of type `type_name` named `name`, ready to add to a scene.
    pub fn body(&self, name: &str, type_name: &str) -> Option<Body> {
        let object_type = self.spec.object_type(type_name)?;
        Some(Body {
            name: name.to_string(),
            type_name: type_name.to_string(),
            movable: object_type.mobility == Mobility::Movable,
            world: object_type.world,
            parts: self.type_parts.get(type_name)?.clone(),
        })
    }

    /// Adds robot `name` to `scene` at configuration `q` (its gripper part is the spec's).
    pub fn add_robot(
        &self,
        scene: &mut Scene,
        name: &str,
        q: Vec<f64>,
    ) -> Result<usize, WorldError> {
        let unknown = || WorldError::UnknownName { what: "robot", name: name.to_string() };
        let model = self.robots.get(name).ok_or_else(unknown)?;
        let spec_robot = self.spec.robot(name).ok_or_else(unknown)?;
        let gripper = match spec_robot.gripper_part() {
            Some(part) => {
                let link = model.link_id(&part.link).ok_or_else(|| WorldError::UnknownName {
                    what: "link",
                    name: format!("{}/{}", name, part.link),
                })?;
                Some((part.type_name.clone(), link))
            }
            None => None,
        };
        scene.add_robot(name, Arc::clone(model), q, gripper)
    }

    /// The configuration of robot `name` with its root at `base` (if given) and the named
    /// configuration applied (if given); other joints at their neutral values.
    pub fn placement_configuration(
        &self,
        name: &str,
        base: Option<&Pose>,
        configuration: Option<&str>,
    ) -> Result<Vec<f64>, WorldError> {
        let unknown = || WorldError::UnknownName { what: "robot", name: name.to_string() };
        let model = self.robots.get(name).ok_or_else(unknown)?;
        let spec_robot = self.spec.robot(name).ok_or_else(unknown)?;
        let mut q = model.neutral_configuration();
        if let Some(base) = base {
            model.mount().write_coordinates(base, &mut q);
        }
        if let Some(configuration) = configuration {
            let named = spec_robot.configuration(configuration).ok_or_else(|| {
                WorldError::UnknownName { what: "configuration", name: configuration.to_string() }
            })?;
            model
                .apply_named_configuration(
                    named.values.iter().map(|(k, v)| (k.as_str(), *v)),
                    &mut q,
                )
                .map_err(|source| robot_error(spec_robot, source))?;
        }
        Ok(q)
    }

    /// The initial scene of a problem: its objects, the markers of its goal (at each target of
    /// an `at` goal or a structure goal, and with `at` goals where every movable object starts),
    /// its robots.
    pub fn problem_scene(&self, problem: &Problem) -> Result<Scene, WorldError> {
        let mut scene = Scene::new();
        for object in &problem.scene.objects {
            let body = self.body(&object.name, &object.type_name).ok_or_else(|| {
                WorldError::Undeclared {
                    problem: problem.name.clone(),
                    name: object.type_name.clone(),
                }
            })?;
            scene.add_body(body, object.pose)?;
        }
        // A problem with AtGoals or a structure goal is solved through markers, as the
        // demonstrations mark theirs: each object with a target gets a marker at it. With AtGoals
        // (the paper's Dinner: markers where objects start and where they are put), every
        // movable object also gets one where it starts (a pick is learned as a pick from a
        // marker, and an object no goal names may have to be moved too). A structure goal (the
        // paper's Keva and Jenga: markers only where blocks are put) places none there: "on a
        // marker" is then something a block becomes once, as in the demonstrations, which is
        // what orders a tower (docs/language.md). Markers collide with nothing.
        if let Some(marker_type) = self.goal_marker_type(problem) {
            let starts = problem
                .scene
                .objects
                .iter()
                .filter(|_| !problem.goal.at.is_empty())
                .filter(|object| {
                    self.spec
                        .object_type(&object.type_name)
                        .is_some_and(|kind| kind.mobility == Mobility::Movable)
                })
                .map(|object| (lamp_spec::start_marker_name(&object.name), object.pose));
            let targets = problem.goal.at.iter().map(|target| (target.marker_name(), target.pose));
            let structure = self
                .structure_targets(problem)?
                .into_iter()
                .map(|(object, pose)| (lamp_spec::marker_name(&object), pose));
            for (name, pose) in starts.chain(targets).chain(structure) {
                let body = self.body(&name, marker_type).ok_or_else(|| WorldError::Undeclared {
                    problem: problem.name.clone(),
                    name: marker_type.to_string(),
                })?;
                scene.add_body(body, pose)?;
            }
        }
        for placement in &problem.scene.robots {
            let q = self.placement_configuration(
                &placement.robot,
                placement.base.as_ref(),
                placement.configuration.as_deref(),
            )?;
            self.add_robot(&mut scene, &placement.robot, q)?;
        }
        Ok(scene)
    }
}

impl SpecWorld {
    /// The marker type a problem's goal places markers of: its `at` goals', or for a structure
    /// goal the spec's marker type (the checker allows at most one). `None` when the goal needs
    /// no markers, or has a structure goal in a spec without a marker type.
    pub fn goal_marker_type<'a>(&'a self, problem: &'a Problem) -> Option<&'a str> {
        if let Some(target) = problem.goal.at.first() {
            return Some(&target.marker_type);
        }
        problem.goal.structure.as_ref()?;
        self.spec
            .object_types
            .iter()
            .find(|kind| kind.mobility == Mobility::Marker)
            .map(|kind| kind.name.as_str())
    }

    /// Where a problem's structure goal puts each of its objects, in the structure's order: the
    /// anchor's pose in the scene · the goal's offset · the object's pose in the structure.
    /// Empty without a structure goal.
    pub fn structure_targets(&self, problem: &Problem) -> Result<Vec<(String, Pose)>, WorldError> {
        let Some(goal) = &problem.goal.structure else { return Ok(Vec::new()) };
        let structure = self.spec.structure(&goal.structure).ok_or_else(|| {
            WorldError::UnknownName { what: "structure", name: goal.structure.clone() }
        })?;
        let anchor =
            problem.scene.objects.iter().find(|object| object.name == goal.anchor).ok_or_else(
                || WorldError::UnknownName { what: "anchor", name: goal.anchor.clone() },
            )?;
        let frame = anchor.pose * goal.offset;
        Ok(structure
            .placements
            .iter()
            .map(|placement| (placement.object.clone(), frame * placement.pose))
            .collect())
    }

    /// Every pose a solution must leave an object at, with its tolerance: the problem's `at`
    /// goals, then each object of its structure goal at its structure pose within
    /// [`STRUCTURE_POSITION_TOLERANCE`] and [`STRUCTURE_ANGLE_TOLERANCE`]. A structure target's
    /// marker type is empty when the spec has none (the structure is then held to its poses at
    /// the end only, with no marker relation to watch while it is built).
    pub fn placement_targets(&self, problem: &Problem) -> Result<Vec<AtGoal>, WorldError> {
        let mut targets = problem.goal.at.clone();
        let marker_type = self.goal_marker_type(problem).unwrap_or_default().to_string();
        targets.extend(self.structure_targets(problem)?.into_iter().map(|(object, pose)| AtGoal {
            object,
            pose,
            position_tolerance: STRUCTURE_POSITION_TOLERANCE,
            angle_tolerance: STRUCTURE_ANGLE_TOLERANCE,
            marker_type: marker_type.clone(),
        }));
        Ok(targets)
    }
}

/// How far an object of a built structure may be from its structure pose: a structure is built
/// to what a careful hand achieves, and the physics check then proves it stands.
pub const STRUCTURE_POSITION_TOLERANCE: f64 = 0.005;

/// How far an object of a built structure may be turned from its structure pose (3°).
pub const STRUCTURE_ANGLE_TOLERANCE: f64 = 3.0 * std::f64::consts::PI / 180.0;

fn robot_error(robot: &lamp_spec::Robot, source: lamp_robot::RobotError) -> WorldError {
    WorldError::Robot {
        robot: robot.name.clone(),
        urdf: robot.urdf.clone(),
        source: Box::new(source),
    }
}

/// The mount a robot of `kind` has; a fixed arm is bolted at `pose`.
pub fn mount_of(kind: RobotKind, pose: Pose) -> Mount {
    match kind {
        RobotKind::FreeFlying => Mount::Floating,
        RobotKind::MobileArm => Mount::Planar,
        RobotKind::FixedArm => Mount::Fixed(pose),
    }
}

/// The names the robot file at `path` defines, loaded as a robot of `kind` is (its mount adds
/// coordinates): what the spec checker compares a robot block's names with.
pub fn robot_names(path: &Path, kind: RobotKind) -> Result<RobotNames, lamp_robot::RobotError> {
    let robot = Robot::from_urdf_file(path, mount_of(kind, Pose::identity()))?;
    let links = 0..robot.link_count();
    Ok(RobotNames {
        links: links.clone().map(|link| robot.link_name(link).to_string()).collect(),
        joints: links.filter_map(|link| robot.parent_joint_name(link)).map(String::from).collect(),
        coordinates: robot.coordinate_names().to_vec(),
    })
}

/// Loads a spec robot: its URDF with the mount its kind implies, its groups and ignored pairs.
pub fn load_robot(spec_dir: &Path, robot: &lamp_spec::Robot) -> Result<Robot, WorldError> {
    let mount = mount_of(robot.kind, robot.mount);
    let path: PathBuf = spec_dir.join(&robot.urdf);
    let fail = |source| robot_error(robot, source);
    let mut model = Robot::from_urdf_file(&path, mount).map_err(fail)?;
    for group in &robot.groups {
        let joints: Vec<&str> = group.joints.iter().map(String::as_str).collect();
        // A spec may spell out a built-in group (`arm`) to document it; the same set is fine.
        if let Some(existing) = model.group(&group.name) {
            let mut coordinates = Vec::new();
            for joint in &joints {
                coordinates.extend(model.joint_coordinates(joint).map_err(fail)?);
            }
            coordinates.sort_unstable();
            coordinates.dedup();
            if coordinates == existing.coordinates {
                continue;
            }
        }
        model = model.with_group(&group.name, &joints).map_err(fail)?;
    }
    let ignored: Vec<(&str, &str)> =
        robot.ignored_collisions.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
    model = model.with_ignored_collisions(&ignored).map_err(fail)?;
    for part in &robot.parts {
        if model.link_id(&part.link).is_none() {
            return Err(WorldError::UnknownName {
                what: "link",
                name: format!("{}/{} (part `{}`)", robot.name, part.link, part.type_name),
            });
        }
    }
    Ok(model)
}

/// The shapes of an object type in its frame (meshes loaded from the spec's folder).
pub fn type_parts_of(
    spec_dir: &Path,
    object_type: &ObjectType,
) -> Result<Vec<(Pose, Shape)>, WorldError> {
    object_type
        .shapes
        .iter()
        .map(|part| {
            let shape = match &part.shape {
                ShapeSpec::Box { size } => {
                    Shape::Box { half_extents: Vec3::new(size[0], size[1], size[2]) * 0.5 }
                }
                ShapeSpec::Cylinder { radius, height } => {
                    Shape::Cylinder { radius: *radius, half_height: height * 0.5 }
                }
                ShapeSpec::Sphere { radius } => Shape::Sphere { radius: *radius },
                ShapeSpec::Mesh { path, mode } => {
                    lamp_robot::load_mesh_file(&spec_dir.join(path), *mode == MeshMode::ConvexHull)
                        .map_err(|reason| WorldError::Shape {
                            type_name: object_type.name.clone(),
                            reason,
                        })?
                }
            };
            Ok((part.origin, shape))
        })
        .collect()
}
