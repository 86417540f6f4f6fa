//! Is a robot configuration collision-free? Robot links against the scene, the robot against
//! itself, and the held object against the scene and the robot (its gripper excepted).
//!
//! Bodies that never move are not checked against each other; movable bodies resting on a
//! surface must clear it (the bundled scenes place them 1 mm above).

use lamp_geometry::{Aabb, BodyId, Pose, intersects, within_margin};

use crate::scene::Scene;

/// The first collision found for a configuration, for messages and tests.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Contact {
    /// A coordinate is outside its limits (or not finite).
    OutOfLimits,
    /// A robot link touches a body.
    LinkBody { link: String, body: String },
    /// Two links of the robot touch.
    SelfCollision { a: String, b: String },
    /// The held object touches a body.
    HeldBody { held: String, body: String },
    /// The held object touches a link other than its gripper's.
    HeldLink { held: String, link: String },
}

impl std::fmt::Display for Contact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Contact::OutOfLimits => write!(f, "a joint is outside its limits"),
            Contact::LinkBody { link, body } => write!(f, "link `{link}` touches `{body}`"),
            Contact::SelfCollision { a, b } => write!(f, "links `{a}` and `{b}` touch"),
            Contact::HeldBody { held, body } => write!(f, "held `{held}` touches `{body}`"),
            Contact::HeldLink { held, link } => write!(f, "held `{held}` touches link `{link}`"),
        }
    }
}

impl Scene {
    /// Whether robot `robot` at `q` (carrying what it holds now) is within limits and
    /// collision-free.
    pub fn is_valid(&self, robot: usize, q: &[f64]) -> bool {
        self.first_contact(robot, q).is_none()
    }

    /// The first problem with robot `robot` at `q`, or `None` if it is valid.
    pub fn first_contact(&self, robot: usize, q: &[f64]) -> Option<Contact> {
        self.first_contact_of_moving(robot, q, None)
    }

    /// [`Scene::first_contact`] skipping the link checks that cannot have changed: with a
    /// `moving` mask (one flag per link with geometry, see [`Scene::moving_links`]) links that
    /// do not move are not checked against the scene, nor against each other. Valid only when
    /// the unmoved links were already checked at the same values (a planner's start state).
    pub(crate) fn first_contact_of_moving(
        &self,
        robot: usize,
        q: &[f64],
        moving: Option<&[bool]>,
    ) -> Option<Contact> {
        let state = self.robots.get(robot)?;
        let model = &state.robot;
        if !model.within_limits(q) {
            return Some(Contact::OutOfLimits);
        }
        let mut poses = vec![Pose::identity(); model.link_count()];
        model.forward_kinematics(q, &mut poses);
        let held = state.gripper.as_ref().and_then(|g| g.held.map(|h| (g.link, h)));
        let link_name = |index: usize| model.link_name(state.links[index].0).to_string();

        let moves = |index: usize| moving.is_none_or(|mask| mask[index]);
        // Every link's world box, once: the broad phase against bodies, each other and the
        // held object (exact tests are far dearer than comparing boxes). The boxes only filter,
        // so the cheaper, looser ones do.
        let boxes: Vec<Aabb> =
            state.links.iter().map(|(link, shape)| shape.bounding_box(&poses[*link])).collect();
        // The bodies near any moving link: each link is then compared with these few, not
        // with every body of the scene.
        let reach = (0..boxes.len()).filter(|&index| moves(index)).map(|index| boxes[index]);
        let near = reach
            .reduce(|all, one| all.union(&one))
            .map(|all| self.collision.bodies_near(&all, self.margin.max(0.0)))
            .unwrap_or_default();
        for (index, (link, shape)) in state.links.iter().enumerate() {
            if !moves(index) {
                continue;
            }
            let pose = poses[*link];
            let hit = self.collision.first_contact_among(
                &near,
                shape,
                &pose,
                &boxes[index],
                self.margin,
                |_| false,
            );
            if let Some(body) = hit {
                return Some(Contact::LinkBody {
                    link: link_name(index),
                    body: self.bodies[body.0].name.clone(),
                });
            }
        }
        for &(a, b) in &state.self_pairs {
            if !moves(a) && !moves(b) {
                continue;
            }
            if !boxes[a].overlaps(&boxes[b], 0.0) {
                continue;
            }
            let (link_a, shape_a) = &state.links[a];
            let (link_b, shape_b) = &state.links[b];
            if intersects(shape_a, &poses[*link_a], shape_b, &poses[*link_b]) {
                return Some(Contact::SelfCollision { a: link_name(a), b: link_name(b) });
            }
        }
        if let Some((gripper_link, held)) = held {
            let held_name = &self.bodies[held.body].name;
            let held_pose = poses[gripper_link] * held.grasp;
            let held_shape = self.collision.shape(BodyId(held.body))?;
            let skip = |id: BodyId| id.0 == held.body;
            let held_box = held_shape.bounding_box(&held_pose);
            if let Some(body) = self.collision.first_contact_in_box(
                held_shape,
                &held_pose,
                &held_box,
                self.margin,
                skip,
            ) {
                return Some(Contact::HeldBody {
                    held: held_name.clone(),
                    body: self.bodies[body.0].name.clone(),
                });
            }
            for (index, (link, shape)) in state.links.iter().enumerate() {
                if !state.touches_held[index]
                    && held_box.overlaps(&boxes[index], 0.0)
                    && within_margin(held_shape, &held_pose, shape, &poses[*link], 0.0)
                {
                    return Some(Contact::HeldLink {
                        held: held_name.clone(),
                        link: link_name(index),
                    });
                }
            }
        }
        None
    }

