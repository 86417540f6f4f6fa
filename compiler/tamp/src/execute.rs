//! Carrying out one candidate in a scene: open the fingers and let go, move along a planned path,
//! take hold and close the fingers (or, without fingers, come to contact and take hold); every
//! visited state recorded at the checking resolution,
//! every motion checked state by state.

use lamp_plugin_api::{
    Candidate, GraspChange, HostServices, MotionOutcome, MotionPlanner, MotionRequest,
    NoPathReason, RobotTarget,
};
use lamp_robot::{IkConfig, Mount, Robot};
use lamp_world::{
    ApproachKind, FingerMove, LinkGoal, MotionConfig, Recorder, RobotSpace, Scene,
    contact_approach, densify, finger_path, straight_line,
};
use nalgebra::Translation3;

use crate::error::SolveError;
use crate::failures::Cause;
use crate::host::GroupHost;
use crate::settings::SolveSettings;

/// Why a candidate was rejected (the search tries another), or a hard error.
pub enum Rejection {
    /// Try the next candidate: why this one failed, and the message that says it best.
    Candidate { cause: Cause, why: String },
    /// The candidate lets go of `object` where nothing holds it up yet (`reason`). Every candidate
    /// of the step does the same, since the object is let go of before anything moves.
    Unsupported { object: String, reason: String },
    /// Stop solving.
    Fatal(SolveError),
}

impl Rejection {
    /// A refusal for an error whose message says it all.
    fn candidate(error: &dyn std::fmt::Display) -> Self {
        Rejection::because(Cause::Other { reason: error.to_string() })
    }

    /// A refusal for `cause`, which says it best.
    fn because(cause: Cause) -> Self {
        let why = cause.to_string();
        Rejection::Candidate { cause, why }
    }
}

impl From<SolveError> for Rejection {
    fn from(error: SolveError) -> Self {
        Rejection::Fatal(error)
    }
}

/// Counts of the motion planner's work.
#[derive(Clone, Copy, Debug, Default)]
pub struct MotionCounts {
    pub calls: usize,
    pub failures: usize,
}

/// Configurations closer than this (in the robot's configuration distance), or coordinates that
/// differ by less, are the same: rounding, with nothing to move.
const SAME_CONFIGURATION: f64 = 1e-12;
/// How close a motion planner's path must begin and end to the start and goal asked for (in the
/// robot's configuration distance): its ends are copies of them, up to the rounding of a plugin's
/// arithmetic and the wire's JSON.
const PATH_END_TOLERANCE: f64 = 1e-9;
/// How close to the goal's gripper pose a straight line must end (metres, radians): 0.1 mm and
/// 0.001 rad, well inside any learned region, looser than the default IK so that the line is not
/// refused for the last micrometre.
const STRAIGHT_POSITION_TOLERANCE: f64 = 1e-4;
const STRAIGHT_ORIENTATION_TOLERANCE: f64 = 1e-3;

/// Applies `candidate` to `scene`, recording every state into `recorder`.
pub fn execute(
    scene: &mut Scene,
    candidate: &Candidate,
    recorder: &mut Recorder,
    motion: &mut dyn MotionPlanner,
    settings: &SolveSettings<'_>,
    seed: u64,
    counts: &mut MotionCounts,
) -> Result<(), Rejection> {
    let planning = Planning { motion, settings, counts };
    let mut execution = Execution { scene, recorder, planning, seed };
    for change in &candidate.releases {
        execution.release(change)?;
    }
    for (offset, target) in candidate.targets.iter().enumerate() {
        execution.move_to(offset, target)?;
    }
    for change in &candidate.grabs {
        execution.grab(change)?;
    }
    Ok(())
}

/// What carrying out one candidate works with.
struct Execution<'e, 's> {
    scene: &'e mut Scene,
    recorder: &'e mut Recorder,
    planning: Planning<'e, 's>,
    seed: u64,
}

/// The motion planner with what its calls are made with and counted in.
struct Planning<'e, 's> {
    motion: &'e mut dyn MotionPlanner,
    settings: &'e SolveSettings<'s>,
    counts: &'e mut MotionCounts,
}

impl Execution<'_, '_> {
    fn robot_index(&self, name: &str) -> Result<usize, Rejection> {
        self.scene.robot_index(name).ok_or_else(|| {
            Rejection::Fatal(SolveError::PluginAnswer {
                kind: "refiner",
                reason: format!("it names robot `{name}`, which is not in the scene"),
            })
        })
    }

