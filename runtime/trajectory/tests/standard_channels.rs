//! The standard ROS 2 and Foxglove channels beside `/lamp/world`: the reader ignores them and
//! returns the same steps, the `/lamp/world` messages are the same bytes as in a file without
//! them, the bytes are deterministic, what is written once is at time zero, labels are written
//! only when they change, frames and joints when they move (and once a second), and the writer
//! refuses values that do not fit the layout.

#![allow(clippy::unwrap_used)] // a failed step is a failed test

mod common;

use std::collections::BTreeMap;
use std::io::Cursor;

use lamp_trajectory::{
    DERIVED_FRAME_PERIOD_NANOSECONDS, IN_MEMORY_NAME, Primitive, RobotModelText, SceneObject,
    StandardChannels, StandardStep, StaticFrame, TF_REFRESH_NANOSECONDS, TfFrame, Trajectory,
    TrajectoryError, TrajectoryReader, TrajectoryWriter, read_standard_channels,
};
use nalgebra::Isometry3;

fn channels(trajectory: &Trajectory, step_labels: bool) -> StandardChannels {
    let world =
        |frame: &str| TfFrame { parent: "world".into(), frame: frame.into(), derived: false };
    let mut frames: Vec<TfFrame> =
        trajectory.header.bodies.iter().map(|body| world(&body.name)).collect();
    frames.push(TfFrame { parent: "map".into(), frame: "base_link".into(), derived: false });
    StandardChannels {
        world_frame: "world".into(),
        frames,
        static_frames: vec![StaticFrame {
            parent: "world".into(),
            frame: "map".into(),
            pose: Isometry3::identity(),
        }],
        joints: vec!["torso".into(), "j1".into()],
        robots: vec![RobotModelText {
            topic: "/robot_description".into(),
            urdf: "<robot name=\"r\"/>".into(),
        }],
        objects: vec![SceneObject {
            id: "can_0".into(),
            frame: "can_0".into(),
            type_name: "can".into(),
            color: [1.0, 0.0, 0.0, 1.0],
            primitives: vec![Primitive::Sphere { pose: Isometry3::identity(), radius: 0.1 }],
        }],
        step_labels,
        approaches: false,
        held_topics: vec!["/lamp/held".into()],
        trajectory_topics: Vec::new(),
        gripper_topics: Vec::new(),
    }
}

/// Per step: the bodies' poses, the first robot's base at its first coordinates, two joints, and
/// a label that changes every ten steps.
fn values(trajectory: &Trajectory) -> Vec<StandardStep> {
    trajectory
        .steps
        .iter()
        .enumerate()
        .map(|(index, step)| {
            let mut frame_poses = step.body_poses.clone();
            frame_poses
                .push(common::random_pose(&mut rand::SeedableRng::seed_from_u64(index as u64)));
            StandardStep {
                frame_poses,
                joint_positions: step.robots[0].positions[3..5].to_vec(),
                label: Some(format!("(step {})", index / 10)),
                approach: None,
                held: vec![if step.robots[0].held[0].is_some() { "can_0" } else { "" }.into()],
                trajectories: Vec::new(),
                gripper_commands: Vec::new(),
            }
        })
        .collect()
}

/// Every message of a file: topic → (log time, sequence, data), in file order.
fn messages(bytes: &[u8]) -> BTreeMap<String, Vec<(u64, u32, Vec<u8>)>> {
    let mut topics: BTreeMap<String, Vec<(u64, u32, Vec<u8>)>> = BTreeMap::new();
    for message in mcap::MessageStream::new(bytes).unwrap() {
        let message = message.unwrap();
        topics.entry(message.channel.topic.clone()).or_default().push((
            message.log_time,
            message.sequence,
            message.data.into_owned(),
        ));
    }
    topics
}

