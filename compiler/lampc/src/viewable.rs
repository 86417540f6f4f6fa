//! The MCAP files lampc writes, demonstrations and solutions alike: lamp's own channel with the
//! standard ones beside it, so that any ROS 2 or Foxglove tool reads them.

/// The file's bytes with the standard ROS 2 and Foxglove channels beside `/lamp/world`, so
/// that Foxglove and RViz show the robot and the objects (`docs/formats.md`); with `plan`
/// (each plan step's first trajectory step and its text), the step being executed on
/// `/lamp/step`, and the channels a controller executes (a solution's joint trajectories and
/// gripper commands: it is timed within the robots' limits, which a demonstration is not).
pub(crate) fn mcap_bytes(
    world: &lamp_world::SpecWorld,
    trajectory: &lamp_trajectory::Trajectory,
    plan: Option<(&[usize], &[String])>,
) -> Result<Vec<u8>, Box<dyn miette::Diagnostic + Send + Sync>> {
    let (mut channels, mut values) = lamp_world::standard_channels(world, trajectory)?;
    if let Some((starts, steps)) = plan {
        lamp_world::label_plan_steps(&mut channels, &mut values, starts, steps);
        lamp_world::execution_channels(world, trajectory, &mut channels, &mut values)?;
    }
    Ok(trajectory.to_bytes_with(&channels, &values)?)
}
