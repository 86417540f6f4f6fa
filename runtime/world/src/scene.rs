//! A scene: bodies at poses, robots at configurations, and what each gripper holds.
//!
//! The scene is the state the demonstrators, the refiner and the validator step through. Moving
//! a robot moves its held object with it (rigidly, keeping the grasp transform); a held object
//! leaves the scene's collision world and is checked as part of its robot instead.

use std::sync::Arc;

use lamp_geometry::{Aabb, BodyId, CollisionShape, CollisionWorld, Pose, Shape};
use lamp_robot::{LinkId, Robot};

use crate::error::WorldError;

/// A rigid body of the scene.
#[derive(Clone, Debug)]
pub struct Body {
    pub name: String,
    pub type_name: String,
    /// Whether a robot may carry it.
    pub movable: bool,
    /// The static world (floor, table): collides, but takes part in no relation.
    pub world: bool,
    /// The body's shapes, each placed in the body's frame (for drawing and reporting). None for
    /// a marker.
    pub parts: Vec<(Pose, Shape)>,
}

impl Body {
    /// Whether the body is a marker: a named pose (a goal location, say) that takes part in
    /// relations but has no geometry, so nothing ever collides with it.
    pub fn is_marker(&self) -> bool {
        self.parts.is_empty()
    }
}

/// A gripper link and the object it holds.
#[derive(Clone, Debug)]
pub struct Gripper {
    /// The relation type of the gripper part (usually `gripper`).
    pub part_type: String,
    pub link: LinkId,
    pub held: Option<Held>,
}

/// An object held by a gripper.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Held {
    /// Index of the body in the scene.
    pub body: usize,
    /// Pose of the object in the gripper link's frame, fixed while held.
    pub grasp: Pose,
}

/// A robot placed in the scene.
#[derive(Clone, Debug)]
pub struct SceneRobot {
    pub name: String,
    pub(crate) robot: Arc<Robot>,
    pub(crate) q: Vec<f64>,
    pub(crate) gripper: Option<Gripper>,
    /// One collision shape per link that has geometry.
    pub(crate) links: Vec<(LinkId, CollisionShape)>,
    /// Pairs of indices into `links` to check against each other.
    pub(crate) self_pairs: Vec<(usize, usize)>,
    /// Per entry of `links`: whether a held object may touch it (the gripper and its fingers).
    pub(crate) touches_held: Vec<bool>,
    /// The finger coordinates (the robot's `gripper` joint group) and their values in the
    /// configuration the robot was added with (a problem's: the spec's named configuration,
    /// open), to which the fingers return when they let go. Empty for a gripper without fingers.
    pub(crate) open_fingers: Vec<(usize, f64)>,
}

impl SceneRobot {
    /// The robot model.
    pub fn robot(&self) -> &Arc<Robot> {
        &self.robot
    }

    /// The current configuration.
    pub fn configuration(&self) -> &[f64] {
        &self.q
    }

    /// The gripper, if the robot has one.
    pub fn gripper(&self) -> Option<&Gripper> {
        self.gripper.as_ref()
    }

    /// The finger coordinates of the gripper and their open values (see [`crate::finger_path`]);
    /// empty for a gripper without finger joints (a magnet, a suction cup) or a robot without
    /// a gripper.
    pub fn open_fingers(&self) -> &[(usize, f64)] {
        &self.open_fingers
    }
}

/// Bodies and robots with their current state.
#[derive(Clone, Debug)]
pub struct Scene {
    pub(crate) bodies: Vec<Body>,
    pub(crate) collision: CollisionWorld,
    pub(crate) robots: Vec<SceneRobot>,
    /// Clearance every collision check demands, in metres (0: touching is a collision).
    pub(crate) margin: f64,
}

impl Default for Scene {
    fn default() -> Self {
        Scene::new()
    }
}

impl Scene {
    /// An empty scene with no safety margin.
    pub fn new() -> Scene {
        Scene {
            bodies: Vec::new(),
            collision: CollisionWorld::new(),
            robots: Vec::new(),
            margin: 0.0,
        }
    }

    /// Sets the clearance every check demands (metres; touching always collides).
    pub fn set_margin(&mut self, margin: f64) {
        self.margin = margin.max(0.0);
    }

