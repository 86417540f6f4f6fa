//! Replaying a finished trajectory from the initial scene, as an independent check before it is
//! written: every step's grasp changes are legal (a gripper without fingers touches what it
//! takes), every configuration is valid (within limits, collision-free, the held object
//! included), consecutive configurations are within the checking
//! resolution of each other, bodies move only while held (a released object settled to rest by
//! lamp-world's rule), and the goal holds at the end, every AtGoal object within its tolerance of
//! its target in the world frame, and every object at rest under gravity (the physics check),
//! checked after every release as well as at the end.

use std::collections::BTreeSet;
use std::sync::{Mutex, PoisonError};

use lamp_abstraction::{GroundAtom, SamplerArtifact};
use lamp_participants::ParticipantMap;
use lamp_spec::AtGoal;
use lamp_trajectory::Step;
use lamp_world::{CONTACT_GAP, MotionConfig, Scene, edge_steps};

use crate::at_rest::check_at_rest;
use crate::error::SolveError;
use crate::state::abstraction;
use crate::summary::Sink;
use crate::targets::first_miss;

/// What must hold at the end of a replay.
#[derive(Clone, Copy)]
pub struct Expected<'a> {
    /// The goal atoms, in the learned abstraction.
    pub goal: &'a BTreeSet<GroundAtom>,
    /// The AtGoal targets, in the world frame.
    pub targets: &'a [AtGoal],
}

/// How far (metres, and radians of rotation) a body that is not held may be from where the replay
/// has it before it counts as moved: the rounding of recomputed poses, far below any resolution.
const UNMOVED_TOLERANCE: f64 = 1e-9;

/// How far a body the replay has just let go of may settle from where the solve settled it (a
/// micrometre, a microradian): the settling drop is a shape cast, whose stopping point moves by
/// a nanometre when the gripper's pose differs in the last bit, and the replay computes that pose
/// from the recorded configuration, whose continuous joints are unwrapped (the same pose, other
/// rounding). The recorded pose is then the body's.
const SETTLED_TOLERANCE: f64 = 1e-6;

/// A gripper without fingers (a magnet, a suction cup) takes hold only of what it touches, to
/// within [`CONTACT_GAP`]; a gripper with fingers closes them after the grab, each until it
/// touches the object, which lamp-world's finger motion refuses otherwise.
fn held_by_contact(scene: &Scene, robot: usize, body: usize) -> Result<(), String> {
    if !scene.holds_by_contact(robot) {
        return Ok(());
    }
    match scene.gripper_gap(robot, body) {
        Some(gap) if gap <= CONTACT_GAP => Ok(()),
        Some(gap) => Err(format!(
            "`{}` takes hold of `{}` {:.1} mm away; a gripper without fingers holds only what it \
             touches (within {:.0} mm)",
            scene.robots()[robot].name,
            scene.bodies()[body].name,
            gap * 1e3,
            CONTACT_GAP * 1e3
        )),
        None => Ok(()),
    }
}

/// What a replay found at the end of a valid trajectory.
#[derive(Clone, Debug)]
pub struct Replayed {
    /// The final abstract state.
    pub reached: BTreeSet<GroundAtom>,
    /// The object of the final scene that sinks farthest onto what it rests on
    /// ([`check_at_rest`]).
    pub sink: Option<Sink>,
}

/// Checks `steps` from `initial`. `cancelled` is polled before every step: a long trajectory
/// takes seconds to replay, and a stop request must not wait.
pub fn replay(
    initial: &Scene,
    steps: &[Step],
    config: &MotionConfig,
    artifact: &SamplerArtifact,
    participants: &ParticipantMap,
    expected: &Expected<'_>,
    cancelled: &dyn Fn() -> bool,
) -> Result<Replayed, SolveError> {
    let Expected { goal, targets } = *expected;
    // The scene after each release is simulated on another thread of the rayon pool while the
    // replay goes on; the first to fall, in step order, is what the replay reports, unless a
    // step before it fails. The answer is the one a replay in turn would give.
    let falls = Mutex::new(Vec::new());
    let walked = rayon::in_place_scope(|scope| {
        walk(initial, steps, config, cancelled, &mut |index, scene| {
            let snapshot = scene.clone();
            let falls = &falls;
            scope.spawn(move |_| {
                if let Err(error) = check_at_rest(&snapshot, Some(index)) {
                    falls.lock().unwrap_or_else(PoisonError::into_inner).push((index, error));
                }
            });
        })
    });
    let scene = in_step_order(walked, falls.into_inner().unwrap_or_else(PoisonError::into_inner))?;
    let reached = abstraction(artifact, participants, &scene)?;
    if let Some(missing) = goal.iter().find(|atom| !reached.contains(atom)) {
        let reason = format!("the goal atom {missing} does not hold at the end");
        return Err(invalid(steps.len(), reason));
    }
    if let Some(miss) = first_miss(targets, &scene) {
        return Err(SolveError::TargetMissed(miss.to_string()));
    }
    let sink = check_at_rest(&scene, None)?;
    Ok(Replayed { reached, sink })
}

