//! Inverse kinematics: damped least squares with adaptive damping, joint-limit clamping and random
//! restarts, over one joint group with every other coordinate held fixed.
//!
//! Each attempt runs Levenberg–Marquardt-style iterations: a damped least-squares step
//! `Δq = Jᵀ (J Jᵀ + λ² I)⁻¹ e` on the group's columns of the geometric Jacobian, the step is clamped
//! into the joint limits, and it is kept only if it lowers the error (λ shrinks) or rejected (λ grows).
//! A target outside the group's reach ball (`Robot::reach_ball`) is refused before any iteration.
//! The first attempt starts at the seed, later ones at uniform samples of the group. A converged
//! configuration is offered to the caller's `accept` callback (e.g. a collision check) before it is
//! returned; a rejected one counts as a failed attempt.

use lamp_geometry::Pose;
use lamp_geometry::math::relative_pose;
use nalgebra::{Matrix6, Matrix6xX, Vector6};
use rand_chacha::ChaCha8Rng;

use crate::error::IkError;
use crate::mount::Mount;
use crate::robot::{CoordinateKind, JointGroup, LinkId, Robot};

/// Default success threshold on the distance between the link origin and the target (metres).
pub const DEFAULT_POSITION_TOLERANCE: f64 = 1e-3;
/// Default success threshold on the rotation angle between the link frame and the target (radians).
pub const DEFAULT_ORIENTATION_TOLERANCE: f64 = 0.01;
/// Default iterations per attempt.
pub const DEFAULT_MAX_ITERATIONS: usize = 100;
/// Default number of random restarts after the attempt from the seed.
pub const DEFAULT_RESTARTS: usize = 30;
/// Default initial damping λ (in the units of the error: metres and radians).
pub const DEFAULT_DAMPING: f64 = 0.05;

/// Smallest damping the adaptive schedule goes down to (keeps J Jᵀ + λ² I well conditioned).
const MINIMUM_DAMPING: f64 = 1e-4;
/// Damping above which an attempt is considered stuck in a local minimum.
const MAXIMUM_DAMPING: f64 = 1e3;
/// Factor by which damping shrinks after an accepted step.
const DAMPING_DECREASE: f64 = 0.3;
/// Factor by which damping grows after a rejected step.
const DAMPING_INCREASE: f64 = 8.0;
/// Largest change of any coordinate in one step (radians or metres); larger steps are scaled down
/// because the linearisation is meaningless that far away.
const MAXIMUM_STEP: f64 = 0.4;
/// How close to a limit a coordinate counts as at it, for blocking steps that push past it.
const LIMIT_SLACK: f64 = 1e-9;

/// Tolerances and budgets of [`solve_ik`].
#[derive(Clone, Debug, PartialEq)]
pub struct IkConfig {
    pub position_tolerance: f64,
    pub orientation_tolerance: f64,
    pub max_iterations: usize,
    pub restarts: usize,
    pub damping: f64,
}

impl IkConfig {
    /// The defaults: 1 mm, 0.01 rad, [`DEFAULT_MAX_ITERATIONS`], [`DEFAULT_RESTARTS`],
    /// [`DEFAULT_DAMPING`].
    pub fn new() -> IkConfig {
        IkConfig {
            position_tolerance: DEFAULT_POSITION_TOLERANCE,
            orientation_tolerance: DEFAULT_ORIENTATION_TOLERANCE,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            restarts: DEFAULT_RESTARTS,
            damping: DEFAULT_DAMPING,
        }
    }
}

impl Default for IkConfig {
    fn default() -> IkConfig {
        IkConfig::new()
    }
}

/// The pose error of `current` with respect to `target`: translation (world) and rotation vector
/// (world) that would carry the current frame onto the target.
#[inline]
fn pose_error(current: &Pose, target: &Pose) -> Vector6<f64> {
    let position = target.translation.vector - current.translation.vector;
    let rotation = (target.rotation * current.rotation.inverse()).scaled_axis();
    Vector6::new(position.x, position.y, position.z, rotation.x, rotation.y, rotation.z)
}

#[inline]
fn error_norms(error: &Vector6<f64>) -> (f64, f64) {
    (error.fixed_rows::<3>(0).norm(), error.fixed_rows::<3>(3).norm())
}