    /// The first robot link (in robot, then link order) closer than the scene's margin to body
    /// `body` if it stood at `pose`, named `link` of `robot`; held objects are not looked at.
    pub(crate) fn link_near_body(&self, body: usize, pose: &Pose) -> Option<String> {
        let shape = self.collision.shape(BodyId(body))?;
        let body_box = shape.aabb(pose);
        for state in &self.robots {
            let model = &state.robot;
            let mut poses = vec![Pose::identity(); model.link_count()];
            model.forward_kinematics(&state.q, &mut poses);
            for (link, link_shape) in &state.links {
                let link_pose = poses[*link];
                if link_shape.aabb(&link_pose).overlaps(&body_box, self.margin.max(0.0))
                    && within_margin(shape, pose, link_shape, &link_pose, self.margin)
                {
                    return Some(format!("`{}` of `{}`", model.link_name(*link), state.name));
                }
            }
        }
        None
    }

    /// One flag per link with geometry (in the robot's internal order): whether changing the
    /// coordinates `coordinates` can move it.
    pub(crate) fn moving_links(&self, robot: usize, coordinates: &[usize]) -> Vec<bool> {
        let Some(state) = self.robots.get(robot) else { return Vec::new() };
        let model = &state.robot;
        let mount = model.mount().coordinate_count();
        let moves_mount = coordinates.iter().any(|&c| c < mount);
        state
            .links
            .iter()
            .map(|(link, _)| {
                moves_mount
                    || model.chain(*link).iter().any(|&on_chain| {
                        model.parent_joint_name(on_chain).is_some_and(|joint| {
                            model
                                .joint_coordinates(joint)
                                .is_ok_and(|own| own.iter().any(|c| coordinates.contains(c)))
                        })
                    })
            })
            .collect()
    }

    /// Pairs of bodies that touch where at least one of them can move, as names, sorted.
    /// A valid initial scene has none.
    pub fn body_contacts(&self) -> Vec<(String, String)> {
        self.collision
            .contacts_between_bodies(self.margin)
            .into_iter()
            .filter(|(a, b)| self.bodies[a.0].movable || self.bodies[b.0].movable)
            .map(|(a, b)| (self.bodies[a.0].name.clone(), self.bodies[b.0].name.clone()))
            .collect()
    }
}