/// What a replay in turn would have reported: the walk's failure, unless a scene released before
/// its step falls (`falls`: the physics check's failures, by step, in any order); the first fall
/// when the walk went through. A cancelled walk is cancelled.
fn in_step_order<T>(
    walked: Result<T, Walk>,
    falls: Vec<(usize, SolveError)>,
) -> Result<T, SolveError> {
    let first_fall = falls.into_iter().min_by_key(|(step, _)| *step);
    match (walked, first_fall) {
        (Err(Walk::Cancelled), _) => Err(SolveError::cancelled()),
        (Err(Walk::Failed(step, _)), Some((fall, unstable))) if fall < step => Err(unstable),
        (Err(Walk::Failed(_, error)), _) => Err(*error),
        (Ok(_), Some((_, unstable))) => Err(unstable),
        (Ok(walked), None) => Ok(walked),
    }
}

/// Why a replay stopped before its end.
enum Walk {
    Cancelled,
    /// The step that failed, and how.
    Failed(usize, Box<SolveError>),
}

fn invalid(step: usize, reason: String) -> SolveError {
    SolveError::InvalidSolution { step, reason }
}

/// The replay's walk through `steps`, every check but the physics check, which is handed the
/// scene after each step that lets go of something (`released`); the final scene.
fn walk(
    initial: &Scene,
    steps: &[Step],
    config: &MotionConfig,
    cancelled: &dyn Fn() -> bool,
    released: &mut dyn FnMut(usize, &Scene),
) -> Result<Scene, Walk> {
    let mut scene = initial.clone();
    let fail = |step: usize, reason: String| Walk::Failed(step, Box::new(invalid(step, reason)));
    for (index, step) in steps.iter().enumerate() {
        if cancelled() {
            return Err(Walk::Cancelled);
        }
        if step.robots.len() != scene.robots().len()
            || step.body_poses.len() != scene.bodies().len()
        {
            return Err(fail(index, "the step does not describe the scene".to_string()));
        }
        let mut settled = Vec::new();
        for (robot, state) in step.robots.iter().enumerate() {
            let held_now = scene.held(robot).map(|held| held.body);
            let held_next = state.held.first().copied().flatten();
            if held_now != held_next {
                if let Some(body) = held_now {
                    scene.release_at_rest(robot).map_err(|error| fail(index, error.to_string()))?;
                    settled.push(body);
                }
                if let Some(body) = held_next {
                    held_by_contact(&scene, robot, body).map_err(|reason| fail(index, reason))?;
                    scene.grab(robot, body).map_err(|error| fail(index, error.to_string()))?;
                }
            }
            let model = scene.robots()[robot].robot().clone();
            let previous = scene.robots()[robot].configuration().to_vec();
            let steps_needed = edge_steps(
                &model,
                &previous,
                &state.positions,
                config.linear_resolution,
                config.angular_resolution,
            );
            if steps_needed > 1 {
                return Err(fail(
                    index,
                    format!("robot `{}` jumps further than one resolution step", model.name()),
                ));
            }
            scene.set_configuration(robot, &state.positions);
        }
        for (body, pose) in step.body_poses.iter().enumerate() {
            let here = scene.body_pose(body);
            let just_settled = settled.contains(&body);
            let tolerance = if just_settled { SETTLED_TOLERANCE } else { UNMOVED_TOLERANCE };
            let moved = (here.translation.vector - pose.translation.vector).norm() > tolerance
                || here.rotation.angle_to(&pose.rotation) > tolerance;
            if just_settled && !moved {
                scene.set_body_pose(body, *pose);
            }
            if moved {
                return Err(fail(
                    index,
                    format!("body `{}` moves without being held", scene.bodies()[body].name),
                ));
            }
        }
        for (robot, state) in step.robots.iter().enumerate() {
            if let Some(contact) = scene.first_contact(robot, &state.positions) {
                return Err(fail(index, contact.to_string()));
            }
        }
        // What is built so far must stand, not only what is finished: a structure may hold
        // when complete and fall while half built.
        if !settled.is_empty() {
            released(index, &scene);
        }
    }
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unstable(step: usize) -> SolveError {
        SolveError::Unstable {
            object: format!("p{step}"),
            shift: 0.01,
            turn: 0.0,
            seconds: 2.0,
            step: Some(step),
        }
    }

    fn stopped_at(result: Result<(), SolveError>) -> String {
        match result.expect_err("a failure") {
            SolveError::Unstable { object, .. } => format!("fall {object}"),
            SolveError::InvalidSolution { step, .. } => format!("invalid {step}"),
            other => other.to_string(),
        }
    }

    #[test]
    fn the_failure_a_replay_in_turn_meets_first_is_the_one_reported() {
        let failed = |step| Err(Walk::Failed(step, Box::new(invalid(step, "touches".into()))));
        // Falls found out of order: the earliest counts.
        assert_eq!(
            stopped_at(in_step_order(Ok(()), vec![(9, unstable(9)), (3, unstable(3))])),
            "fall p3"
        );
        // A fall after the release at step 3 comes before a collision at step 4...
        assert_eq!(stopped_at(in_step_order(failed(4), vec![(3, unstable(3))])), "fall p3");
        // ...and after a collision at step 2, which a replay in turn meets first.
        assert_eq!(stopped_at(in_step_order(failed(2), vec![(3, unstable(3))])), "invalid 2");
        assert_eq!(stopped_at(in_step_order(failed(2), Vec::new())), "invalid 2");
        assert!(matches!(
            in_step_order::<()>(Err(Walk::Cancelled), vec![(1, unstable(1))]),
            Err(error) if error.to_string() == SolveError::cancelled().to_string()
        ));
        assert!(in_step_order(Ok(7), Vec::new()).is_ok_and(|walked| walked == 7));
    }
}
