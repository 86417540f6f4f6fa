//! Writing and reading 100 000 steps of two scenes, and writing them with the standard channels
//! viewers read:
//! - Café-like: ten bodies and one 11-coordinate robot, `/tf` with the ten bodies and a
//!   Fetch-like tree of a moving base and eleven moving joints (every joint moves at every
//!   step), `/joint_states`;
//! - Packing-like: three bodies and a free-flying gripper (six mount coordinates, one link),
//!   `/tf` with the bodies and the gripper, no joints.
//!
//! Prints the file sizes per step once; criterion reports the time (divide by 100 000 for
//! steps/s).

// The benchmark reports the file size on the terminal.
#![allow(clippy::print_stdout)]

use std::hint::black_box;
use std::io::Cursor;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use lamp_trajectory::{
    BodyDescription, RobotDescription, RobotModelText, RobotState, StandardChannels, StandardStep,
    StaticFrame, Step, TfFrame, Trajectory, TrajectoryHeader, TrajectoryReader, TrajectoryWriter,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};

const STEPS: usize = 100_000;

/// The shape of a benchmark scene.
struct Scene {
    name: &'static str,
    bodies: usize,
    /// The robot's coordinates: the mount's, then one per joint.
    coordinates: usize,
    /// Joints (links below the root, each moving with one coordinate, on `/joint_states`).
    joints: usize,
}

const CAFE: Scene = Scene { name: "cafe_like", bodies: 10, coordinates: 11, joints: 11 };
const PACKING: Scene = Scene { name: "packing_like", bodies: 3, coordinates: 6, joints: 0 };

/// A smooth motion, like a real demonstration (random numbers would not compress at all).
fn trajectory(scene: &Scene) -> Trajectory {
    let header = TrajectoryHeader {
        domain: scene.name.into(),
        seed: 0,
        provenance: Default::default(),
        bodies: (0..scene.bodies)
            .map(|index| BodyDescription { name: format!("can_{index}"), type_name: "can".into() })
            .collect(),
        robots: vec![RobotDescription {
            name: "robot".into(),
            coordinates: (0..scene.coordinates).map(|index| format!("joint_{index}")).collect(),
            grippers: vec!["gripper".into()],
        }],
    };
    let steps = (0..STEPS)
        .map(|index| {
            let time = index as f64 * 0.01;
            let moving = index % scene.bodies;
            Step {
                time_nanoseconds: index as u64 * 10_000_000,
                body_poses: (0..scene.bodies)
                    .map(|body| {
                        let phase = if body == moving { time } else { body as f64 };
                        Isometry3::from_parts(
                            Translation3::new(phase.cos(), phase.sin(), 0.75 + 0.01 * body as f64),
                            UnitQuaternion::from_euler_angles(0.0, 0.0, phase),
                        )
                    })
                    .collect(),
                robots: vec![RobotState {
                    positions: (0..scene.coordinates)
                        .map(|joint| (time + joint as f64).sin())
                        .collect(),
                    held: vec![Some(moving)],
                }],
            }
        })
        .collect();
    Trajectory { header, steps }
}

fn write(trajectory: &Trajectory) -> Vec<u8> {
    let mut writer =
        TrajectoryWriter::new(Cursor::new(Vec::new()), "bench", trajectory.header.clone())
            .expect("the header is valid");
    for step in &trajectory.steps {
        writer.write_step(step).expect("the steps are valid");
    }
    writer.finish().expect("writing to memory succeeds").into_inner()
}

/// The channels of the scene: bodies below `world`, the robot's root below `world`, each joint's
/// link below the previous link, a fixed camera link on `/tf_static`.
fn channels(scene: &Scene, trajectory: &Trajectory) -> StandardChannels {
    let mut frames: Vec<TfFrame> = trajectory
        .header
        .bodies
        .iter()
        .map(|body| TfFrame { parent: "world".into(), frame: body.name.clone(), derived: false })
        .collect();
    frames.push(TfFrame { parent: "world".into(), frame: "base_link".into(), derived: false });
    let mut parent = "base_link".to_string();
    for joint in 0..scene.joints {
        let frame = format!("link_{joint}");
        frames.push(TfFrame { parent: parent.clone(), frame: frame.clone(), derived: true });
        parent = frame;
    }
    let coordinates = &trajectory.header.robots[0].coordinates;
    StandardChannels {
        world_frame: "world".into(),
        frames,
        static_frames: vec![StaticFrame {
            parent: "base_link".into(),
            frame: "camera_link".into(),
            pose: Isometry3::identity(),
        }],
        joints: coordinates[coordinates.len() - scene.joints..].to_vec(),
        robots: vec![RobotModelText {
            topic: "/robot_description".into(),
            urdf: "<robot/>".into(),
        }],
        objects: vec![],
        step_labels: false,
        approaches: false,
        held_topics: vec![],
        trajectory_topics: Vec::new(),
        gripper_topics: Vec::new(),
    }
}

