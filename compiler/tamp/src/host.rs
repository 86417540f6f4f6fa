//! The host services the runtime offers plugins, over a scene.
//!
//! [`SceneHost`] serves refiners: validity of whole configurations, collision-free IK, forward
//! kinematics. [`GroupHost`] serves one motion-planning call: the robot's space restricted to the
//! joint group that moves (the other coordinates stay where they start), with sampling.
//!
//! IK picks the coordinates that can move the link: a link rigidly attached to the mount (a
//! free-flying gripper, a mobile base) is placed by writing the mount's coordinates (a planar
//! base keeps only the target's floor projection and yaw); any other link is solved over the
//! `arm` group (the chain to the end effector) with the scene as acceptance test.

use std::cell::RefCell;

use lamp_plugin_api::{HostError, HostServices, Pose as WirePose};
use lamp_robot::IkError;
use lamp_robot::{ALL_GROUP, ARM_GROUP, IkConfig, LinkId, Robot};
use lamp_world::{
    DEFAULT_ANGULAR_RESOLUTION, DEFAULT_LINEAR_RESOLUTION, LinkGoal, MAX_EDGE_STEPS, ReachError,
    RobotSpace, Scene, Space, edge_steps, reach_observed,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::failures::{Cause, Tally};
use crate::poses::{from_wire, to_wire};

/// Random restarts of one IK call a refiner makes, after the attempt from the current
/// configuration.
///
/// A refiner turns region draws into link targets, and draws are cheap: when the attempt from
/// the current configuration fails, the target is almost always one the arm cannot take (a grasp
/// from the far side of a round object, a placement beyond reach from where the base stands), and
/// restarting from random configurations costs the most on exactly those. Measured on Café and
/// Dinner solves, nearly every IK solution came from the first attempt, and 30 restarts spent
/// 70–90 % of a solve failing; with two, the streams draw again instead (docs/solving.md). A
/// solution from a random restart also lies far from the current configuration, a long motion.
pub const REFINEMENT_IK_RESTARTS: usize = 2;

/// Refiner services over a scene, which tally what the refiner's attempts run into (for the
/// failure report): the refiner only says that a draw failed, the host sees why.
pub struct SceneHost<'a> {
    scene: &'a Scene,
    rng: RefCell<ChaCha8Rng>,
    cancelled: &'a dyn Fn() -> bool,
    seen: RefCell<Tally>,
}

impl<'a> SceneHost<'a> {
    /// Services over `scene`; IK restarts draw from a generator seeded with `seed`; the refiner
    /// polls `cancelled` between its draws.
    pub fn new(scene: &'a Scene, seed: u64, cancelled: &'a dyn Fn() -> bool) -> Self {
        SceneHost {
            scene,
            rng: RefCell::new(ChaCha8Rng::seed_from_u64(seed)),
            cancelled,
            seen: RefCell::default(),
        }
    }

    /// What the refiner's attempts ran into since the last call.
    pub fn take_seen(&self) -> Tally {
        self.seen.take()
    }

    /// Whether `robot` (index `index`) is valid at `q`, tallying why not.
    fn valid(&self, robot: &str, index: usize, q: &[f64]) -> bool {
        match self.scene.first_contact(index, q) {
            None => true,
            Some(contact) => {
                self.seen.borrow_mut().note(Cause::of_contact(robot, contact, self.scene), None);
                false
            }
        }
    }

    fn robot(&self, name: &str) -> Result<(usize, &Robot), HostError> {
        let index = self
            .scene
            .robot_index(name)
            .ok_or_else(|| HostError::failed(format!("no robot `{name}` in the scene")))?;
        Ok((index, self.scene.robots()[index].robot()))
    }

    fn checked<'q>(&self, robot: &Robot, q: &'q [f64]) -> Result<&'q [f64], HostError> {
        if q.len() == robot.dof() && q.iter().all(|v| v.is_finite()) {
            Ok(q)
        } else {
            Err(HostError::failed(format!(
                "a configuration of `{}` has {} finite coordinates, not {}",
                robot.name(),
                robot.dof(),
                q.len()
            )))
        }
    }
}

fn link_of(robot: &Robot, link: &str) -> Result<LinkId, HostError> {
    robot
        .link_id(link)
        .ok_or_else(|| HostError::failed(format!("robot `{}` has no link `{link}`", robot.name())))
}