#[test]
fn the_reader_ignores_the_standard_channels_and_world_messages_are_unchanged() {
    let trajectory = common::trajectory(3, 35, 7);
    let plain = trajectory.to_bytes().unwrap();
    let with =
        trajectory.to_bytes_with(&channels(&trajectory, true), &values(&trajectory)).unwrap();
    assert_eq!(
        TrajectoryReader::from_bytes(&with, "with").unwrap().read_all().unwrap(),
        trajectory
    );
    let (plain, with) = (messages(&plain), messages(&with));
    assert_eq!(plain["/lamp/world"], with["/lamp/world"]);
    assert_eq!(with["/tf"].len(), 35);
    assert_eq!(with["/joint_states"].len(), 35);
    let once: Vec<_> = ["/robot_description", "/tf_static", "/lamp/scene"]
        .iter()
        .map(|topic| (with[*topic].len(), with[*topic][0].0))
        .collect();
    assert_eq!(once, vec![(1, 0); 3]);
    // Labels change at steps 0, 10, 20 and 30: four messages, at those steps' times.
    let labels = &with["/lamp/step"];
    let times: Vec<u64> = labels.iter().map(|(time, _, _)| *time).collect();
    let expected: Vec<u64> =
        [0, 10, 20, 30].iter().map(|step| trajectory.steps[*step].time_nanoseconds).collect();
    assert_eq!(times, expected);
    assert_eq!(labels.iter().map(|(_, sequence, _)| *sequence).collect::<Vec<_>>(), [0, 1, 2, 3]);
    assert_eq!(&labels[1].2[8..], b"(step 1)\0");
    // The gripper holds can_0 in the middle third: held at steps 0 (nothing), 11 and 23.
    let held: Vec<(u64, Vec<u8>)> =
        with["/lamp/held"].iter().map(|(time, _, data)| (*time, data[8..].to_vec())).collect();
    let time = |step: usize| trajectory.steps[step].time_nanoseconds;
    let expected = vec![
        (time(0), b"\0".to_vec()),
        (time(11), b"can_0\0".to_vec()),
        (time(23), b"\0".to_vec()),
    ];
    assert_eq!(held, expected);
}

#[test]
fn files_with_standard_channels_are_deterministic() {
    let trajectory = common::trajectory(2, 20, 3);
    let write = || trajectory.to_bytes_with(&channels(&trajectory, true), &values(&trajectory));
    assert_eq!(write().unwrap(), write().unwrap());
}

#[test]
fn values_that_do_not_fit_the_layout_are_refused() {
    let trajectory = common::trajectory(2, 5, 3);
    let mut values = values(&trajectory);
    // Labels on a file without the label channel.
    let error = trajectory.to_bytes_with(&channels(&trajectory, false), &values).unwrap_err();
    assert!(matches!(error, TrajectoryError::Inconsistent { step: 0, .. }), "{error}");
    values[3].label = None;
    values[3].frame_poses.pop();
    let error = trajectory.to_bytes_with(&channels(&trajectory, true), &values).unwrap_err();
    assert!(
        matches!(&error, TrajectoryError::Inconsistent { step: 3, reason, .. } if reason.contains("tf frame poses")),
        "{error}"
    );
    let error = trajectory.to_bytes_with(&channels(&trajectory, true), &values[..2]).unwrap_err();
    assert!(matches!(error, TrajectoryError::Inconsistent { .. }), "{error}");
    // A plain step on a writer with standard channels, and the other way round.
    let header = trajectory.header.clone();
    let sink = Cursor::new(Vec::new());
    let mut writer = TrajectoryWriter::with_standard_channels(
        sink,
        IN_MEMORY_NAME,
        header.clone(),
        channels(&trajectory, true),
    )
    .unwrap();
    assert!(writer.write_step(&trajectory.steps[0]).is_err());
    let mut writer =
        TrajectoryWriter::new(Cursor::new(Vec::new()), IN_MEMORY_NAME, header).unwrap();
    assert!(writer.write_step_with(&trajectory.steps[0], &values[0]).is_err());
}

#[test]
fn channels_that_cannot_be_written_are_refused_before_anything_is_written() {
    let trajectory = common::trajectory(2, 5, 3);
    let mut bad = channels(&trajectory, false);
    let pose = Isometry3::identity();
    bad.static_frames.push(StaticFrame { parent: "world".into(), frame: "can_0".into(), pose });
    let header = trajectory.header.clone();
    let error = TrajectoryWriter::with_standard_channels(Cursor::new(Vec::new()), "x", header, bad)
        .err()
        .unwrap();
    assert!(
        matches!(&error, TrajectoryError::Header { reason, .. } if reason.contains("`can_0` is listed twice")),
        "{error}"
    );
}