/// Per step: the bodies' poses, the root moving with the first coordinates, each joint a
/// rotation about z.
fn values(scene: &Scene, trajectory: &Trajectory) -> Vec<StandardStep> {
    trajectory
        .steps
        .iter()
        .map(|step| {
            let q = &step.robots[0].positions;
            let joints = &q[q.len() - scene.joints..];
            let mut frame_poses = step.body_poses.clone();
            frame_poses.push(Isometry3::from_parts(
                Translation3::new(q[0], q[1], 0.0),
                UnitQuaternion::from_euler_angles(0.0, 0.0, q[2]),
            ));
            frame_poses.extend(joints.iter().map(|value| {
                Isometry3::from_parts(
                    Translation3::new(0.1, 0.0, 0.2),
                    UnitQuaternion::from_euler_angles(0.0, 0.0, *value),
                )
            }));
            StandardStep {
                frame_poses,
                joint_positions: joints.to_vec(),
                label: None,
                approach: None,
                held: vec![],
                trajectories: Vec::new(),
                gripper_commands: Vec::new(),
            }
        })
        .collect()
}

fn write_with_channels(
    trajectory: &Trajectory,
    channels: &StandardChannels,
    values: &[StandardStep],
) -> Vec<u8> {
    let sink = Cursor::new(Vec::new());
    let header = trajectory.header.clone();
    let mut writer =
        TrajectoryWriter::with_standard_channels(sink, "bench", header, channels.clone())
            .expect("the header and channels are valid");
    for (step, values) in trajectory.steps.iter().zip(values) {
        writer.write_step_with(step, values).expect("the steps are valid");
    }
    writer.finish().expect("writing to memory succeeds").into_inner()
}

fn benchmark_scene(criterion: &mut Criterion, scene: &Scene) {
    let trajectory = trajectory(scene);
    let bytes = write(&trajectory);
    println!(
        "{}: {STEPS} steps of {} bodies: {} bytes, {:.1} bytes per step",
        scene.name,
        scene.bodies,
        bytes.len(),
        bytes.len() as f64 / STEPS as f64
    );
    let (channels, values) = (channels(scene, &trajectory), values(scene, &trajectory));
    let viewable = write_with_channels(&trajectory, &channels, &values);
    println!(
        "{}: with the standard channels: {} bytes, {:.1} bytes per step ({:.2} times)",
        scene.name,
        viewable.len(),
        viewable.len() as f64 / STEPS as f64,
        viewable.len() as f64 / bytes.len() as f64
    );
    let mut group = criterion.benchmark_group(format!("trajectory_100k_steps_{}", scene.name));
    group.sample_size(10);
    group.throughput(Throughput::Elements(STEPS as u64));
    group.bench_function("write", |bencher| bencher.iter(|| black_box(write(&trajectory))));
    group.bench_function("write_with_standard_channels", |bencher| {
        bencher.iter(|| black_box(write_with_channels(&trajectory, &channels, &values)));
    });
    group.bench_function("read", |bencher| {
        bencher.iter(|| {
            let reader = TrajectoryReader::from_bytes(&bytes, "bench").expect("a valid file");
            let mut count = 0;
            for step in reader {
                black_box(step.expect("a valid step"));
                count += 1;
            }
            assert_eq!(count, STEPS);
        });
    });
    group.finish();
}

fn benchmark(criterion: &mut Criterion) {
    benchmark_scene(criterion, &CAFE);
    benchmark_scene(criterion, &PACKING);
}

criterion_group!(benches, benchmark);
criterion_main!(benches);
