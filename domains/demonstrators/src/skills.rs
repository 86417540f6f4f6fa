//! Skills shared by the demonstrators: plan a collision-free path for one joint group and
//! record every state along it at the checking resolution, grab and release.

use lamp_geometry::{Pose, Rotation, Vec3};
use lamp_world::{MotionConfig, Scene, densify, plan_motion};
use rand_chacha::ChaCha8Rng;

use crate::recorder::Recorder;

/// The motion settings of every demonstrator: the world's default resolutions (5 mm,
/// 0.01 rad) and RRT-Connect with an iteration budget but no wall-clock limit, so that the same
/// seed gives the same demonstration on any machine.
pub(crate) fn motion_config() -> MotionConfig {
    let mut config = MotionConfig::default();
    config.rrt.timeout = None;
    config
}

/// Why one attempt at a demonstration failed; the demonstrator retries with fresh choices.
pub(crate) type Attempt<T> = Result<T, String>;

/// Moves `group` of `robot` from where it is to `goal` along a planned path, recording it.
pub(crate) fn move_to(
    scene: &mut Scene,
    recorder: &mut Recorder,
    robot: usize,
    group: &str,
    goal: &[f64],
    rng: &mut ChaCha8Rng,
) -> Attempt<()> {
    let config = motion_config();
    let start = scene
        .robots()
        .get(robot)
        .map(|r| r.configuration().to_vec())
        .ok_or_else(|| "the robot is not in the scene".to_string())?;
    let plan = plan_motion(scene, robot, group, &start, goal, &config, rng)
        .map_err(|error| format!("motion planning ({group}): {error}"))?;
    let model = scene.robots()[robot].robot().clone();
    let states = densify(&model, &plan.waypoints, &config);
    recorder.follow(scene, robot, &states);
    Ok(())
}

/// Grabs `body` where the gripper is and records the step where the held flag changes.
pub(crate) fn grab(
    scene: &mut Scene,
    recorder: &mut Recorder,
    robot: usize,
    body: usize,
) -> Attempt<()> {
    scene.grab(robot, body).map_err(|error| error.to_string())?;
    recorder.record(scene);
    Ok(())
}

/// Releases what the gripper holds and records the step where the held flag changes.
pub(crate) fn release(scene: &mut Scene, recorder: &mut Recorder, robot: usize) -> Attempt<()> {
    scene.release(robot).ok_or_else(|| "the gripper holds nothing".to_string())?;
    recorder.record(scene);
    Ok(())
}

/// A pose from a translation and roll, pitch, yaw (radians; `Rz(yaw)·Ry(pitch)·Rx(roll)`).
pub(crate) fn pose(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> Pose {
    Pose::from_parts(Vec3::new(x, y, z).into(), Rotation::from_euler_angles(roll, pitch, yaw))
}
