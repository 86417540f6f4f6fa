//! Motion planning for a robot of a scene: RRT-Connect in the configuration space of one joint
//! group (the arm, the base, or a free-flying body), with the rest of the robot held still and
//! the held object carried along.
//!
//! Edges are checked at a stated resolution: no coordinate moves more than `linear_resolution`
//! metres or `angular_resolution` radians between two checked states (a rotation counts by its
//! geodesic angle). Recorded paths use the same resolution.

use std::time::Duration;

use lamp_robot::{CoordinateKind, JointGroup, Robot, wrap_angle};
use lamp_rrt::{
    MAX_EDGE_STEPS, RrtConfig, RrtError, RrtStats, Space, edge_check_order, rrt_connect,
};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::scene::Scene;

/// Default checking resolution for lengths: 5 mm.
pub const DEFAULT_LINEAR_RESOLUTION: f64 = 0.005;
/// Default checking resolution for angles: 0.01 rad (about 0.6°).
pub const DEFAULT_ANGULAR_RESOLUTION: f64 = 0.01;
/// Unbounded coordinates (a mobile base's x, y) are sampled this far around start and goal.
pub const FREE_SAMPLING_MARGIN: f64 = 1.5;

/// How far a coordinate outside the moving group may differ between start and goal and still
/// count as held still: rounding, far below any checking resolution.
const HELD_STILL_TOLERANCE: f64 = 1e-9;

/// How to plan one motion.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionConfig {
    pub linear_resolution: f64,
    pub angular_resolution: f64,
    pub rrt: RrtConfig,
}

impl Default for MotionConfig {
    fn default() -> Self {
        MotionConfig {
            linear_resolution: DEFAULT_LINEAR_RESOLUTION,
            angular_resolution: DEFAULT_ANGULAR_RESOLUTION,
            rrt: RrtConfig {
                step: 0.5,
                max_iterations: 4_000,
                timeout: Some(Duration::from_secs(10)),
                shortcut_attempts: 60,
            },
        }
    }
}

/// Why a motion could not be planned.
#[derive(Clone, Debug, PartialEq, thiserror::Error, miette::Diagnostic)]
pub enum MotionError {
    #[error("robot `{robot}` has no joint group `{group}`")]
    #[diagnostic(code(lamp::motion::unknown_group))]
    UnknownGroup { robot: String, group: String },
    #[error("there is no robot {robot} in the scene")]
    #[diagnostic(code(lamp::motion::unknown_robot))]
    UnknownRobot { robot: usize },
    #[error("start and goal differ outside group `{group}` (coordinate `{coordinate}`)")]
    #[diagnostic(code(lamp::motion::outside_group))]
    OutsideGroup { group: String, coordinate: String },
    #[error(transparent)]
    #[diagnostic(transparent)]
    Planning(#[from] RrtError),
    #[error(
        "a straight move of {distance} needs {steps} states at the checking resolution, more than the {limit} one edge may have"
    )]
    #[diagnostic(
        code(lamp::motion::too_many_steps),
        help(
            "The robot would travel absurdly far in one move: check where the problem places the robot and the objects, and the units of the motion planner's `resolution`."
        )
    )]
    TooManySteps {
        /// How far the move goes, with its unit ("99999 m", "3.1 rad").
        distance: String,
        /// The states it would need (rounded up; may exceed any integer type).
        steps: f64,
        limit: usize,
    },
}

/// A planned path: waypoints joined by valid straight edges.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionPlan {
    pub waypoints: Vec<Vec<f64>>,
    pub stats: RrtStats,
}

/// The configuration space of one group of a robot in a scene.
pub struct RobotSpace<'a> {
    scene: &'a Scene,
    robot_index: usize,
    robot: &'a Robot,
    group: &'a JointGroup,
    reference: Vec<f64>,
    /// Which links the group moves; the others are checked once, at the start.
    moving: Vec<bool>,
    start_is_valid: bool,
    /// Sampling bounds for unbounded linear coordinates of the group.
    free_bounds: Vec<(usize, f64, f64)>,
    linear_resolution: f64,
    angular_resolution: f64,
}