    /// Opens the fingers on the object `change` names and lets go of it, where it rests.
    fn release(&mut self, change: &GraspChange) -> Result<(), Rejection> {
        let robot = self.robot_index(&change.robot)?;
        let scene = &mut *self.scene;
        let held = scene.held(robot).map(|held| scene.bodies()[held.body].name.clone());
        if held.as_deref() != Some(change.object.as_str()) {
            return Err(Rejection::because(Cause::Other {
                reason: format!("`{}` does not hold `{}`", change.robot, change.object),
            }));
        }
        if let Some(body) = scene.held(robot).map(|held| held.body) {
            self.recorder.confirm_put_down(robot, body);
        }
        // The fingers open while they still hold the object (they may touch it, nothing else),
        // then it is let go.
        let opening =
            finger_path(scene, robot, FingerMove::Open, &self.planning.settings.motion.config)
                .map_err(|error| Rejection::candidate(&error))?;
        if opening.len() > 1 {
            self.recorder.follow(scene, robot, &opening);
        }
        scene.release_at_rest(robot).map_err(|error| match error.lacks_support() {
            Some(object) => {
                Rejection::Unsupported { object: object.to_string(), reason: error.to_string() }
            }
            None => Rejection::candidate(&error),
        })?;
        self.recorder.record(scene);
        Ok(())
    }

    /// Moves a robot to `target` (the candidate's `offset`-th), along a straight line where
    /// one is free, else along the motion planner's path, checked state by state.
    fn move_to(&mut self, offset: usize, target: &RobotTarget) -> Result<(), Rejection> {
        let robot = self.robot_index(&target.robot)?;
        let config = &self.planning.settings.motion.config;
        let model = self.scene.robots()[robot].robot().clone();
        let start = self.scene.robots()[robot].configuration().to_vec();
        if target.configuration.len() != start.len() {
            return Err(Rejection::Fatal(SolveError::PluginAnswer {
                kind: "refiner",
                reason: format!(
                    "a target of `{}` has {} coordinates",
                    target.robot,
                    target.configuration.len()
                ),
            }));
        }
        // The fingers move only at grasp changes: a target keeps them where they are (closed on
        // a held object, open otherwise), whatever finger values the refiner gave.
        let mut goal = target.configuration.clone();
        for &(finger, _) in self.scene.robots()[robot].open_fingers() {
            goal[finger] = start[finger];
        }
        let goal = &goal;
        if model.distance(&start, goal) < SAME_CONFIGURATION {
            return Ok(());
        }
        let group = motion_group(&model, &start, goal);
        let request = MotionRequest {
            robot: target.robot.clone(),
            start: start.clone(),
            goal: goal.clone(),
            budget: self.planning.settings.motion.budget,
            seed: self.seed.wrapping_add(offset as u64),
        };
        // A carry leaves its support straight up and comes down onto its place straight down,
        // as a robot picks and places: a path that slides the object along what it stood on, or
        // skims a wall on the way down, is collision-free only at the world's zero clearance.
        let carrying = self.scene.held(robot).is_some();
        let carried = if carrying {
            let space = RobotSpace::new(self.scene, robot, group, &start, goal, config)
                .map_err(|error| Rejection::candidate(&error))?;
            let host =
                GroupHost::new(&target.robot, &model, space, self.planning.settings.cancelled);
            let ends = Lifted { scene: self.scene, robot, group, start: &start, goal };
            ends.plan(self.planning.motion, &request, &host, config, self.planning.counts)?
        } else {
            None
        };
        let waypoints = match carried {
            Some(LiftedPath { waypoints, descent: Some(descent) }) => {
                self.follow_path(robot, &model, &waypoints, (&start, goal))?;
                self.note_descent(robot, &model, &waypoints[descent..]);
                return Ok(());
            }
            Some(LiftedPath { waypoints, descent: None }) => waypoints,
            None => {
                if let Some(path) = straight_first(self.scene, robot, group, &start, goal, config) {
                    let states = densify(&model, &path, config)
                        .map_err(|error| Rejection::candidate(&error))?;
                    self.recorder.follow(self.scene, robot, &states);
                    self.scene.set_configuration(robot, states.last().unwrap_or(&start));
                    return Ok(());
                }
                let ends = Lifted { scene: self.scene, robot, group, start: &start, goal };
                self.planning.plan_path(&ends, &model, &request, carrying)?
            }
        };
        self.follow_path(robot, &model, &waypoints, (&start, goal))
    }

