//! The times of a recorded trajectory: when a robot that follows it would reach each step.
//!
//! The recorder stamps its steps a fixed 10 ms apart, which is what demonstrations keep. A
//! solution's trajectory is timed again here, as a robot would execute it: every run of motion
//! between two grasp changes is timed from rest to rest within every coordinate's velocity and
//! acceleration limits (`lamp_robot::time_path`), and every grasp change takes [`GRASP_SECONDS`].

use lamp_robot::{Limits, Robot, time_path};
use lamp_trajectory::Step;
use rayon::prelude::*;

use crate::error::WorldError;

/// How long a grasp or a release takes, in seconds. lamp models no gripper dynamics; a parallel
/// gripper at full speed (a Robotiq 2F-85: 150 mm/s over its 85 mm stroke) closes in about this,
/// and a grasp rarely uses the whole stroke.
pub const GRASP_SECONDS: f64 = 0.5;

const NANOSECONDS_PER_SECOND: f64 = 1e9;

/// Stamps `steps` with the times a robot takes to follow them, from the first step's time on,
/// and returns how long the whole trajectory takes (nanoseconds). `robots` are the models of the
/// steps' robots, in their order.
///
/// The wrapped angles of each step (continuous joints, a planar yaw) are first rewritten to the
/// value nearest the step before ([`Robot::unwrap_towards`]), so that the positions turn the short
/// way round, as the motion was planned and checked, instead of jumping by 2π at ±π.
///
/// Stamps are whole nanoseconds; the time from each step to the next is rounded up, so that
/// rounding never makes a recorded velocity exceed its limit.
pub fn time_steps(steps: &mut [Step], robots: &[&Robot]) -> Result<u64, WorldError> {
    let fail = |step: usize, reason: String| WorldError::Timing { step, reason };
    for (index, step) in steps.iter().enumerate() {
        if step.robots.len() != robots.len() {
            return Err(fail(
                index,
                format!("it has {} robots, not {}", step.robots.len(), robots.len()),
            ));
        }
        for (state, robot) in step.robots.iter().zip(robots) {
            if state.positions.len() != robot.dof() {
                return Err(fail(
                    index,
                    format!(
                        "robot `{}` has {} positions, not {}",
                        robot.name(),
                        state.positions.len(),
                        robot.dof()
                    ),
                ));
            }
        }
    }
    for index in 1..steps.len() {
        let (before, after) = steps.split_at_mut(index);
        let (previous, current) = (&before[index - 1], &mut after[0]);
        for ((state, earlier), robot) in current.robots.iter_mut().zip(&previous.robots).zip(robots)
        {
            robot.unwrap_towards(&earlier.positions, &mut state.positions);
        }
    }
    let velocity: Vec<f64> =
        robots.iter().flat_map(|robot| robot.coordinates().iter().map(|c| c.velocity)).collect();
    let acceleration: Vec<f64> = robots
        .iter()
        .flat_map(|robot| robot.coordinates().iter().map(|c| c.acceleration))
        .collect();
    let limits = Limits { velocity: &velocity, acceleration: &acceleration };
    let pieces: Vec<Vec<f64>> = steps
        .par_windows(2)
        .map(|pair| {
            let mut piece = vec![0.0; velocity.len()];
            let mut offset = 0;
            for ((from, to), robot) in pair[0].robots.iter().zip(&pair[1].robots).zip(robots) {
                let end = offset + robot.dof();
                robot.displacement(&from.positions, &to.positions, &mut piece[offset..end]);
                offset = end;
            }
            piece
        })
        .collect();
    let grasps: Vec<bool> =
        steps.windows(2).map(|pair| pair[0].grasp_changes_to(&pair[1])).collect();
    let time = |start: usize, pieces: &[Vec<f64>]| {
        time_path(pieces, &limits).map_err(|error| fail(start + 1, error.to_string()))
    };
    // The runs of motion between grasp changes, and each grasp change: each is timed on its
    // own, so they are timed side by side, and the first error in trajectory order is the one
    // reported, as in turn.
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut start = 0;
    while start < pieces.len() {
        let end = match grasps[start] {
            true => start + 1,
            false => (start..pieces.len()).find(|&k| grasps[k]).unwrap_or(pieces.len()),
        };
        runs.push((start, end));
        start = end;
    }
    let timed: Vec<Result<Vec<f64>, WorldError>> = runs
        .par_iter()
        .map(|&(start, end)| {
            let mut durations = time(start, &pieces[start..end])?;
            if grasps[start] {
                // The robot is at rest while its gripper closes or opens; a motion recorded in
                // the same step (none in a solution) is timed on its own.
                durations[0] += GRASP_SECONDS;
            }
            Ok(durations)
        })
        .collect();
    let mut durations = vec![0.0; pieces.len()];
    for (&(start, end), run) in runs.iter().zip(timed) {
        durations[start..end].copy_from_slice(&run?);
    }
    let Some(first) = steps.first().map(|step| step.time_nanoseconds) else {
        return Ok(0);
    };
    let mut now = first;
    for (index, duration) in durations.iter().enumerate() {
        let nanoseconds = (duration * NANOSECONDS_PER_SECOND).ceil();
        // u64 holds 584 years of nanoseconds; a trajectory longer than that is no robot's.
        let too_long = || fail(index + 1, format!("it would end after {duration} s more"));
        if !(nanoseconds.is_finite() && nanoseconds < u64::MAX as f64) {
            return Err(too_long());
        }
        now = now.checked_add(nanoseconds as u64).ok_or_else(too_long)?;
        steps[index + 1].time_nanoseconds = now;
    }
    Ok(now - first)
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use lamp_robot::{Mount, Pose};
    use lamp_trajectory::RobotState;

    use super::*;

    /// One continuous joint at 2 rad/s, and a gripper.
    fn wrist() -> Robot {
        let urdf = r#"<robot name="wrist"><link name="base"/><link name="gripper_link"/>
            <joint name="roll" type="continuous"><parent link="base"/><child link="gripper_link"/>
            <axis xyz="0 0 1"/><limit effort="1" velocity="2"/></joint></robot>"#;
        Robot::from_urdf_str(urdf, None, Mount::Fixed(Pose::identity())).expect("loads")
    }

    fn step(angle: f64, held: Option<usize>) -> Step {
        Step {
            time_nanoseconds: 0,
            body_poses: Vec::new(),
            robots: vec![RobotState { positions: vec![angle], held: vec![held] }],
        }
    }

    #[test]
    fn a_turn_through_pi_is_unwrapped_and_timed_with_a_grasp_at_rest() {
        let robot = wrist();
        // 0.1 rad steps from 3.0 through π to −3.0 + 2π − …: as recorded, wrapped into [−π, π).
        let angles: Vec<f64> =
            (0..=10).map(|k| lamp_robot::wrap_angle(3.0 + 0.1 * k as f64)).collect();
        assert!(angles[10] < 0.0, "the recording jumps by 2π");
        let mut steps: Vec<Step> = angles.iter().map(|&angle| step(angle, None)).collect();
        // Then the gripper takes hold, at rest.
        steps.push(step(angles[10], Some(0)));
        let total = time_steps(&mut steps, &[&robot]).expect("times");
        for (k, step) in steps.iter().take(11).enumerate() {
            assert!((step.robots[0].positions[0] - (3.0 + 0.1 * k as f64)).abs() < 1e-12);
        }
        // 1 rad at 2 rad/s and 1 rad/s²: a triangle of 2·√(1/1) = 2 s, then 0.5 s to grasp.
        let moving = steps[10].time_nanoseconds;
        assert!((moving as f64 * 1e-9 - 2.0).abs() < 1e-8, "{moving}");
        assert_eq!(total, moving + 500_000_000);
        assert_eq!(steps[11].time_nanoseconds, total);
        // The same steps give the same stamps.
        let mut again: Vec<Step> = angles.iter().map(|&angle| step(angle, None)).collect();
        again.push(step(angles[10], Some(0)));
        time_steps(&mut again, &[&robot]).expect("times");
        assert_eq!(again, steps);
    }

    #[test]
    fn steps_that_do_not_fit_the_robots_are_named() {
        let robot = wrist();
        let mut steps = vec![step(0.0, None), step(0.1, None)];
        steps[1].robots[0].positions.push(0.0);
        let error = time_steps(&mut steps, &[&robot]).unwrap_err();
        assert_eq!(
            error.to_string(),
            "the trajectory cannot be timed at step 1: robot `wrist` has 2 positions, not 1"
        );
        let mut steps = vec![step(0.0, None), step(PI, None)];
        let error = time_steps(&mut steps, &[]).unwrap_err();
        assert!(error.to_string().contains("step 0: it has 1 robots, not 0"), "{error}");
        assert_eq!(time_steps(&mut [], &[&robot]).expect("nothing to time"), 0);
    }
}
