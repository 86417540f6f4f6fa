//! A 2-D maze host for the planner's tests: a disc robot at [x, y] in a 10 m square, walls of
//! unit squares, uniform sampling in the square, and edges checked by fine sub-stepping.

// Each test binary uses its own part of this module.
#![allow(dead_code)]

use lamp_plugin_api::{HostError, HostServices, MotionBudget, MotionRequest};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub const ROBOT: &str = "disc";
pub const SIZE: f64 = 10.0;
/// Edges are checked every centimetre, far finer than the planner's 0.3 step.
pub const EDGE_RESOLUTION: f64 = 0.01;

/// Axis-aligned unit squares, by their lower-left corners.
#[derive(Clone, Debug)]
pub struct Maze {
    squares: Vec<[f64; 2]>,
}

impl Maze {
    /// Two walls to weave through: one at x = 3 from the floor up to y = 8, one at x = 6 from
    /// y = 2 up to the top. The straight line from (1, 1) to (9, 9) crosses both.
    pub fn two_walls() -> Self {
        let first = (0..8).map(|row| [3.0, f64::from(row)]);
        let second = (2..10).map(|row| [6.0, f64::from(row)]);
        Self { squares: first.chain(second).collect() }
    }

    /// A corridor one square wide that zig-zags across the room four times: hard for a small
    /// iteration budget.
    pub fn serpentine() -> Self {
        let mut squares = Vec::new();
        for (column, gap_at_top) in [(2, true), (4, false), (6, true), (8, false)] {
            let rows = if gap_at_top { 0..9 } else { 1..10 };
            squares.extend(rows.map(|row| [f64::from(column), f64::from(row)]));
        }
        Self { squares }
    }

    fn free(&self, q: &[f64]) -> bool {
        q.len() == 2
            && q.iter().all(|coordinate| (0.0..=SIZE).contains(coordinate))
            && !self.squares.iter().any(|corner| {
                (corner[0]..=corner[0] + 1.0).contains(&q[0])
                    && (corner[1]..=corner[1] + 1.0).contains(&q[1])
            })
    }
}

pub fn check_robot(robot: &str) -> Result<(), HostError> {
    if robot == ROBOT { Ok(()) } else { Err(HostError::failed(format!("no robot `{robot}`"))) }
}

impl HostServices for Maze {
    fn configuration_is_valid(&self, robot: &str, q: &[f64]) -> Result<bool, HostError> {
        check_robot(robot)?;
        Ok(self.free(q))
    }
    fn edge_is_valid(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<bool, HostError> {
        let steps = (self.distance(robot, a, b)? / EDGE_RESOLUTION).ceil().max(1.0) as usize;
        for step in 0..=steps {
            if !self.free(&self.interpolate(robot, a, b, step as f64 / steps as f64)?) {
                return Ok(false);
            }
        }
        Ok(true)
    }
    fn distance(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<f64, HostError> {
        check_robot(robot)?;
        Ok((a[0] - b[0]).hypot(a[1] - b[1]))
    }
    fn interpolate(
        &self,
        robot: &str,
        a: &[f64],
        b: &[f64],
        t: f64,
    ) -> Result<Vec<f64>, HostError> {
        check_robot(robot)?;
        Ok(a.iter().zip(b).map(|(a, b)| a + (b - a) * t).collect())
    }
    fn sample_configuration(&self, robot: &str, seed: u64) -> Result<Vec<f64>, HostError> {
        check_robot(robot)?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        Ok(vec![SIZE * rng.random::<f64>(), SIZE * rng.random::<f64>()])
    }
}

/// A request from `start` to `goal` with an iteration budget.
pub fn request(start: [f64; 2], goal: [f64; 2], iterations: u64, seed: u64) -> MotionRequest {
    MotionRequest {
        robot: ROBOT.into(),
        start: start.to_vec(),
        goal: goal.to_vec(),
        budget: MotionBudget { max_iterations: Some(iterations), time_limit: None },
        seed,
    }
}

/// Asserts that `path` runs from the request's start to its goal over edges the host accepts.
pub fn assert_valid_path(host: &dyn HostServices, request: &MotionRequest, path: &[Vec<f64>]) {
    assert_eq!(path.first(), Some(&request.start));
    assert_eq!(path.last(), Some(&request.goal));
    for edge in path.windows(2) {
        assert!(
            host.edge_is_valid(ROBOT, &edge[0], &edge[1]).expect("the host checks the edge"),
            "the host refuses the edge {:?} -> {:?}",
            edge[0],
            edge[1]
        );
    }
}

/// The path's length in the host's metric.
pub fn length(path: &[Vec<f64>]) -> f64 {
    path.windows(2).map(|edge| (edge[0][0] - edge[1][0]).hypot(edge[0][1] - edge[1][1])).sum()
}
