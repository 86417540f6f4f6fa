//! Drawing a trajectory or demonstration: the first step faded, one later step solid, and the
//! path of each gripper over all steps.

use lamp_trajectory::Trajectory;
use lamp_world::{Scene, SpecWorld};

use crate::colour::PATH_COLOUR;
use crate::error::RenderError;
use crate::figure::{Figure, LegendEntry, Path};
use crate::layout::{RenderOptions, render};
use crate::replay::{GripperPath, Replay};
use crate::scene::{Layer, add_scene};

/// The robot colour at the faded opacity over white, for the legend's marker.
const FADED_LEGEND: &str = "#c6d3e5";

/// Draws `shown` over a faded `start` (its movable bodies and robots), with the gripper paths.
/// Pass the same scene twice to draw one state with its paths.
pub fn render_motion(
    start: Option<&Scene>,
    shown: &Scene,
    paths: &[GripperPath],
    options: &RenderOptions,
) -> String {
    let mut figure = Figure { title: "trajectory".to_string(), ..Figure::default() };
    if let Some(start) = start {
        add_scene(&mut figure, start, Layer::Faded, &options.marked);
    }
    add_scene(&mut figure, shown, Layer::Shown, &options.marked);
    for path in paths {
        figure.paths.push(Path { points: path.points.clone(), colour: PATH_COLOUR.to_string() });
        figure.legend.push(LegendEntry {
            text: format!("gripper path of {} (open circle: start)", path.robot),
            colour: PATH_COLOUR.to_string(),
            line: true,
        });
    }
    if start.is_some() {
        figure.legend.push(LegendEntry {
            text: "faded, dashed: first step".to_string(),
            colour: FADED_LEGEND.to_string(),
            line: false,
        });
    }
    render(&figure, options)
}

/// Draws a whole trajectory of `world`'s spec: step `step` (the last if `None`) over the first.
pub fn render_trajectory(
    world: &SpecWorld,
    trajectory: &Trajectory,
    step: Option<usize>,
    options: &RenderOptions,
) -> Result<String, RenderError> {
    let steps = &trajectory.steps;
    let Some(last) = steps.len().checked_sub(1) else {
        return Err(RenderError::Empty);
    };
    let shown_index = step.unwrap_or(last);
    let Some(shown_step) = steps.get(shown_index) else {
        return Err(RenderError::StepOutOfRange { step: shown_index, count: steps.len() });
    };
    let replay = Replay::new(world, &trajectory.header)?;
    let shown = replay.scene_at(shown_index, shown_step)?;
    let start = if shown_index == 0 { None } else { Some(replay.scene_at(0, &steps[0])?) };
    let paths = replay.gripper_paths(steps)?;
    let mut options = options.clone();
    if options.title.is_none() {
        options.title = Some(format!(
            "{} \u{b7} step {shown_index} of 0\u{2013}{last} (t = {:.2} s)",
            trajectory.header.domain,
            shown_step.time_seconds()
        ));
    }
    Ok(render_motion(start.as_ref(), &shown, &paths, &options))
}