impl<'a> RobotSpace<'a> {
    /// The space of `group` for robot `robot_index`, between `start` and `goal`.
    pub fn new(
        scene: &'a Scene,
        robot_index: usize,
        group_name: &str,
        start: &[f64],
        goal: &[f64],
        config: &MotionConfig,
    ) -> Result<RobotSpace<'a>, MotionError> {
        let state = scene
            .robots
            .get(robot_index)
            .ok_or(MotionError::UnknownRobot { robot: robot_index })?;
        let robot: &Robot = &state.robot;
        let group = robot.group(group_name).ok_or_else(|| MotionError::UnknownGroup {
            robot: state.name.clone(),
            group: group_name.to_string(),
        })?;
        for (index, name) in robot.coordinate_names().iter().enumerate() {
            if !group.coordinates.contains(&index)
                && (start[index] - goal[index]).abs() > HELD_STILL_TOLERANCE
            {
                return Err(MotionError::OutsideGroup {
                    group: group_name.to_string(),
                    coordinate: name.clone(),
                });
            }
        }
        let free_bounds = group
            .coordinates
            .iter()
            .filter_map(|&index| {
                let coordinate = &robot.coordinates()[index];
                let unbounded = !(coordinate.lower.is_finite() && coordinate.upper.is_finite());
                (coordinate.kind == CoordinateKind::Linear && unbounded).then(|| {
                    let low = start[index].min(goal[index]) - FREE_SAMPLING_MARGIN;
                    let high = start[index].max(goal[index]) + FREE_SAMPLING_MARGIN;
                    (index, low.max(coordinate.lower), high.min(coordinate.upper))
                })
            })
            .collect();
        Ok(RobotSpace {
            scene,
            robot_index,
            robot,
            group,
            reference: start.to_vec(),
            moving: scene.moving_links(robot_index, &group.coordinates),
            start_is_valid: scene.is_valid(robot_index, start),
            free_bounds,
            linear_resolution: config.linear_resolution,
            angular_resolution: config.angular_resolution,
        })
    }
}

impl Space for RobotSpace<'_> {
    fn sample(&self, rng: &mut ChaCha8Rng, out: &mut [f64]) {
        self.robot.sample_uniform(self.group, &self.reference, rng, out);
        for &(index, low, high) in &self.free_bounds {
            out[index] = low + (high - low) * rng.random::<f64>();
        }
    }

    fn distance(&self, a: &[f64], b: &[f64]) -> f64 {
        self.robot.distance(a, b)
    }

    fn distance_form(&self, q: &[f64]) -> Vec<f64> {
        self.robot.distance_form(q)
    }

    fn nearest(&self, forms: &[Vec<f64>], form: &[f64]) -> usize {
        self.robot.nearest_form(forms, form)
    }

    fn interpolate(&self, a: &[f64], b: &[f64], t: f64, out: &mut [f64]) {
        self.robot.interpolate(a, b, t, out);
    }

    fn is_valid(&self, q: &[f64]) -> bool {
        // Links the group does not move are where they were at the start: when the start is
        // valid their checks cannot change, so only the moving ones are repeated.
        let moving = self.start_is_valid.then_some(self.moving.as_slice());
        self.scene.first_contact_of_moving(self.robot_index, q, moving).is_none()
    }

    fn edge_steps(&self, a: &[f64], b: &[f64]) -> usize {
        edge_steps(self.robot, a, b, self.linear_resolution, self.angular_resolution)
    }

    /// The states of an edge are independent checks, so the threads of the rayon pool share
    /// them (in chunks of at least [`PARALLEL_EDGE_CHUNK`] states, middle first as in sequence):
    /// the answer is the same on any number of threads, only sooner.
    fn edge_is_valid(&self, a: &[f64], b: &[f64]) -> bool {
        let steps = self.edge_steps(a, b);
        if steps > MAX_EDGE_STEPS {
            return false;
        }
        let order = edge_check_order(steps);
        if order.len() < 2 * PARALLEL_EDGE_CHUNK {
            let mut q = a.to_vec();
            return order.into_iter().all(|i| {
                self.interpolate(a, b, i as f64 / steps as f64, &mut q);
                self.is_valid(&q)
            });
        }
        order
            .par_iter()
            .with_min_len(PARALLEL_EDGE_CHUNK)
            .try_for_each_init(
                || a.to_vec(),
                |q, &i| {
                    self.interpolate(a, b, i as f64 / steps as f64, q);
                    if self.is_valid(q) { Ok(()) } else { Err(()) }
                },
            )
            .is_ok()
    }
}

/// The fewest states of an edge one thread checks: a state's check takes about 2 µs, and waking
/// another thread for it tens of µs. With chunks of 4 states, two threads were no faster than
/// one on Café's `cafe18_01`; with 16 or 32, they save an eighth of its solve.
const PARALLEL_EDGE_CHUNK: usize = 32;