    /// Notes the straight `descent` that ends the carry just recorded (its waypoints, the last
    /// where the recording ends): a put-down if the object is let go of there.
    fn note_descent(&mut self, robot: usize, model: &Robot, descent: &[Vec<f64>]) {
        let config = &self.planning.settings.motion.config;
        let (Some(held), Ok(states)) = (self.scene.held(robot), densify(model, descent, config))
        else {
            return;
        };
        // The descent's states are the recording's last ones.
        let from_step = self.recorder.len().saturating_sub(states.len());
        let metres = gripper_travel(self.scene, robot, descent);
        self.recorder.note_descent(from_step, robot, held.body, metres);
    }

    /// Follows a motion planner's `waypoints` from the first to the second of `ends`, densified
    /// to the checking resolution and checked state by state, and records it.
    fn follow_path(
        &mut self,
        robot: usize,
        model: &Robot,
        waypoints: &[Vec<f64>],
        ends: (&[f64], &[f64]),
    ) -> Result<(), Rejection> {
        let (start, goal) = ends;
        if let Some(reason) = malformed_waypoint(waypoints, start.len()) {
            return Err(bad_path(&reason));
        }
        let states = densify(model, waypoints, &self.planning.settings.motion.config)
            .map_err(|error| Rejection::candidate(&error))?;
        let joins = |a: &[f64], b: &[f64]| model.distance(a, b) < PATH_END_TOLERANCE;
        let (Some(first), Some(last)) = (states.first(), states.last().cloned()) else {
            return Err(bad_path("it is empty"));
        };
        if !joins(first, start) || !joins(&last, goal) {
            return Err(bad_path("it does not run from the start to the goal"));
        }
        for (index, q) in states.iter().enumerate() {
            // Up to MAX_EDGE_STEPS states per edge, each a collision check: poll on the way.
            if (self.planning.settings.cancelled)() {
                return Err(Rejection::Fatal(SolveError::cancelled()));
            }
            if !self.scene.is_valid(robot, q) {
                return Err(bad_path(&format!("its state {index} collides or leaves the limits")));
            }
        }
        self.recorder.follow(self.scene, robot, &states);
        // Where the recording ends (within PATH_END_TOLERANCE of the goal), so that what
        // happens next, an object let go of and settled, happens as the replay will see it.
        self.scene.set_configuration(robot, &last);
        Ok(())
    }

    /// Takes hold of the object `change` names, within the grab range (coming to contact first
    /// with a gripper that holds by contact), and closes the fingers on it.
    fn grab(&mut self, change: &GraspChange) -> Result<(), Rejection> {
        let robot = self.robot_index(&change.robot)?;
        let config = &self.planning.settings.motion.config;
        let scene = &mut *self.scene;
        let Some(body) = scene.body_index(&change.object) else {
            return Err(Rejection::because(Cause::Other {
                reason: format!("no body `{}`", change.object),
            }));
        };
        // Where the approach to contact begins and how long it is; it ends where the gripper
        // takes hold (none left when the motion there already ended in contact).
        let mut contact = None;
        // A magnet or a suction cup holds only what it touches: it comes straight to the object
        // first (fingers close after the grab instead).
        if scene.holds_by_contact(robot) {
            let approach = contact_approach(scene, robot, body, config).map_err(|error| {
                Rejection::Candidate {
                    cause: Cause::OutOfGrabRange { object: change.object.clone() },
                    why: error.to_string(),
                }
            })?;
            contact = Some((
                self.recorder.len().saturating_sub(1),
                gripper_travel(scene, robot, &approach),
            ));
            if let [_, .., last] = approach.as_slice() {
                self.recorder.follow(scene, robot, &approach);
                scene.set_configuration(robot, last);
            }
        }
        let reach =
            scene.gripper_pose(robot, scene.robots()[robot].configuration()).map(|gripper| {
                (gripper.translation.vector - scene.body_pose(body).translation.vector).norm()
            });
        let ranges = &self.planning.settings.motion.grab_ranges;
        if let (Some(distance), Some((_, (low, high)))) =
            (reach, ranges.iter().find(|(name, _)| name == &change.robot))
            && !(*low..=*high).contains(&distance)
        {
            return Err(Rejection::Candidate {
                cause: Cause::OutOfGrabRange { object: change.object.clone() },
                why: format!(
                    "`{}` is {distance:.3} m from the gripper, outside the grab range {low:.3}–{high:.3} m",
                    change.object
                ),
            });
        }
        scene.grab(robot, body).map_err(|error| Rejection::candidate(&error))?;
        // Lifted, the object would leave what rests on it hanging in the air.
        if let Err(left) = scene.rests_without(body) {
            return Err(Rejection::because(Cause::Other {
                reason: format!("taking `{}`: {left}", change.object),
            }));
        }
        self.recorder.record(scene);
        if let Some((from_step, metres)) = contact {
            self.recorder.mark_approach(from_step, robot, body, ApproachKind::Contact, metres);
        }
        // Held first, so that the fingers may touch the object as they close onto it.
        let closing = finger_path(scene, robot, FingerMove::Close, config)
            .map_err(|error| Rejection::candidate(&error))?;
        if closing.len() > 1 {
            self.recorder.follow(scene, robot, &closing);
        }
        Ok(())
    }
}