#[test]
fn the_standard_channels_read_back_as_written() {
    let trajectory = common::trajectory(2, 12, 5);
    let (channels, values) = (channels(&trajectory, false), values(&trajectory));
    let values: Vec<StandardStep> =
        values.into_iter().map(|value| StandardStep { label: None, ..value }).collect();
    let bytes = trajectory.to_bytes_with(&channels, &values).unwrap();
    let recording = read_standard_channels(bytes.as_slice(), "bag", &["/lamp/held"]).unwrap();
    assert_eq!(recording.tf.len(), 12);
    for ((message, step), value) in recording.tf.iter().zip(&trajectory.steps).zip(&values) {
        assert_eq!(message.log_time, step.time_nanoseconds);
        let read: Vec<(&str, &str, u64, Isometry3<f64>)> = message
            .transforms
            .iter()
            .map(|t| (t.parent.as_str(), t.frame.as_str(), t.stamp_nanoseconds, t.pose))
            .collect();
        let written: Vec<(&str, &str, u64, Isometry3<f64>)> = channels
            .frames
            .iter()
            .zip(&value.frame_poses)
            .map(|(f, pose)| (f.parent.as_str(), f.frame.as_str(), step.time_nanoseconds, *pose))
            .collect();
        assert_eq!(read, written);
    }
    assert_eq!(recording.tf_static.len(), 1);
    assert_eq!(recording.tf_static[0].transforms[0].frame, "map");
    let joints: Vec<(Vec<String>, Vec<f64>)> =
        recording.joint_states.iter().map(|j| (j.names.clone(), j.positions.clone())).collect();
    let expected: Vec<(Vec<String>, Vec<f64>)> =
        values.iter().map(|v| (channels.joints.clone(), v.joint_positions.clone())).collect();
    assert_eq!(joints, expected);
    let held: Vec<&str> = recording.strings["/lamp/held"].iter().map(|(_, t)| t.as_str()).collect();
    assert_eq!(held, ["", "can_0", ""]);
}

#[test]
fn a_filtered_copy_keeps_the_chosen_messages_at_the_chosen_times() {
    let trajectory = common::trajectory(2, 6, 5);
    let (channels, values) = (channels(&trajectory, true), values(&trajectory));
    let bytes = trajectory.to_bytes_with(&channels, &values).unwrap();
    let bag = lamp_trajectory::filter_bag(&bytes, "bag", |topic, time| {
        (topic != "/lamp/world").then_some(time + 1)
    })
    .unwrap();
    // No lamp record and no /lamp/world: a plain bag of the other channels, one nanosecond later.
    assert!(matches!(
        TrajectoryReader::from_bytes(&bag, "bag").err(),
        Some(TrajectoryError::Schema { .. })
    ));
    let (before, after) = (messages(&bytes), messages(&bag));
    assert!(!after.contains_key("/lamp/world"));
    assert_eq!(after.len(), before.len() - 1);
    for (topic, list) in &after {
        let shifted: Vec<_> = before[topic]
            .iter()
            .map(|(time, sequence, data)| (time + 1, *sequence, data.clone()))
            .collect();
        assert_eq!(list, &shifted, "{topic}");
    }
}

/// A body that rests, then moves; a derived link that moves at every 10 ms step; a joint that
/// rests in the middle third.
fn resting_and_moving(steps: usize) -> (Trajectory, StandardChannels, Vec<StandardStep>) {
    let mut trajectory = common::trajectory(1, steps, 3);
    let resting = common::random_pose(&mut rand::SeedableRng::seed_from_u64(1));
    for (index, step) in trajectory.steps.iter_mut().enumerate() {
        step.time_nanoseconds = index as u64 * 10_000_000;
        if index < steps / 2 {
            step.body_poses[0] = resting;
        }
    }
    let channels = StandardChannels {
        frames: vec![
            TfFrame { parent: "world".into(), frame: "can_0".into(), derived: false },
            TfFrame { parent: "can_0".into(), frame: "link".into(), derived: true },
        ],
        joints: vec!["j".into()],
        ..StandardChannels::rooted_at("world")
    };
    let values = trajectory
        .steps
        .iter()
        .enumerate()
        .map(|(index, step)| {
            let link = common::random_pose(&mut rand::SeedableRng::seed_from_u64(index as u64));
            let joint =
                if (steps / 3..2 * steps / 3).contains(&index) { 0.5 } else { index as f64 };
            StandardStep {
                frame_poses: vec![step.body_poses[0], link],
                joint_positions: vec![joint],
                label: None,
                approach: None,
                held: vec![],
                trajectories: Vec::new(),
                gripper_commands: Vec::new(),
            }
        })
        .collect();
    (trajectory, channels, values)
}

