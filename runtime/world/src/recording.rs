//! Recording a scene as it changes, as lamp-trajectory steps: one step per visited state, 10 ms
//! apart, with every body, every robot's full configuration and what each gripper holds. The
//! demonstrators and the solver's trajectories are both recorded this way; a solution's steps are
//! then stamped with the times a robot would take (`time_steps`).

use lamp_spec::Spec;
use lamp_trajectory::{BodyDescription, RobotDescription, RobotState, Step, TrajectoryHeader};

use crate::scene::Scene;

/// Time between two recorded steps: 10 ms (until `time_steps` stamps them again).
pub const STEP_NANOSECONDS: u64 = 10_000_000;

/// The steps recorded so far.
#[derive(Clone, Debug, Default)]
pub struct Recorder {
    pub steps: Vec<Step>,
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