    /// The clearance every check demands.
    pub fn margin(&self) -> f64 {
        self.margin
    }

    /// Adds a body; names must be unique.
    pub fn add_body(&mut self, body: Body, pose: Pose) -> Result<usize, WorldError> {
        if self.body_index(&body.name).is_some() {
            return Err(WorldError::Shape {
                type_name: body.type_name,
                reason: format!("a second body named `{}`", body.name),
            });
        }
        let id = if body.is_marker() {
            self.collision.insert_marker(pose)
        } else {
            let shape = CollisionShape::compound(&body.parts).map_err(|error| {
                WorldError::Shape { type_name: body.type_name.clone(), reason: error.to_string() }
            })?;
            self.collision.insert(shape, pose)
        };
        self.bodies.push(body);
        debug_assert_eq!(id.0, self.bodies.len() - 1);
        Ok(id.0)
    }

    /// Adds a robot at configuration `q`, with its gripper link (if any) and its part type.
    pub fn add_robot(
        &mut self,
        name: &str,
        robot: Arc<Robot>,
        q: Vec<f64>,
        gripper: Option<(String, LinkId)>,
    ) -> Result<usize, WorldError> {
        if q.len() != robot.dof() {
            return Err(WorldError::Configuration {
                robot: name.to_string(),
                reason: format!("{} values for {} coordinates", q.len(), robot.dof()),
            });
        }
        let mut per_link: Vec<(LinkId, Vec<(Pose, Shape)>)> = Vec::new();
        for geometry in robot.collision_geometry() {
            match per_link.iter_mut().find(|(link, _)| *link == geometry.link) {
                Some((_, parts)) => parts.push((geometry.origin, geometry.shape.clone())),
                None => {
                    per_link.push((geometry.link, vec![(geometry.origin, geometry.shape.clone())]))
                }
            }
        }
        per_link.sort_by_key(|(link, _)| *link);
        let mut links = Vec::with_capacity(per_link.len());
        for (link, parts) in per_link {
            let shape = CollisionShape::compound(&parts).map_err(|error| WorldError::Shape {
                type_name: format!("{name}/{}", robot.link_name(link)),
                reason: error.to_string(),
            })?;
            links.push((link, shape));
        }
        let position = |link: LinkId| links.iter().position(|(l, _)| *l == link);
        let self_pairs = robot
            .self_collision_pairs()
            .iter()
            .filter_map(|&(a, b)| Some((position(a)?, position(b)?)))
            .collect();
        let touches_held = links
            .iter()
            .map(|(link, _)| {
                gripper
                    .as_ref()
                    .is_some_and(|(_, gripper_link)| in_subtree(&robot, *link, *gripper_link))
            })
            .collect();
        let open_fingers = match &gripper {
            Some(_) => robot.group(lamp_robot::GRIPPER_GROUP).map_or_else(Vec::new, |group| {
                group.coordinates.iter().map(|&c| (c, q[c])).collect()
            }),
            None => Vec::new(),
        };
        let gripper = gripper.map(|(part_type, link)| Gripper { part_type, link, held: None });
        self.robots.push(SceneRobot {
            name: name.to_string(),
            robot,
            q,
            gripper,
            links,
            self_pairs,
            touches_held,
            open_fingers,
        });
        Ok(self.robots.len() - 1)
    }

