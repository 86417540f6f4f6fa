//! The standard ROS 2 and Foxglove channels of a recorded trajectory, so that Foxglove and RViz
//! show it: every robot link's and every body's world pose per step (links by forward
//! kinematics of the recorded configuration), the joint values, the robots' URDF text and the
//! bodies' shapes from the spec. lamp-trajectory writes them beside `/lamp/world`;
//! `docs/formats.md` describes them.

use lamp_geometry::{Pose, Shape};
use lamp_robot::LinkId;
use lamp_trajectory::{
    HELD_TOPIC, Primitive, ROBOT_DESCRIPTION_TOPIC, RobotModelText, SceneObject, StandardChannels,
    StandardStep, StaticFrame, TfFrame, Trajectory,
};

use crate::error::WorldError;
use crate::from_spec::SpecWorld;

/// The fixed frame of every transform.
pub const WORLD_FRAME: &str = "world";

/// Colour of the static world (tables, floors): grey.
const WORLD_COLOR: [f64; 4] = [0.6, 0.6, 0.6, 1.0];
/// Colour of static objects (boxes, shelves): light wood.
const STATIC_COLOR: [f64; 4] = [0.8, 0.68, 0.5, 1.0];
/// Colours of movable objects, one per movable type in name order, repeating.
const MOVABLE_COLORS: [[f64; 4]; 6] = [
    [0.9, 0.3, 0.2, 1.0],
    [0.2, 0.5, 0.9, 1.0],
    [0.3, 0.7, 0.3, 1.0],
    [0.95, 0.75, 0.1, 1.0],
    [0.6, 0.35, 0.8, 1.0],
    [0.1, 0.75, 0.75, 1.0],
];