impl Planning<'_, '_> {
    /// The motion planner's path for `request` between `ends`; a free move it cannot plan is
    /// tried once more from above its ends. A refusal names what is in the way, if anything.
    fn plan_path(
        &mut self,
        ends: &Lifted<'_>,
        model: &Robot,
        request: &MotionRequest,
        carrying: bool,
    ) -> Result<Vec<Vec<f64>>, Rejection> {
        let Lifted { scene, robot, group, start, goal } = *ends;
        let config = &self.settings.motion.config;
        let space = RobotSpace::new(scene, robot, group, start, goal, config)
            .map_err(|error| Rejection::candidate(&error))?;
        let host = GroupHost::new(&request.robot, model, space, self.settings.cancelled);
        self.counts.calls += 1;
        let (reason, message) = match self.motion.plan_path(request, &host) {
            Ok(MotionOutcome::Path(waypoints)) => return Ok(waypoints),
            Ok(MotionOutcome::NoPath { reason, message }) => (reason, message),
            Err(error) => return Err(Rejection::Fatal(SolveError::from_plugin("motion", error))),
        };
        self.counts.failures += 1;
        // A carry was tried from above its ends already.
        if reason == NoPathReason::BudgetExhausted
            && !carrying
            && let Some(lifted) = ends.plan(self.motion, request, &host, config, self.counts)?
        {
            return Ok(lifted.waypoints);
        }
        let blocked = match reason {
            NoPathReason::StartInvalid => scene.first_contact(robot, start),
            NoPathReason::GoalInvalid => scene.first_contact(robot, goal),
            NoPathReason::BudgetExhausted | NoPathReason::Other => None,
        };
        let cause = match blocked {
            Some(contact) => Cause::of_contact(&request.robot, contact, scene),
            None => Cause::NoPath { robot: request.robot.clone(), group: group.to_string() },
        };
        let why = format!(
            "no {group} path for `{}` ({reason:?}{}{message})",
            request.robot,
            if message.is_empty() { "" } else { ": " }
        );
        Err(Rejection::Candidate { cause, why })
    }
}

/// What is wrong with a motion plugin's waypoint, if anything: a waypoint with another number of
/// coordinates than the robot has, or one that is not a number (NaN or infinite), which no
/// straight edge or collision check can make sense of.
fn malformed_waypoint(waypoints: &[Vec<f64>], coordinates: usize) -> Option<String> {
    waypoints.iter().enumerate().find_map(|(index, waypoint)| {
        if waypoint.len() != coordinates {
            return Some(format!(
                "its waypoint {index} has {} coordinates, and the robot has {coordinates}",
                waypoint.len()
            ));
        }
        let coordinate = waypoint.iter().position(|value| !value.is_finite())?;
        Some(format!(
            "its waypoint {index} has coordinate {coordinate} = {}, not a number a robot can take",
            waypoint[coordinate]
        ))
    })
}

fn bad_path(reason: &str) -> Rejection {
    Rejection::Fatal(SolveError::PluginAnswer {
        kind: "motion",
        reason: format!("it returned a path the world rejects: {reason}"),
    })
}