/// What an inverse-kinematics solve looks for: `link` of `robot` at `target`, changing only the
/// coordinates of `group` (others are copied from `seed`, where the first attempt starts).
#[derive(Debug, Clone, Copy)]
pub struct IkGoal<'a> {
    pub robot: &'a Robot,
    pub group: &'a JointGroup,
    pub link: LinkId,
    pub target: &'a Pose,
    pub seed: &'a [f64],
}

/// Finds a configuration that meets `goal`. See the module docs for the method.
pub fn solve_ik(
    goal: &IkGoal<'_>,
    config: &IkConfig,
    rng: &mut ChaCha8Rng,
    accept: &mut dyn FnMut(&[f64]) -> bool,
) -> Result<Vec<f64>, IkError> {
    solve_ik_screened(goal, config, rng, &mut || true, accept)
}

/// [`solve_ik`] with a screen of the target, asked once before any iteration (after the reach
/// test): `false` when the caller knows that `accept` refuses every configuration meeting the
/// target within the tolerances (a gripper that would stand inside an obstacle there, whatever
/// the arm does). The search is then skipped with [`IkError::TargetRefused`].
///
/// A refused target takes from `rng` exactly what a search that tried every restart takes, so
/// that the screen decides how soon the answer comes, never which draws follow it: the same seed
/// gives the same results with or without it.
pub fn solve_ik_screened(
    goal: &IkGoal<'_>,
    config: &IkConfig,
    rng: &mut ChaCha8Rng,
    target_possible: &mut dyn FnMut() -> bool,
    accept: &mut dyn FnMut(&[f64]) -> bool,
) -> Result<Vec<f64>, IkError> {
    let IkGoal { robot, group, link, target, seed } = *goal;
    validate(robot, group, link, target, seed, config)?;
    if let Some(result) = solve_floating_base_exactly(robot, group, link, target, seed, accept) {
        return result;
    }

    let chain = robot.chain(link);
    if let Some((centre, reach)) = robot.reach_ball_of_chain(group, &chain, seed) {
        let distance = (target.translation.vector - centre).norm();
        if distance > reach + config.position_tolerance {
            return Err(IkError::OutOfReach {
                link: robot.link_name(link).to_string(),
                distance,
                reach,
            });
        }
    }

    let mut start = seed.to_vec();
    if !target_possible() {
        for _ in 0..config.restarts {
            robot.sample_uniform(group, seed, rng, &mut start);
        }
        return Err(IkError::TargetRefused { link: robot.link_name(link).to_string() });
    }
    let mut solver = Solver::new(robot, group, chain, target, config);
    let mut rejected = 0;
    for attempt in 0..=config.restarts {
        if attempt > 0 {
            robot.sample_uniform(group, seed, rng, &mut start);
        }
        solver.clamp_group(&mut start);
        if solver.run(&mut start) {
            if accept(&start) {
                return Ok(start);
            }
            rejected += 1;
        }
    }
    Err(IkError::NoSolution {
        link: robot.link_name(link).to_string(),
        attempts: config.restarts + 1,
        rejected,
        best_position_error: solver.best.0,
        best_orientation_error: solver.best.1,
    })
}

fn validate(
    robot: &Robot,
    group: &JointGroup,
    link: LinkId,
    target: &Pose,
    seed: &[f64],
    config: &IkConfig,
) -> Result<(), IkError> {
    let invalid = |reason: String| Err(IkError::InvalidRequest { reason });
    if seed.len() != robot.dof() {
        return invalid(format!(
            "seed has {} coordinates, robot `{}` has {}",
            seed.len(),
            robot.name(),
            robot.dof()
        ));
    }
    if !seed.iter().all(|value| value.is_finite()) {
        return invalid("seed has a non-finite coordinate".into());
    }
    if link >= robot.link_count() {
        return invalid(format!("link id {link} out of range ({} links)", robot.link_count()));
    }
    if group.coordinates.is_empty() || group.coordinates.iter().any(|&index| index >= robot.dof()) {
        return invalid(format!(
            "group `{}` is empty or names a coordinate out of range",
            group.name
        ));
    }
    if !group.coordinates.windows(2).all(|pair| pair[0] < pair[1]) {
        return invalid(format!("group `{}` coordinates are not sorted and unique", group.name));
    }
    let finite_target = target.translation.vector.iter().all(|value| value.is_finite())
        && target.rotation.coords.iter().all(|value| value.is_finite());
    if !finite_target {
        return invalid("target pose is not finite".into());
    }
    if !(config.position_tolerance > 0.0
        && config.orientation_tolerance > 0.0
        && config.damping >= 0.0)
    {
        return invalid("tolerances must be positive and damping non-negative".into());
    }
    Ok(())
}

