//! The MCAP files lampc writes, demonstrations and solutions alike: lamp's own channel with the
//! standard ones beside it, so that any ROS 2 or Foxglove tool reads them.

/// What a solution's file says beyond its steps.
pub(crate) struct SolutionMarks<'a> {
    /// Each plan step's first trajectory step, and its text.
    pub(crate) starts: &'a [usize],
    pub(crate) plan: &'a [String],
    /// Each approach into contact's first trajectory step, and its description.
    pub(crate) approaches: &'a [(usize, String)],
}

/// The file's bytes with the standard ROS 2 and Foxglove channels beside `/lamp/world`, so
/// that Foxglove and RViz show the robot and the objects (`docs/formats.md`); with a solution's
/// marks, the step being executed on `/lamp/step`, the approaches into contact on
/// `/lamp/approach`, and the channels a controller executes (a solution's joint trajectories and
/// gripper commands: it is timed within the robots' limits, which a demonstration is not).
pub(crate) fn mcap_bytes(
    world: &lamp_world::SpecWorld,
    trajectory: &lamp_trajectory::Trajectory,
    solution: Option<SolutionMarks<'_>>,
) -> Result<Vec<u8>, Box<dyn miette::Diagnostic + Send + Sync>> {
    let (mut channels, mut values) = lamp_world::standard_channels(world, trajectory)?;
    if let Some(marks) = solution {
        lamp_world::label_plan_steps(&mut channels, &mut values, marks.starts, marks.plan);
        lamp_world::mark_approaches(&mut channels, &mut values, marks.approaches);
        lamp_world::execution_channels(world, trajectory, &mut channels, &mut values)?;
    }
    Ok(trajectory.to_bytes_with(&channels, &values)?)
}