/// Sub-steps needed between `a` and `b` so that no coordinate moves more than the resolution,
/// at most [`MAX_EDGE_STEPS`] + 1 (more cannot be checked or recorded; [`checked_edge_steps`]
/// says so, and edge checks find such an edge invalid).
pub fn edge_steps(robot: &Robot, a: &[f64], b: &[f64], linear: f64, angular: f64) -> usize {
    let (steps, _) = needed_steps(robot, a, b, linear, angular);
    // Bounded: at most MAX_EDGE_STEPS + 1 (NaN, from a NaN coordinate, becomes that too).
    if steps <= MAX_EDGE_STEPS as f64 { steps as usize } else { MAX_EDGE_STEPS + 1 }
}

/// [`edge_steps`], or [`MotionError::TooManySteps`] when the edge needs more than
/// [`MAX_EDGE_STEPS`].
pub fn checked_edge_steps(
    robot: &Robot,
    a: &[f64],
    b: &[f64],
    linear: f64,
    angular: f64,
) -> Result<usize, MotionError> {
    let (steps, widest) = needed_steps(robot, a, b, linear, angular);
    if steps <= MAX_EDGE_STEPS as f64 {
        // Whole and within MAX_EDGE_STEPS.
        return Ok(steps as usize);
    }
    Err(MotionError::TooManySteps { distance: widest, steps, limit: MAX_EDGE_STEPS })
}

/// The sub-steps an edge needs (a whole number of at least 1, not capped) and the move that
/// needs the most, with its unit, for messages.
fn needed_steps(robot: &Robot, a: &[f64], b: &[f64], linear: f64, angular: f64) -> (f64, String) {
    let mut steps: f64 = 1.0;
    let mut widest = String::new();
    for (index, coordinate) in robot.coordinates().iter().enumerate() {
        let (distance, resolution, unit) = match coordinate.kind {
            CoordinateKind::Linear => ((b[index] - a[index]).abs(), linear, "m"),
            CoordinateKind::Angle => ((b[index] - a[index]).abs(), angular, "rad"),
            CoordinateKind::WrappedAngle => (wrap_angle(b[index] - a[index]).abs(), angular, "rad"),
            CoordinateKind::Rotation(0) => {
                let ra = nalgebra::UnitQuaternion::from_scaled_axis(nalgebra::Vector3::new(
                    a[index],
                    a[index + 1],
                    a[index + 2],
                ));
                let rb = nalgebra::UnitQuaternion::from_scaled_axis(nalgebra::Vector3::new(
                    b[index],
                    b[index + 1],
                    b[index + 2],
                ));
                (ra.angle_to(&rb), angular, "rad")
            }
            CoordinateKind::Rotation(_) => continue,
        };
        let needed = (distance / resolution).ceil();
        // A NaN (from a NaN coordinate) is taken too, and then refuses the edge.
        if needed.is_nan() || needed > steps {
            steps = needed;
            widest = format!("{distance:.3} {unit}");
        }
    }
    (steps, widest)
}

/// Plans a collision-free path for `group` of robot `robot` from `start` to `goal`, carrying what
/// the robot holds now.
pub fn plan_motion(
    scene: &Scene,
    robot: usize,
    group: &str,
    start: &[f64],
    goal: &[f64],
    config: &MotionConfig,
    rng: &mut ChaCha8Rng,
) -> Result<MotionPlan, MotionError> {
    let space = RobotSpace::new(scene, robot, group, start, goal, config)?;
    let (waypoints, stats) = rrt_connect(&space, start, goal, &config.rrt, rng)?;
    Ok(MotionPlan { waypoints, stats })
}

/// Every state along the path at the checking resolution, endpoints included: what a robot
/// controller would step through, and what validation checks.
///
/// # Errors
/// [`MotionError::TooManySteps`] when an edge needs more than [`MAX_EDGE_STEPS`] states.
pub fn densify(
    robot: &Robot,
    waypoints: &[Vec<f64>],
    config: &MotionConfig,
) -> Result<Vec<Vec<f64>>, MotionError> {
    let Some(first) = waypoints.first() else { return Ok(Vec::new()) };
    let mut states = vec![first.clone()];
    for pair in waypoints.windows(2) {
        let steps = checked_edge_steps(
            robot,
            &pair[0],
            &pair[1],
            config.linear_resolution,
            config.angular_resolution,
        )?;
        for i in 1..steps {
            let mut q = pair[0].clone();
            robot.interpolate(&pair[0], &pair[1], i as f64 / steps as f64, &mut q);
            states.push(q);
        }
        // The waypoint itself, not `a + 1 · (b − a)`, which may differ from it in the last
        // bit: the state recorded last is the one the scene is left in, and an object let go
        // of there must settle where the replay settles it.
        states.push(pair[1].clone());
    }
    Ok(states)
}