/// A straight line of the gripper from where it is to where `goal` puts it, when the arm moves
/// and the mount stays: the way into and out of a grasp among other objects, a narrow passage a
/// sampling planner rarely finds (and the way the demonstrations move there). `None` when the
/// line leaves the arm's reach, jumps or touches something; the motion planner then plans the
/// move. The line ends where IK puts the gripper within [`STRAIGHT_POSITION_TOLERANCE`] and
/// [`STRAIGHT_ORIENTATION_TOLERANCE`] of the goal's pose,
/// not necessarily at `goal` itself: the learned relations see link poses, not joint values.
fn straight_first(
    scene: &Scene,
    robot: usize,
    group: &str,
    start: &[f64],
    goal: &[f64],
    config: &MotionConfig,
) -> Option<Vec<Vec<f64>>> {
    let state = &scene.robots()[robot];
    let model = state.robot();
    if mount_moves(model, start, goal) {
        return None;
    }
    let link = state.gripper()?.link;
    let target = model.link_pose(goal, link);
    let ik = IkConfig {
        position_tolerance: STRAIGHT_POSITION_TOLERANCE,
        orientation_tolerance: STRAIGHT_ORIENTATION_TOLERANCE,
        ..IkConfig::new()
    };
    straight_line(
        scene,
        &LinkGoal { robot, group, link: Some(link), target: &target, start },
        config,
        &ik,
    )
    .ok()
}

/// How far straight up the gripper is lifted at each end of an arm motion the motion planner
/// did not find (metres): [`Lifted`].
pub const LIFT_HEIGHT: f64 = 0.1;

/// How far above everything around it a carried object is lifted at each end of a carry
/// (metres), when that is higher than [`LIFT_HEIGHT`]: a robot tracks its trajectory within
/// millimetres, and an object carried over a box's wall at the height of its rim hits it.
pub const CARRY_CLEARANCE: f64 = 0.02;

/// An arm motion planned again from above its ends: the gripper goes straight up
/// [`LIFT_HEIGHT`] from the start, the motion planner plans from there to the same height above
/// the goal, and the gripper comes straight down onto the goal.
///
/// An arm whose gripper is down among objects on a table (just let go of one, about to take
/// one, or holding one above its place) starts or ends in a narrow pocket: the fingers, the
/// wrist and the held object have room upwards and little else, and a sampling planner, whose
/// every extension is a step in a random direction, rarely finds the way out. Most of a sampled
/// motion's difficulty is there; above the objects the arm moves freely. An end that cannot be
/// lifted (out of reach, or something above it) is used as it is.
struct Lifted<'s> {
    scene: &'s Scene,
    robot: usize,
    group: &'s str,
    start: &'s [f64],
    goal: &'s [f64],
}

impl Lifted<'_> {
    /// The whole path from the start to the goal through the lifted ends, or `None` when
    /// neither end can be lifted, a mount other than a free-flying one moves (a mobile base), or
    /// the motion planner finds no path between the lifted ends either.
    fn plan(
        &self,
        motion: &mut dyn MotionPlanner,
        request: &MotionRequest,
        host: &dyn HostServices,
        config: &MotionConfig,
        counts: &mut MotionCounts,
    ) -> Result<Option<LiftedPath>, Rejection> {
        let model = self.scene.robots()[self.robot].robot();
        // A free-flying mount is the gripper's own motion, and lifts it like an arm.
        let free_flying = matches!(model.mount(), Mount::Floating);
        if mount_moves(model, self.start, self.goal) && !free_flying {
            return Ok(None);
        }
        let up = self.lift(self.start, config);
        let down = self.lift(self.goal, config);
        if up.is_none() && down.is_none() {
            return Ok(None);
        }
        let up = up.unwrap_or_else(|| vec![self.start.to_vec()]);
        let lowered = down.is_some();
        let mut down = down.unwrap_or_else(|| vec![self.goal.to_vec()]);
        down.reverse();
        let (Some(from), Some(to)) = (up.last(), down.first()) else { return Ok(None) };
        let lifted = MotionRequest {
            start: from.clone(),
            goal: to.clone(),
            seed: request.seed ^ LIFTED_SEED,
            ..request.clone()
        };
        counts.calls += 1;
        let middle = match motion.plan_path(&lifted, host) {
            Ok(MotionOutcome::Path(middle)) => middle,
            Ok(MotionOutcome::NoPath { .. }) => {
                counts.failures += 1;
                return Ok(None);
            }
            Err(error) => return Err(Rejection::Fatal(SolveError::from_plugin("motion", error))),
        };
        // The middle path begins and ends at copies of the lifted ends (up to the plugin's
        // rounding): the lines' own ends are kept, and the middle's dropped.
        let inner = middle.len().saturating_sub(1);
        let mut path = up;
        path.extend(middle.into_iter().take(inner).skip(1));
        let descent = lowered.then_some(path.len());
        path.extend(down);
        Ok(Some(LiftedPath { waypoints: path, descent }))
    }

    /// The straight line of the gripper from `from` up [`LIFT_HEIGHT`], with the mount still;
    /// `None` when it cannot be made.
    fn lift(&self, from: &[f64], config: &MotionConfig) -> Option<Vec<Vec<f64>>> {
        let state = &self.scene.robots()[self.robot];
        let model = state.robot();
        let gripper = state.gripper()?;
        let link = gripper.link;
        let at = model.link_pose(from, link);
        // A carried object rises clear of what is around it, a box's walls included.
        let height = gripper.held.map_or(LIFT_HEIGHT, |held| {
            let rise = self.scene.rise_to_clear(held.body, &(at * held.grasp), CARRY_CLEARANCE);
            rise.max(LIFT_HEIGHT)
        });
        let target = Translation3::new(0.0, 0.0, height) * at;
        let goal = LinkGoal {
            robot: self.robot,
            group: self.group,
            link: Some(link),
            target: &target,
            start: from,
        };
        straight_line(self.scene, &goal, config, &IkConfig::new()).ok()
    }
}