/// For a floating mount solved over exactly its six coordinates the answer is a pose product.
fn solve_floating_base_exactly(
    robot: &Robot,
    group: &JointGroup,
    link: LinkId,
    target: &Pose,
    seed: &[f64],
    accept: &mut dyn FnMut(&[f64]) -> bool,
) -> Option<Result<Vec<f64>, IkError>> {
    if *robot.mount() != Mount::Floating || group.coordinates != [0, 1, 2, 3, 4, 5] {
        return None;
    }
    let root_to_link = relative_pose(&robot.mount().root_pose(seed), &robot.link_pose(seed, link));
    let root = target * root_to_link.inverse();
    let mut solution = seed.to_vec();
    robot.mount().write_coordinates(&root, &mut solution);
    if accept(&solution) {
        return Some(Ok(solution));
    }
    let reached = pose_error(&robot.link_pose(&solution, link), target);
    let (position, orientation) = error_norms(&reached);
    Some(Err(IkError::NoSolution {
        link: robot.link_name(link).to_string(),
        attempts: 1,
        rejected: 1,
        best_position_error: position,
        best_orientation_error: orientation,
    }))
}

/// Scratch buffers reused across iterations and attempts: the hot loop does not allocate.
struct Solver<'a> {
    robot: &'a Robot,
    group: &'a JointGroup,
    link: LinkId,
    target: &'a Pose,
    config: &'a IkConfig,
    /// The links from the root to `link`: the only poses the error and the Jacobian read.
    chain: Vec<LinkId>,
    poses: Vec<Pose>,
    jacobian: Matrix6xX<f64>,
    step: Vec<f64>,
    /// Per group coordinate: at a limit and pushed past it by this iteration's step, so left out
    /// of the step (its column would otherwise be clamped away after the solve and stall it).
    blocked: Vec<bool>,
    candidate: Vec<f64>,
    /// Best (position, orientation) error seen, for the failure report.
    best: (f64, f64),
}

impl<'a> Solver<'a> {
    /// A solver for the last link of `chain` (the links from the root to it).
    fn new(
        robot: &'a Robot,
        group: &'a JointGroup,
        chain: Vec<LinkId>,
        target: &'a Pose,
        config: &'a IkConfig,
    ) -> Self {
        Solver {
            robot,
            group,
            link: *chain.last().unwrap_or(&0),
            target,
            config,
            chain,
            poses: vec![Pose::identity(); robot.link_count()],
            jacobian: Matrix6xX::zeros(robot.dof()),
            step: vec![0.0; group.coordinates.len()],
            blocked: vec![false; group.coordinates.len()],
            candidate: vec![0.0; robot.dof()],
            best: (f64::INFINITY, f64::INFINITY),
        }
    }

    fn clamp_group(&self, q: &mut [f64]) {
        for &index in &self.group.coordinates {
            let coordinate = &self.robot.coordinates[index];
            match coordinate.kind {
                CoordinateKind::Linear | CoordinateKind::Angle => {
                    q[index] = q[index].clamp(coordinate.lower, coordinate.upper)
                }
                CoordinateKind::WrappedAngle => {
                    q[index] = crate::configuration::wrap_angle(q[index])
                }
                // Rotation vectors stay canonical through `integrate_sparse`.
                CoordinateKind::Rotation(_) => {}
            }
        }
    }

    fn error_at(&mut self, q: &[f64]) -> Vector6<f64> {
        self.robot.forward_kinematics_chain(q, &self.chain, &mut self.poses);
        pose_error(&self.poses[self.link], self.target)
    }