/// The standard channels of `trajectory`, whose robots and body types are `world`'s, and their
/// values at every step.
///
/// Frames form the tree `robot_state_publisher` would publish: `world` is the root; each body's
/// frame is its name, a child of `world`; each robot's root link is a child of `world` (its
/// mount's pose) and every other link a child of its parent link (its joint's origin and
/// motion). Link frames are the URDF's link names, or `<robot>/<link>` when the file has several
/// robots (their descriptions are then on `/<robot>/robot_description`). Fixed frames are on
/// `/tf_static` once: a body whose pose is the same at every step, the root link of a fixed
/// mount, a link below a fixed joint. Every other frame is on `/tf` when it moves (links below
/// the root at most at 50 Hz, as they follow from the joints; see [`TfFrame`]). Joints with
/// one coordinate are on `/joint_states` under their URDF names (prefixed likewise). The frame
/// each gripper holds (the body's name, empty when none) is on `/lamp/held`
/// (`/<robot>/lamp/held` with several robots, `…/<gripper>` with several grippers).
pub fn standard_channels(
    world: &SpecWorld,
    trajectory: &Trajectory,
) -> Result<(StandardChannels, Vec<StandardStep>), WorldError> {
    let header = &trajectory.header;
    let several = header.robots.len() > 1;
    let prefixed =
        |robot: &str, name: &str| if several { format!("{robot}/{name}") } else { name.into() };

    let world_child =
        |frame: &str| TfFrame { parent: WORLD_FRAME.into(), frame: frame.into(), derived: false };
    let mut frames = Vec::new();
    let mut static_frames = Vec::new();
    let mut moving_bodies = Vec::new();
    for (index, body) in header.bodies.iter().enumerate() {
        let first = trajectory.steps.first().map(|step| step.body_poses[index]);
        let fixed = first
            .filter(|first| trajectory.steps.iter().all(|step| step.body_poses[index] == *first));
        match fixed {
            Some(pose) => static_frames.push(StaticFrame {
                parent: WORLD_FRAME.into(),
                frame: body.name.clone(),
                pose,
            }),
            None => {
                frames.push(world_child(&body.name));
                moving_bodies.push(index);
            }
        }
    }

    let mut models = Vec::new();
    let mut joints = Vec::new();
    let mut robots = Vec::new();
    let mut held_topics = Vec::new();
    for description in &header.robots {
        let unknown = || WorldError::UnknownName { what: "robot", name: description.name.clone() };
        let model = world.robots.get(&description.name).ok_or_else(unknown)?;
        let urdf = world.urdf_text(&description.name).ok_or_else(unknown)?;
        let topic = match several {
            true => format!("/{}{ROBOT_DESCRIPTION_TOPIC}", description.name),
            false => ROBOT_DESCRIPTION_TOPIC.to_string(),
        };
        robots.push(RobotModelText { topic, urdf: urdf.to_string() });
        for gripper in &description.grippers {
            held_topics.push(match (several, description.grippers.len() > 1) {
                (false, false) => HELD_TOPIC.to_string(),
                (true, false) => format!("/{}{HELD_TOPIC}", description.name),
                (_, true) => format!("/{}{HELD_TOPIC}/{gripper}", description.name),
            });
        }
        let neutral = model.neutral_configuration();
        let mut moving_links: Vec<LinkId> = Vec::new();
        for link in 0..model.link_count() {
            let frame = prefixed(&description.name, model.link_name(link));
            let parent = match model.parent_link(link) {
                Some(parent) => prefixed(&description.name, model.link_name(parent)),
                None => WORLD_FRAME.to_string(),
            };
            let fixed = match link {
                0 => model.mount().coordinate_count() == 0,
                _ => model.has_fixed_joint(link),
            };
            if fixed {
                let pose = local_pose(model, &neutral, link);
                static_frames.push(StaticFrame { parent, frame, pose });
            } else {
                // Only the root link's pose is the robot's own; the others follow from the joints.
                frames.push(TfFrame { parent, frame, derived: link != 0 });
                moving_links.push(link);
            }
        }
        let mut coordinates = Vec::new();
        for link in 0..model.link_count() {
            let Some(joint) = model.parent_joint_name(link) else { continue };
            let indices = model.joint_coordinates(joint).map_err(|source| WorldError::Robot {
                robot: description.name.clone(),
                urdf: world
                    .spec()
                    .robot(&description.name)
                    .map(|r| r.urdf.clone())
                    .unwrap_or_default(),
                source: Box::new(source),
            })?;
            if let [coordinate] = indices[..] {
                joints.push(prefixed(&description.name, joint));
                coordinates.push(coordinate);
            }
        }
        models.push((model, coordinates, moving_links));
    }

    let objects = scene_objects(world, trajectory)?;
    let channels = StandardChannels {
        world_frame: WORLD_FRAME.to_string(),
        frames,
        static_frames,
        joints,
        robots,
        objects,
        step_labels: false,
        approaches: false,
        held_topics,
        trajectory_topics: Vec::new(),
        gripper_topics: Vec::new(),
    };

    let mut values = Vec::with_capacity(trajectory.steps.len());
    for step in &trajectory.steps {
        let mut frame_poses: Vec<Pose> =
            moving_bodies.iter().map(|index| step.body_poses[*index]).collect();
        let mut joint_positions = Vec::new();
        let mut held = Vec::new();
        for ((model, coordinates, moving_links), state) in models.iter().zip(&step.robots) {
            held.extend(state.held.iter().map(|body| match body {
                Some(body) => header.bodies[*body].name.clone(),
                None => String::new(),
            }));
            if state.positions.len() != model.dof() {
                return Err(WorldError::Configuration {
                    robot: model.name().to_string(),
                    reason: format!(
                        "the trajectory has {} coordinates, the robot {}",
                        state.positions.len(),
                        model.dof()
                    ),
                });
            }
            let q = &state.positions;
            frame_poses.extend(moving_links.iter().map(|link| local_pose(model, q, *link)));
            joint_positions.extend(coordinates.iter().map(|index| state.positions[*index]));
        }
        values.push(StandardStep {
            frame_poses,
            joint_positions,
            label: None,
            approach: None,
            held,
            trajectories: Vec::new(),
            gripper_commands: Vec::new(),
        });
    }
    Ok((channels, values))
}

/// Labels every step from `starts[k]` up to the next start with `plan[k]`, the plan step being
/// executed there, and turns `/lamp/step` on; steps before the first start (the initial state)
/// carry no label. `starts` are increasing trajectory step indices, one per plan step.
pub fn label_plan_steps(
    channels: &mut StandardChannels,
    values: &mut [StandardStep],
    starts: &[usize],
    plan: &[String],
) {
    channels.step_labels = true;
    for (k, (start, label)) in starts.iter().zip(plan).enumerate() {
        let end = starts.get(k + 1).copied().unwrap_or(values.len()).min(values.len());
        for value in values.iter_mut().take(end).skip(*start) {
            value.label = Some(label.clone());
        }
    }
}

/// Writes each of `approaches` (its first trajectory step and its description) on
/// `/lamp/approach` at that step, and turns the topic on.
pub fn mark_approaches(
    channels: &mut StandardChannels,
    values: &mut [StandardStep],
    approaches: &[(usize, String)],
) {
    channels.approaches = true;
    for (step, text) in approaches {
        if let Some(value) = values.get_mut(*step) {
            value.approach = Some(text.clone());
        }
    }
}