/// A path through lifted ends.
struct LiftedPath {
    waypoints: Vec<Vec<f64>>,
    /// The waypoint where the straight descent onto the goal begins, when the goal was lifted.
    descent: Option<usize>,
}

/// How far the gripper of `robot` travels along `waypoints`, point to point, in metres.
fn gripper_travel(scene: &Scene, robot: usize, waypoints: &[Vec<f64>]) -> f64 {
    let positions: Vec<_> = waypoints
        .iter()
        .filter_map(|q| scene.gripper_pose(robot, q))
        .map(|pose| pose.translation.vector)
        .collect();
    positions.windows(2).fold(0.0, |travel, pair| travel + (pair[1] - pair[0]).norm())
}

/// Whether any of the mount's coordinates (a mobile base, a free-flying gripper) differs between
/// `start` and `goal`: then the move is no arm motion, and no straight line applies, nor a lift
/// unless the mount is free-flying (its motion is the gripper's own).
fn mount_moves(model: &Robot, start: &[f64], goal: &[f64]) -> bool {
    let mount = model.mount().coordinate_count();
    (0..mount).any(|index| (start[index] - goal[index]).abs() > SAME_CONFIGURATION)
}

/// Mixed into a motion's seed for its lifted attempt, so that it samples anew.
const LIFTED_SEED: u64 = 0x11F7_5EED;

/// The smallest joint group that holds every coordinate that changes from `start` to `goal`.
fn motion_group<'r>(robot: &'r Robot, start: &[f64], goal: &[f64]) -> &'r str {
    let changed: Vec<usize> = (0..start.len())
        .filter(|&index| (start[index] - goal[index]).abs() > SAME_CONFIGURATION)
        .collect();
    let mut groups: Vec<_> = robot
        .groups()
        .filter(|group| changed.iter().all(|index| group.coordinates.contains(index)))
        .collect();
    groups.sort_by_key(|group| (group.coordinates.len(), group.name.clone()));
    groups.first().map_or(lamp_robot::ALL_GROUP, |group| group.name.as_str())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A motion plugin's NaN, infinite or short waypoint is named, with its index and coordinate,
    /// instead of surfacing as a straight move of NaN rad.
    #[test]
    fn a_waypoint_that_is_not_a_configuration_is_named() {
        let good = vec![vec![0.0, 1.0], vec![0.5, 1.5]];
        assert_eq!(malformed_waypoint(&good, 2), None);
        let not_a_number = vec![vec![0.0, 1.0], vec![f64::NAN, 1.5]];
        assert_eq!(
            malformed_waypoint(&not_a_number, 2).as_deref(),
            Some("its waypoint 1 has coordinate 0 = NaN, not a number a robot can take")
        );
        let infinite = vec![vec![0.0, f64::INFINITY]];
        assert_eq!(
            malformed_waypoint(&infinite, 2).as_deref(),
            Some("its waypoint 0 has coordinate 1 = inf, not a number a robot can take")
        );
        assert_eq!(
            malformed_waypoint(&[vec![0.0]], 2).as_deref(),
            Some("its waypoint 0 has 1 coordinates, and the robot has 2")
        );
    }
}