    /// Every body, in insertion order.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The index of the body with this name.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|body| body.name == name)
    }

    /// The world pose of a body (a held body's pose follows its gripper).
    pub fn body_pose(&self, body: usize) -> Pose {
        self.collision.pose(BodyId(body)).copied().unwrap_or_else(Pose::identity)
    }

    /// Moves a body that no gripper holds.
    pub fn set_body_pose(&mut self, body: usize, pose: Pose) {
        self.collision.set_pose(BodyId(body), pose);
    }

    /// Every robot, in insertion order.
    pub fn robots(&self) -> &[SceneRobot] {
        &self.robots
    }

    /// The index of the robot with this name.
    pub fn robot_index(&self, name: &str) -> Option<usize> {
        self.robots.iter().position(|robot| robot.name == name)
    }

    /// Sets a robot's configuration; its held object follows.
    pub fn set_configuration(&mut self, robot: usize, q: &[f64]) {
        let Some(state) = self.robots.get_mut(robot) else { return };
        state.q.copy_from_slice(q);
        if let Some(gripper) = &state.gripper
            && let Some(held) = gripper.held
        {
            let pose = state.robot.link_pose(q, gripper.link) * held.grasp;
            self.collision.set_pose(BodyId(held.body), pose);
        }
    }

    /// The world pose of a robot's gripper link at configuration `q`.
    pub fn gripper_pose(&self, robot: usize, q: &[f64]) -> Option<Pose> {
        let state = self.robots.get(robot)?;
        let gripper = state.gripper.as_ref()?;
        Some(state.robot.link_pose(q, gripper.link))
    }

    /// How far `body`, held by robot `robot` at configuration `q`, must rise straight up so
    /// that its bottom is `clearance` above the top of every other body whose box, grown by
    /// `clearance`, it overlaps across (0 when it is already that high). Boxes, world-aligned:
    /// conservative for what a carry passes on its way up and over.
    pub fn rise_to_clear(&self, body: usize, pose: &Pose, clearance: f64) -> f64 {
        let Some(shape) = self.collision.shape(BodyId(body)) else { return 0.0 };
        let held = shape.aabb(pose);
        let across = |other: &Aabb| {
            (0..2).all(|axis| {
                held.mins[axis] < other.maxs[axis] + clearance
                    && other.mins[axis] < held.maxs[axis] + clearance
            })
        };
        (0..self.bodies.len())
            .filter(|&other| other != body)
            .filter_map(|other| {
                let id = BodyId(other);
                let outline = self.collision.shape(id)?.aabb(self.collision.pose(id)?);
                across(&outline).then_some(outline.maxs.z + clearance - held.mins.z)
            })
            .fold(0.0, f64::max)
    }

    /// The body a robot's gripper holds.
    pub fn held(&self, robot: usize) -> Option<Held> {
        self.robots.get(robot)?.gripper.as_ref()?.held
    }

    /// Attaches `body` to the robot's gripper at the current relative pose.
    pub fn grab(&mut self, robot: usize, body: usize) -> Result<(), WorldError> {
        let object = self.bodies.get(body).map(|b| (b.name.clone(), b.movable));
        let Some(state) = self.robots.get(robot) else {
            return Err(WorldError::UnknownName { what: "robot", name: robot.to_string() });
        };
        let refuse = |reason: &str| WorldError::Grab {
            robot: state.name.clone(),
            object: object.as_ref().map_or_else(|| body.to_string(), |(name, _)| name.clone()),
            reason: reason.to_string(),
        };
        let Some((_, movable)) = object else { return Err(refuse("there is no such body")) };
        if !movable {
            return Err(refuse("it is static"));
        }
        let Some(gripper) = &state.gripper else { return Err(refuse("the robot has no gripper")) };
        if gripper.held.is_some() {
            return Err(refuse("the gripper already holds an object"));
        }
        if self
            .robots
            .iter()
            .any(|r| r.gripper.as_ref().and_then(|g| g.held).is_some_and(|h| h.body == body))
        {
            return Err(refuse("another gripper holds it"));
        }
        let link_pose = state.robot.link_pose(&state.q, gripper.link);
        let grasp = link_pose.inv_mul(&self.body_pose(body));
        if let Some(gripper) = &mut self.robots[robot].gripper {
            gripper.held = Some(Held { body, grasp });
        }
        self.collision.set_enabled(BodyId(body), false);
        Ok(())
    }

    /// Detaches the held object where it is; returns its index.
    pub fn release(&mut self, robot: usize) -> Option<usize> {
        let held = self.robots.get_mut(robot)?.gripper.as_mut()?.held.take()?;
        self.collision.set_enabled(BodyId(held.body), true);
        Some(held.body)
    }
}

/// Whether `link` is `root` or below it.
fn in_subtree(robot: &Robot, link: LinkId, root: LinkId) -> bool {
    let mut current = Some(link);
    while let Some(id) = current {
        if id == root {
            return true;
        }
        current = robot.parent_link(id);
    }
    false
}