/// Whether no joint coordinate lies between the mount and `link`.
fn rigid_on_mount(robot: &Robot, link: LinkId) -> bool {
    robot
        .chain(link)
        .into_iter()
        .filter_map(|on_chain| robot.parent_joint_name(on_chain))
        .all(|joint| robot.coordinate_index(joint).is_none())
}

impl HostServices for SceneHost<'_> {
    fn is_cancelled(&self) -> bool {
        (self.cancelled)()
    }

    fn configuration_is_valid(&self, robot: &str, q: &[f64]) -> Result<bool, HostError> {
        let (index, model) = self.robot(robot)?;
        Ok(self.valid(robot, index, self.checked(model, q)?))
    }

    fn edge_is_valid(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<bool, HostError> {
        let (index, model) = self.robot(robot)?;
        let (a, b) = (self.checked(model, a)?, self.checked(model, b)?);
        let steps = edge_steps(model, a, b, DEFAULT_LINEAR_RESOLUTION, DEFAULT_ANGULAR_RESOLUTION);
        if steps > MAX_EDGE_STEPS {
            // Too long to check or record at the resolution: never a valid edge.
            return Ok(false);
        }
        let mut q = a.to_vec();
        Ok((0..=steps).all(|i| {
            model.interpolate(a, b, i as f64 / steps as f64, &mut q);
            self.valid(robot, index, &q)
        }))
    }

    fn solve_ik(
        &self,
        robot: &str,
        link: &str,
        target: &WirePose,
        seed_q: &[f64],
    ) -> Result<Option<Vec<f64>>, HostError> {
        let (index, model) = self.robot(robot)?;
        let seed_q = self.checked(model, seed_q)?;
        let link = link_of(model, link)?;
        let target = from_wire(target).map_err(HostError::failed)?;
        if rigid_on_mount(model, link) {
            // The link's pose relative to the root is fixed: place the root.
            let root_in_link =
                model.link_pose(seed_q, link).inv_mul(&model.mount().root_pose(seed_q));
            let mut q = seed_q.to_vec();
            model.mount().write_coordinates(&(target * root_in_link), &mut q);
            return Ok(self.valid(robot, index, &q).then_some(q));
        }
        let group = if model.group(ARM_GROUP).is_some() { ARM_GROUP } else { ALL_GROUP };
        let mut rng = self.rng.borrow_mut();
        // A call is one attempt at the target: the first thing in its way is what it met,
        // however many restarts met something.
        let mut refused = None;
        let reached = reach_observed(
            self.scene,
            &LinkGoal { robot: index, group, link: Some(link), target: &target, start: seed_q },
            &IkConfig { restarts: REFINEMENT_IK_RESTARTS, ..IkConfig::default() },
            &mut rng,
            &mut |contact| {
                refused.get_or_insert_with(|| Cause::of_contact(robot, contact, self.scene));
            },
        );
        let mut seen = self.seen.borrow_mut();
        if let Some(cause) = refused {
            seen.note(cause, None);
        }
        let placing = || (robot.to_string(), model.link_name(link).to_string());
        match reached {
            Ok(q) => Ok(Some(q)),
            Err(ReachError::Ik(IkError::OutOfReach { distance, reach, .. })) => {
                let (robot, link) = placing();
                seen.note(Cause::OutOfReach { robot, link }, Some(distance - reach));
                Ok(None)
            }
            Err(ReachError::Ik(IkError::NoSolution {
                rejected: 0, best_position_error, ..
            })) => {
                let (robot, link) = placing();
                seen.note(Cause::NoIkSolution { robot, link }, Some(best_position_error));
                Ok(None)
            }
            Err(ReachError::Ik(_)) => Ok(None),
            Err(error) => Err(HostError::failed(error.to_string())),
        }
    }

    fn forward_kinematics(
        &self,
        robot: &str,
        q: &[f64],
        link: &str,
    ) -> Result<WirePose, HostError> {
        let (_, model) = self.robot(robot)?;
        let q = self.checked(model, q)?;
        Ok(to_wire(&model.link_pose(q, link_of(model, link)?)))
    }

    fn distance(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<f64, HostError> {
        let (_, model) = self.robot(robot)?;
        Ok(model.distance(self.checked(model, a)?, self.checked(model, b)?))
    }

    fn interpolate(
        &self,
        robot: &str,
        a: &[f64],
        b: &[f64],
        t: f64,
    ) -> Result<Vec<f64>, HostError> {
        let (_, model) = self.robot(robot)?;
        let mut q = self.checked(model, a)?.to_vec();
        model.interpolate(a, self.checked(model, b)?, t, &mut q);
        Ok(q)
    }
}

/// Motion-planning services for one call: the space of one joint group of one robot.
pub struct GroupHost<'a> {
    robot: &'a str,
    model: &'a Robot,
    /// How many values the model's distance forms have.
    form_len: usize,
    space: RobotSpace<'a>,
    cancelled: &'a dyn Fn() -> bool,
}

