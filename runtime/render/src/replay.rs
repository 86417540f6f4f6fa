//! Replaying a trajectory file's steps as scenes of a spec: bodies matched to the spec's object
//! types by type name, robots to the spec's robots by name, coordinates by name.
//!
//! A step stores every body's world pose, held ones included, so replay only places things; it
//! never grabs or releases.

use lamp_geometry::Point3;
use lamp_trajectory::{Step, TrajectoryHeader};
use lamp_world::{Scene, SpecWorld};

use crate::error::RenderError;

/// The path of one robot's gripper link over a trajectory, in world coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct GripperPath {
    pub robot: String,
    pub points: Vec<Point3>,
}

/// Turns steps of one trajectory into scenes of one spec.
#[derive(Clone, Debug)]
pub struct Replay {
    /// Every body and robot of the header, in header order, at neutral configurations.
    scene: Scene,
    /// Per header robot: for each model coordinate, its index in the step's positions.
    coordinate_maps: Vec<Vec<usize>>,
    body_count: usize,
}

impl Replay {
    /// Matches the header's bodies and robots to `world`'s spec.
    pub fn new(world: &SpecWorld, header: &TrajectoryHeader) -> Result<Replay, RenderError> {
        let mut scene = Scene::new();
        for body in &header.bodies {
            let Some(spec_body) = world.body(&body.name, &body.type_name) else {
                return Err(RenderError::UnknownType {
                    body: body.name.clone(),
                    type_name: body.type_name.clone(),
                    spec: world.spec().domain.clone(),
                });
            };
            scene.add_body(spec_body, lamp_geometry::Pose::identity())?;
        }
        let mut coordinate_maps = Vec::with_capacity(header.robots.len());
        for robot in &header.robots {
            let Some(model) = world.robots.get(&robot.name) else {
                return Err(RenderError::UnknownRobot {
                    robot: robot.name.clone(),
                    spec: world.spec().domain.clone(),
                    known: world.robots.keys().cloned().collect::<Vec<_>>().join(", "),
                });
            };
            let mut map = Vec::with_capacity(model.dof());
            for name in model.coordinate_names() {
                let Some(index) = robot.coordinates.iter().position(|c| c == name) else {
                    return Err(RenderError::Coordinates {
                        robot: robot.name.clone(),
                        reason: format!("the file has no coordinate `{name}`"),
                    });
                };
                map.push(index);
            }
            if robot.coordinates.len() != map.len() {
                let extra: Vec<&str> = robot
                    .coordinates
                    .iter()
                    .filter(|c| !model.coordinate_names().contains(c))
                    .map(String::as_str)
                    .collect();
                return Err(RenderError::Coordinates {
                    robot: robot.name.clone(),
                    reason: format!("the model has no coordinate(s) {}", extra.join(", ")),
                });
            }
            world.add_robot(&mut scene, &robot.name, model.neutral_configuration())?;
            coordinate_maps.push(map);
        }
        Ok(Replay { scene, coordinate_maps, body_count: header.bodies.len() })
    }

    /// The scene at one step; `index` names the step in errors.
    pub fn scene_at(&self, index: usize, step: &Step) -> Result<Scene, RenderError> {
        let mut scene = self.scene.clone();
        self.apply(&mut scene, index, step)?;
        Ok(scene)
    }

    /// The gripper link's world position at every step, one path per robot with a gripper.
    pub fn gripper_paths(&self, steps: &[Step]) -> Result<Vec<GripperPath>, RenderError> {
        let robots = self.scene.robots();
        let mut paths: Vec<GripperPath> = robots
            .iter()
            .map(|robot| GripperPath { robot: robot.name.clone(), points: Vec::new() })
            .collect();
        for (index, step) in steps.iter().enumerate() {
            self.check(index, step)?;
            for (robot, state) in step.robots.iter().enumerate() {
                let q = self.configuration(robot, &state.positions);
                if let Some(pose) = self.scene.gripper_pose(robot, &q) {
                    paths[robot].points.push(Point3::from(pose.translation.vector));
                }
            }
        }
        paths.retain(|path| !path.points.is_empty());
        Ok(paths)
    }

    fn apply(&self, scene: &mut Scene, index: usize, step: &Step) -> Result<(), RenderError> {
        self.check(index, step)?;
        for (body, pose) in step.body_poses.iter().enumerate() {
            scene.set_body_pose(body, *pose);
        }
        for (robot, state) in step.robots.iter().enumerate() {
            let q = self.configuration(robot, &state.positions);
            scene.set_configuration(robot, &q);
        }
        Ok(())
    }

    /// The step's positions of robot `robot` in the model's coordinate order.
    fn configuration(&self, robot: usize, positions: &[f64]) -> Vec<f64> {
        self.coordinate_maps[robot].iter().map(|&i| positions[i]).collect()
    }

    /// Whether the step has the header's shape (the reader checks this; in-memory steps may not).
    fn check(&self, index: usize, step: &Step) -> Result<(), RenderError> {
        let inconsistent = |reason: String| Err(RenderError::Inconsistent { step: index, reason });
        if step.body_poses.len() != self.body_count {
            return inconsistent(format!(
                "{} body poses for {} bodies",
                step.body_poses.len(),
                self.body_count
            ));
        }
        if step.robots.len() != self.coordinate_maps.len() {
            return inconsistent(format!(
                "{} robot states for {} robots",
                step.robots.len(),
                self.coordinate_maps.len()
            ));
        }
        for (robot, state) in step.robots.iter().enumerate() {
            let needed = self.coordinate_maps[robot].iter().max().map_or(0, |m| m + 1);
            if state.positions.len() < needed {
                return inconsistent(format!(
                    "robot `{}` has {} positions, the header lists at least {needed}",
                    self.scene.robots()[robot].name,
                    state.positions.len()
                ));
            }
        }
        Ok(())
    }
}
