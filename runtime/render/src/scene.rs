//! Drawing a scene: its bodies coloured by role and its robots' links at their configurations.

use lamp_geometry::{Point3, Pose};
use lamp_world::{Body, Scene, SceneRobot};

use crate::colour::{Role, style_for};
use crate::figure::{Figure, Placement, Solid};
use crate::layout::{RenderOptions, render};
use crate::outline::world_points;

/// Draws a scene in a top and a side view; the title defaults to "scene".
pub fn render_scene(scene: &Scene, options: &RenderOptions) -> String {
    let mut figure = Figure { title: "scene".to_string(), ..Figure::default() };
    add_scene(&mut figure, scene, Layer::Shown, &options.marked);
    render(&figure, options)
}

/// Which copy of a scene is being added to a figure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Layer {
    /// The scene itself, labelled.
    Shown,
    /// An earlier state, faded and unlabelled, and only what moves (the rest is drawn once).
    Faded,
}

/// Adds the scene's bodies and robots to the figure, the bodies named in `marked` outlined.
pub(crate) fn add_scene(figure: &mut Figure, scene: &Scene, layer: Layer, marked: &[String]) {
    let faded = layer == Layer::Faded;
    for (index, body) in scene.bodies().iter().enumerate() {
        if faded && !body.movable {
            continue;
        }
        let role = role_of(body);
        let mut style = style_for(role, &body.name, faded);
        style.marked = !faded && marked.contains(&body.name);
        let pose = scene.body_pose(index);
        let placement = if body.movable { Placement::Middle } else { Placement::Corner };
        let label = (!faded).then_some(placement);
        figure.add_body(&body.name, &pose, &body.parts, &style, role == Role::World, label);
    }
    for robot in scene.robots() {
        add_robot(figure, robot, faded);
    }
}

fn role_of(body: &Body) -> Role {
    if body.movable {
        Role::Movable
    } else if body.world {
        Role::World
    } else {
        Role::Surface
    }
}

/// Adds every link's collision geometry at the robot's configuration, labelled with its name.
fn add_robot(figure: &mut Figure, robot: &SceneRobot, faded: bool) {
    let model = robot.robot();
    let q = robot.configuration();
    if q.len() != model.dof() {
        return; // a scene never holds such a robot; drawing nothing beats a panic
    }
    let mut poses = vec![Pose::identity(); model.link_count()];
    model.forward_kinematics(q, &mut poses);
    let style = style_for(Role::Robot, &robot.name, faded);
    let mut all: Vec<Point3> = Vec::new();
    for geometry in model.collision_geometry() {
        let Some(link_pose) = poses.get(geometry.link) else { continue };
        let points = world_points(&(link_pose * geometry.origin), &geometry.shape);
        all.extend_from_slice(&points);
        figure.solids.push(Solid { points, style: style.clone(), backdrop: false });
    }
    if !faded {
        figure.add_label(&robot.name, &all, false, Placement::Middle);
    }
}