/// The pose of a link in its tf parent's frame: the mount's pose for the root link, the joint's
/// origin and motion for the others.
fn local_pose(model: &lamp_robot::Robot, q: &[f64], link: LinkId) -> Pose {
    model.joint_transform(q, link).unwrap_or_else(|| model.mount().root_pose(q))
}

/// One scene object per body, its shapes from its type, coloured by role.
fn scene_objects(
    world: &SpecWorld,
    trajectory: &Trajectory,
) -> Result<Vec<SceneObject>, WorldError> {
    let spec = world.spec();
    let mut movable_types: Vec<&str> = spec
        .object_types
        .iter()
        .filter(|object_type| object_type.mobility == lamp_spec::Mobility::Movable)
        .map(|object_type| object_type.name.as_str())
        .collect();
    movable_types.sort_unstable();
    trajectory
        .header
        .bodies
        .iter()
        .map(|body| {
            let unknown =
                || WorldError::UnknownName { what: "object type", name: body.type_name.clone() };
            let object_type = spec.object_type(&body.type_name).ok_or_else(unknown)?;
            let parts = world.type_parts.get(&body.type_name).ok_or_else(unknown)?;
            let color = if object_type.world {
                WORLD_COLOR
            } else if let Ok(index) = movable_types.binary_search(&body.type_name.as_str()) {
                MOVABLE_COLORS[index % MOVABLE_COLORS.len()]
            } else {
                STATIC_COLOR
            };
            Ok(SceneObject {
                id: body.name.clone(),
                frame: body.name.clone(),
                type_name: body.type_name.clone(),
                color,
                primitives: parts.iter().map(|(pose, shape)| primitive(pose, shape)).collect(),
            })
        })
        .collect()
}

/// The viewer primitive of a shape; a convex hull is drawn as its points' bounding box.
fn primitive(pose: &Pose, shape: &Shape) -> Primitive {
    let pose = *pose;
    match shape {
        Shape::Box { half_extents } => {
            let size = half_extents * 2.0;
            Primitive::Cube { pose, size: [size.x, size.y, size.z] }
        }
        Shape::Cylinder { radius, half_height } => {
            Primitive::Cylinder { pose, radius: *radius, height: 2.0 * half_height }
        }
        Shape::Sphere { radius } => Primitive::Sphere { pose, radius: *radius },
        Shape::ConvexHull { points } => {
            let mut low = [f64::INFINITY; 3];
            let mut high = [f64::NEG_INFINITY; 3];
            for point in points {
                for axis in 0..3 {
                    low[axis] = low[axis].min(point[axis]);
                    high[axis] = high[axis].max(point[axis]);
                }
            }
            if points.is_empty() {
                return Primitive::Cube { pose, size: [0.0; 3] };
            }
            let centre = nalgebra::Translation3::new(
                0.5 * (low[0] + high[0]),
                0.5 * (low[1] + high[1]),
                0.5 * (low[2] + high[2]),
            );
            let size = [high[0] - low[0], high[1] - low[1], high[2] - low[2]];
            Primitive::Cube { pose: pose * centre, size }
        }
        Shape::TriMesh { vertices, triangles } => Primitive::Triangles {
            pose,
            points: triangles
                .iter()
                .flatten()
                .filter_map(|index| vertices.get(*index as usize))
                .map(|point| [point.x, point.y, point.z])
                .collect(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plan_labels_cover_each_step_from_its_start_to_the_next() {
        let mut channels = StandardChannels::rooted_at(WORLD_FRAME);
        let step = StandardStep {
            frame_poses: Vec::new(),
            joint_positions: Vec::new(),
            label: None,
            approach: None,
            held: Vec::new(),
            trajectories: Vec::new(),
            gripper_commands: Vec::new(),
        };
        let mut values = vec![step; 6];
        let plan = ["(a1 x)".to_string(), "(a2 x)".to_string()];
        label_plan_steps(&mut channels, &mut values, &[1, 4], &plan);
        assert!(channels.step_labels);
        let labels: Vec<Option<&str>> = values.iter().map(|v| v.label.as_deref()).collect();
        assert_eq!(
            labels,
            [None, Some("(a1 x)"), Some("(a1 x)"), Some("(a1 x)"), Some("(a2 x)"), Some("(a2 x)")]
        );
    }
}
