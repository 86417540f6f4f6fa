//! Recording a scene as it changes, as lamp-trajectory steps: one step per visited state, 10 ms
//! apart, with every body, every robot's full configuration and what each gripper holds. The
//! demonstrators and the solver's trajectories are both recorded this way; a solution's steps are
//! then stamped with the times a robot would take (`time_steps`).

use lamp_spec::Spec;
use lamp_trajectory::{BodyDescription, RobotDescription, RobotState, Step, TrajectoryHeader};

use crate::scene::Scene;

/// Time between two recorded steps: 10 ms (until `time_steps` stamps them again).
pub const STEP_NANOSECONDS: u64 = 10_000_000;

/// The steps recorded so far, and where the straight last approaches among them begin.
#[derive(Clone, Debug, Default)]
pub struct Recorder {
    pub steps: Vec<Step>,
    pub approaches: Vec<Approach>,
    /// The straight descent of a carry that ended at the last step, until the object is let go
    /// of there ([`Recorder::confirm_put_down`]); a carry to a pose in the air is not a put-down.
    descent: Option<Approach>,
}

/// A straight last approach that ends in contact: a carried object coming down onto its place,
/// or a gripper that holds by contact coming to what it takes. A robot tracks its trajectory to
/// within millimetres, and the world leaves a resting object a millimetre above its support, so a
/// real robot meets the contact before or after the trajectory does; it should make this part of
/// the motion compliant or force-limited.
#[derive(Clone, Debug, PartialEq)]
pub struct Approach {
    /// The recorded step where the approach begins, the robot at rest or still moving.
    pub from_step: usize,
    /// The recorded step where it ends, in contact.
    pub to_step: usize,
    /// The robot's index in the scene.
    pub robot: usize,
    /// The body brought down (a put-down) or come to (a contact grasp), by its index.
    pub body: usize,
    pub kind: ApproachKind,
    /// How far the gripper travels along the approach, in metres.
    pub metres: f64,
}

/// What an approach ends in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ApproachKind {
    /// A carried object comes straight down onto its place.
    PutDown,
    /// A magnet or suction cup comes straight to the object it will hold.
    Contact,
}

impl Recorder {
    /// Records the scene as it is now.
    pub fn record(&mut self, scene: &Scene) {
        let time_nanoseconds = self.steps.len() as u64 * STEP_NANOSECONDS;
        let body_poses = (0..scene.bodies().len()).map(|body| scene.body_pose(body)).collect();
        let robots = scene
            .robots()
            .iter()
            .map(|robot| RobotState {
                positions: robot.configuration().to_vec(),
                held: robot
                    .gripper()
                    .map(|gripper| vec![gripper.held.map(|held| held.body)])
                    .unwrap_or_default(),
            })
            .collect();
        self.steps.push(Step { time_nanoseconds, body_poses, robots });
    }

    /// Steps robot `robot` through `states`, recording each; the first state is skipped when it
    /// is where the previous segment ended, so that no state is recorded twice in a row.
    pub fn follow(&mut self, scene: &mut Scene, robot: usize, states: &[Vec<f64>]) {
        for (index, q) in states.iter().enumerate() {
            if index == 0 && !self.steps.is_empty() {
                continue;
            }
            scene.set_configuration(robot, q);
            self.record(scene);
        }
    }

    /// Marks the steps from `from_step` to the last recorded one as a straight last approach.
    pub fn mark_approach(
        &mut self,
        from_step: usize,
        robot: usize,
        body: usize,
        kind: ApproachKind,
        metres: f64,
    ) {
        let to_step = self.steps.len().saturating_sub(1);
        self.approaches.push(Approach { from_step, to_step, robot, body, kind, metres });
    }

    /// Notes that the carry just recorded came straight down from `from_step`, carrying `body`:
    /// a put-down once the object is let go of where it ends.
    pub fn note_descent(&mut self, from_step: usize, robot: usize, body: usize, metres: f64) {
        let to_step = self.steps.len().saturating_sub(1);
        let kind = ApproachKind::PutDown;
        self.descent = Some(Approach { from_step, to_step, robot, body, kind, metres });
    }

