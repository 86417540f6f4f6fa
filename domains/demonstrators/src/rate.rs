//! Recording at a fixed rate, as a robot's logger writes: the script's motion timed within the
//! robots' velocity and acceleration limits (`lamp_world::time_steps`), then sampled every 1/R
//! seconds.
//!
//! The script records one step per state of each planned path (5 mm, 0.01 rad apart). Timed, those
//! steps are the corners of a piecewise linear path in configuration space with a time at each;
//! a sample between two of them is the configuration interpolated at its time (wrap-aware, slerp
//! for a rotation), a held object carried rigidly with the gripper at it. A grasp or a release
//! takes [`lamp_world::GRASP_SECONDS`] with the robot at rest: the samples in that time show the
//! state before it, and the first sample at or after its end the state after it (the object
//! held, or let go of and settled). The last sample is the first at or after the end of the
//! motion, and shows the final state.

use lamp_trajectory::Step;
use lamp_world::{Scene, time_steps};

const NANOSECONDS_PER_SECOND: f64 = 1e9;

/// `steps` resampled at `rate` hertz, and the number of samples up to and including the state
/// after step `through` (the release: a cut keeps no more than those).
pub(crate) fn resample(
    steps: &[Step],
    scene: &Scene,
    rate: f64,
    through: usize,
) -> Result<(Vec<Step>, usize), String> {
    let Some(last) = steps.last() else {
        return Ok((Vec::new(), 0));
    };
    let robots: Vec<&lamp_robot::Robot> =
        scene.robots().iter().map(|robot| robot.robot().as_ref()).collect();
    let mut timed = steps.to_vec();
    timed[0].time_nanoseconds = 0;
    let total = time_steps(&mut timed, &robots).map_err(|error| error.to_string())? as f64;
    let times: Vec<f64> = timed.iter().map(|step| step.time_nanoseconds as f64).collect();
    let period = NANOSECONDS_PER_SECOND / rate;
    // The first sample at or after the end; a duration a rounding error past a whole number of
    // periods does not add one.
    let count = ((total / period) - 1e-9).ceil().max(0.0) as usize;
    let time_of = |k: usize| k as f64 * period;
    let mut samples = Vec::with_capacity(count + 1);
    for k in 0..=count {
        let t = time_of(k);
        let mut sample = if t >= total {
            last.clone()
        } else {
            // The piece [i, i + 1] that holds t: i is the last step stamped at or before it, and
            // the step after it is stamped later (t is before the end).
            let i = times.partition_point(|&stamp| stamp <= t).saturating_sub(1);
            between(steps, scene, i, (t - times[i]) / (times[i + 1] - times[i]))
        };
        sample.time_nanoseconds = t.round() as u64;
        samples.push(sample);
    }
    let after = times.get(through).copied().unwrap_or(total);
    let kept = (0..=count).find(|&k| time_of(k) >= after).unwrap_or(count) + 1;
    Ok((samples, kept))
}

/// The state a fraction `s` (in [0, 1)) of the way from step `i` to step `i + 1`.
fn between(steps: &[Step], scene: &Scene, i: usize, s: f64) -> Step {
    let (from, to) = (&steps[i], &steps[i + 1]);
    let mut step = from.clone();
    if s <= 0.0 || from.grasp_changes_to(to) {
        // A grasp or a release: the robot waits at rest for the gripper.
        return step;
    }
    for (index, ((state, a), b)) in
        step.robots.iter_mut().zip(&from.robots).zip(&to.robots).enumerate()
    {
        let robot = scene.robots()[index].robot();
        robot.interpolate(&a.positions, &b.positions, s, &mut state.positions);
        for body in state.held.iter().flatten() {
            let (Some(at), Some(now)) = (
                scene.gripper_pose(index, &a.positions),
                scene.gripper_pose(index, &state.positions),
            ) else {
                continue;
            };
            let grasp = at.inv_mul(&from.body_poses[*body]);
            step.body_poses[*body] = now * grasp;
        }
    }
    step
}