#[test]
fn frames_are_written_when_they_move_derived_ones_at_most_every_period_and_all_every_second() {
    let steps = 300; // three seconds of 10 ms steps
    let (trajectory, channels, values) = resting_and_moving(steps);
    let bytes = trajectory.to_bytes_with(&channels, &values).unwrap();
    let recording = read_standard_channels(bytes.as_slice(), "bag", &[]).unwrap();
    // One /tf message per step, even when nothing in it moved.
    assert_eq!(recording.tf.len(), steps);
    let mut last_written: BTreeMap<&str, (usize, Isometry3<f64>)> = BTreeMap::new();
    for (index, message) in recording.tf.iter().enumerate() {
        let time = trajectory.steps[index].time_nanoseconds;
        assert_eq!(message.log_time, time);
        let frames: Vec<&str> = message.transforms.iter().map(|t| t.frame.as_str()).collect();
        let period = (DERIVED_FRAME_PERIOD_NANOSECONDS / 10_000_000) as usize;
        let refresh = (TF_REFRESH_NANOSECONDS / 10_000_000) as usize;
        // The resting body: at the first step, then once a second, then at every step it moves.
        let body_expected = index == 0 || index >= steps / 2 || index % refresh == 0;
        assert_eq!(frames.contains(&"can_0"), body_expected, "step {index}: {frames:?}");
        // The moving link: every period, and at the last step.
        let link_expected = index % period == 0 || index + 1 == steps;
        assert_eq!(frames.contains(&"link"), link_expected, "step {index}: {frames:?}");
        for transform in &message.transforms {
            let frame = if transform.frame == "can_0" { 0 } else { 1 };
            assert_eq!(transform.pose, values[index].frame_poses[frame], "step {index}");
            assert_eq!(transform.stamp_nanoseconds, time);
            last_written.insert(if frame == 0 { "can_0" } else { "link" }, (index, transform.pose));
        }
        // What a viewer holds for the body is its pose at this step.
        assert_eq!(last_written["can_0"].1, values[index].frame_poses[0]);
    }
    assert_eq!(last_written["link"].1, values[steps - 1].frame_poses[1]);
    // /joint_states: at every change, and once a second while the joint rests.
    let times: Vec<u64> = recording.joint_states.iter().map(|j| j.log_time).collect();
    let expected: Vec<u64> = (0..steps)
        .filter(|index| {
            let resting = (steps / 3 + 1..2 * steps / 3).contains(index);
            !resting || (index - steps / 3) % 100 == 0
        })
        .map(|index| trajectory.steps[index].time_nanoseconds)
        .collect();
    assert_eq!(times, expected);
}

#[test]
fn the_last_steps_tf_is_written_by_finish() {
    let (trajectory, channels, values) = resting_and_moving(5);
    let mut writer = TrajectoryWriter::with_standard_channels(
        Cursor::new(Vec::new()),
        "x",
        trajectory.header.clone(),
        channels,
    )
    .unwrap();
    for (step, value) in trajectory.steps.iter().zip(&values) {
        writer.write_step_with(step, value).unwrap();
    }
    let bytes = writer.finish().unwrap().into_inner();
    let recording = read_standard_channels(bytes.as_slice(), "bag", &[]).unwrap();
    assert_eq!(recording.tf.len(), 5);
    let last = &recording.tf[4].transforms;
    assert!(last.iter().any(|t| t.frame == "link" && t.pose == values[4].frame_poses[1]));
}