    fn converged(&mut self, error: &Vector6<f64>) -> bool {
        let (position, orientation) = error_norms(error);
        if position * position + orientation * orientation
            < self.best.0 * self.best.0 + self.best.1 * self.best.1
        {
            self.best = (position, orientation);
        }
        position <= self.config.position_tolerance
            && orientation <= self.config.orientation_tolerance
    }

    /// One attempt from `q`; on success `q` holds the solution.
    fn run(&mut self, q: &mut [f64]) -> bool {
        let mut error = self.error_at(q);
        let mut damping = self.config.damping.max(MINIMUM_DAMPING);
        for _ in 0..self.config.max_iterations {
            if self.converged(&error) {
                return true;
            }
            // `poses` holds the FK of `q` here: every rejected candidate is followed by a re-evaluation.
            self.robot.jacobian_into(&self.poses, self.link, &mut self.jacobian);
            self.blocked.fill(false);
            self.damped_step(&error, damping);
            while self.block_outward(q) {
                self.damped_step(&error, damping);
            }
            self.candidate.copy_from_slice(q);
            self.robot.integrate_sparse(&mut self.candidate, &self.group.coordinates, &self.step);
            let mut candidate = std::mem::take(&mut self.candidate);
            self.clamp_group(&mut candidate);
            let candidate_error = self.error_at(&candidate);
            if candidate_error.norm_squared() < error.norm_squared() {
                q.copy_from_slice(&candidate);
                error = candidate_error;
                damping = (damping * DAMPING_DECREASE).max(MINIMUM_DAMPING);
            } else {
                damping *= DAMPING_INCREASE;
                // Restore the poses of `q` for the next Jacobian.
                self.robot.forward_kinematics_chain(q, &self.chain, &mut self.poses);
                if damping > MAXIMUM_DAMPING {
                    self.candidate = candidate;
                    return false;
                }
            }
            self.candidate = candidate;
        }
        self.converged(&error)
    }

    /// Marks the coordinates that sit at a limit and that the step pushes past it; true if any
    /// was newly marked (the step must then be solved again without them).
    fn block_outward(&mut self, q: &[f64]) -> bool {
        let mut changed = false;
        for (slot, &index) in self.group.coordinates.iter().enumerate() {
            let coordinate = &self.robot.coordinates[index];
            if self.blocked[slot]
                || !matches!(coordinate.kind, CoordinateKind::Linear | CoordinateKind::Angle)
            {
                continue;
            }
            let step = self.step[slot];
            let at_lower = q[index] <= coordinate.lower + LIMIT_SLACK && step < 0.0;
            let at_upper = q[index] >= coordinate.upper - LIMIT_SLACK && step > 0.0;
            if at_lower || at_upper {
                self.blocked[slot] = true;
                changed = true;
            }
        }
        changed
    }

    /// `step = Jᵀ (J Jᵀ + λ² I)⁻¹ e` over the group's unblocked columns, scaled to at most
    /// [`MAXIMUM_STEP`].
    fn damped_step(&mut self, error: &Vector6<f64>, damping: f64) {
        let mut normal = Matrix6::identity() * (damping * damping);
        for (slot, &index) in self.group.coordinates.iter().enumerate() {
            if self.blocked[slot] {
                continue;
            }
            let column = self.jacobian.fixed_view::<6, 1>(0, index);
            normal += column * column.transpose();
        }
        let solved = match normal.cholesky() {
            Some(cholesky) => cholesky.solve(error),
            None => Vector6::zeros(),
        };
        let mut largest: f64 = 0.0;
        for ((slot, &index), &blocked) in
            self.step.iter_mut().zip(&self.group.coordinates).zip(&self.blocked)
        {
            *slot =
                if blocked { 0.0 } else { self.jacobian.fixed_view::<6, 1>(0, index).dot(&solved) };
            largest = largest.max(slot.abs());
        }
        if largest > MAXIMUM_STEP {
            let scale = MAXIMUM_STEP / largest;
            self.step.iter_mut().for_each(|slot| *slot *= scale);
        }
    }
}

/// The position and orientation error between a link pose and a target (for callers' reports).
pub fn pose_error_norms(current: &Pose, target: &Pose) -> (f64, f64) {
    error_norms(&pose_error(current, target))
}