impl<'a> GroupHost<'a> {
    /// Services for moving `space`'s group of `robot`.
    pub fn new(
        robot: &'a str,
        model: &'a Robot,
        space: RobotSpace<'a>,
        cancelled: &'a dyn Fn() -> bool,
    ) -> Self {
        GroupHost { robot, model, form_len: model.distance_form_len(), space, cancelled }
    }

    fn check(&self, robot: &str, q: &[f64]) -> Result<(), HostError> {
        if robot != self.robot {
            return Err(HostError::failed(format!(
                "this motion call plans for `{}`, not `{robot}`",
                self.robot
            )));
        }
        if q.len() != self.model.dof() || !q.iter().all(|v| v.is_finite()) {
            return Err(HostError::failed(format!(
                "a configuration of `{robot}` has {} finite coordinates",
                self.model.dof()
            )));
        }
        Ok(())
    }

    /// Whether `form` can be one of `robot`'s distance forms. Its values are not checked to be
    /// finite, as configurations are: a form comes from [`HostServices::distance_form`], which
    /// checks its configuration, and a non-finite value could only make a distance infinite or
    /// NaN, never chosen as the nearest.
    fn check_form(&self, robot: &str, form: &[f64]) -> Result<(), HostError> {
        if robot != self.robot {
            return Err(HostError::failed(format!(
                "this motion call plans for `{}`, not `{robot}`",
                self.robot
            )));
        }
        if form.len() != self.form_len {
            return Err(HostError::failed(format!(
                "a distance form of `{robot}` has {} values, not {}",
                form.len(),
                self.form_len
            )));
        }
        Ok(())
    }
}

impl HostServices for GroupHost<'_> {
    fn is_cancelled(&self) -> bool {
        (self.cancelled)()
    }

    fn configuration_is_valid(&self, robot: &str, q: &[f64]) -> Result<bool, HostError> {
        self.check(robot, q)?;
        Ok(self.space.is_valid(q))
    }

    fn edge_is_valid(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<bool, HostError> {
        self.check(robot, a)?;
        self.check(robot, b)?;
        Ok(self.space.is_valid(a) && self.space.is_valid(b) && self.space.edge_is_valid(a, b))
    }

    fn forward_kinematics(
        &self,
        robot: &str,
        q: &[f64],
        link: &str,
    ) -> Result<WirePose, HostError> {
        self.check(robot, q)?;
        Ok(to_wire(&self.model.link_pose(q, link_of(self.model, link)?)))
    }

    fn distance(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<f64, HostError> {
        self.check(robot, a)?;
        self.check(robot, b)?;
        Ok(self.space.distance(a, b))
    }

    fn distance_form(&self, robot: &str, q: &[f64]) -> Result<Vec<f64>, HostError> {
        self.check(robot, q)?;
        Ok(self.space.distance_form(q))
    }

    fn nearest(&self, robot: &str, forms: &[Vec<f64>], form: &[f64]) -> Result<usize, HostError> {
        self.check_form(robot, form)?;
        for candidate in forms {
            self.check_form(robot, candidate)?;
        }
        Ok(self.space.nearest(forms, form))
    }

    fn interpolate(
        &self,
        robot: &str,
        a: &[f64],
        b: &[f64],
        t: f64,
    ) -> Result<Vec<f64>, HostError> {
        self.check(robot, a)?;
        self.check(robot, b)?;
        let mut q = a.to_vec();
        self.space.interpolate(a, b, t, &mut q);
        Ok(q)
    }

    fn sample_configuration(&self, robot: &str, seed: u64) -> Result<Vec<f64>, HostError> {
        if robot != self.robot {
            return Err(HostError::failed(format!("this motion call plans for `{}`", self.robot)));
        }
        let mut q = vec![0.0; self.model.dof()];
        self.space.sample(&mut ChaCha8Rng::seed_from_u64(seed), &mut q);
        Ok(q)
    }
}