    /// Marks the noted descent as a put-down when `robot` lets go of `body` where it ended; a
    /// release anywhere else, or of something else, forgets it.
    pub fn confirm_put_down(&mut self, robot: usize, body: usize) {
        let last = self.steps.len().checked_sub(1);
        if let Some(descent) = self.descent.take()
            && descent.robot == robot
            && descent.body == body
            && Some(descent.to_step) == last
        {
            self.approaches.push(descent);
        }
    }

    /// Keeps the first `len` steps, and the approaches that end among them.
    pub fn truncate(&mut self, len: usize) {
        self.steps.truncate(len);
        self.approaches.retain(|approach| approach.to_step < len);
        self.descent = self.descent.take().filter(|descent| descent.to_step < len);
    }

    /// How many steps are recorded.
    pub fn len(&self) -> usize {
        self.steps.len()
    }

    /// Whether nothing is recorded yet.
    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }
}

/// The header describing `scene`'s bodies and robots, in the order steps store them.
pub fn trajectory_header(spec: &Spec, scene: &Scene, seed: u64) -> TrajectoryHeader {
    let bodies = scene
        .bodies()
        .iter()
        .map(|body| BodyDescription { name: body.name.clone(), type_name: body.type_name.clone() })
        .collect();
    let robots = scene
        .robots()
        .iter()
        .map(|robot| RobotDescription {
            name: robot.name.clone(),
            coordinates: robot.robot().coordinate_names().to_vec(),
            grippers: robot.gripper().map(|g| vec![g.part_type.clone()]).unwrap_or_default(),
        })
        .collect();
    TrajectoryHeader {
        domain: spec.domain.clone(),
        seed,
        provenance: Default::default(),
        bodies,
        robots,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A recorder with `count` empty steps.
    fn recorded(count: usize) -> Recorder {
        let mut recorder = Recorder::default();
        for index in 0..count {
            let time_nanoseconds = index as u64 * STEP_NANOSECONDS;
            recorder.steps.push(Step {
                time_nanoseconds,
                body_poses: Vec::new(),
                robots: Vec::new(),
            });
        }
        recorder
    }

    #[test]
    fn a_descent_is_a_put_down_only_when_the_object_is_let_go_of_where_it_ends() {
        let mut recorder = recorded(10);
        recorder.note_descent(6, 0, 2, 0.1);
        recorder.confirm_put_down(0, 2);
        let put_down = Approach {
            from_step: 6,
            to_step: 9,
            robot: 0,
            body: 2,
            kind: ApproachKind::PutDown,
            metres: 0.1,
        };
        assert_eq!(recorder.approaches, std::slice::from_ref(&put_down));
        // Carried on after the descent (a carry to a pose in the air), then let go of.
        recorder.note_descent(10, 0, 3, 0.1);
        recorder.steps.push(recorder.steps[0].clone());
        recorder.confirm_put_down(0, 3);
        // Another object let go of where the descent ended.
        recorder.note_descent(10, 0, 3, 0.1);
        recorder.confirm_put_down(0, 4);
        recorder.confirm_put_down(0, 3);
        assert_eq!(recorder.approaches, [put_down], "neither is a put-down");
    }

    #[test]
    fn going_back_keeps_the_approaches_that_end_before_and_forgets_a_later_descent() {
        let mut recorder = recorded(10);
        recorder.mark_approach(3, 0, 1, ApproachKind::Contact, 0.005);
        let more = recorded(10).steps;
        recorder.steps.extend(more);
        recorder.note_descent(15, 0, 1, 0.1);
        recorder.truncate(19);
        recorder.confirm_put_down(0, 1);
        assert_eq!(recorder.approaches.len(), 1, "the descent ended at step 19, now undone");
        assert_eq!(recorder.approaches[0].to_step, 9);
        recorder.truncate(10);
        assert_eq!(recorder.approaches.len(), 1);
        recorder.truncate(9);
        assert!(recorder.approaches.is_empty(), "the contact approach ended at step 9");
    }
}
