//! Writing and reading 100 000 steps of a scene with ten bodies and one 11-coordinate robot.
//! Prints the file size per step once; criterion reports the time (divide by 100 000 for steps/s).

// The benchmark reports the file size on the terminal.
#![allow(clippy::print_stdout)]

use std::hint::black_box;
use std::io::Cursor;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use lamp_trajectory::{
    BodyDescription, RobotDescription, RobotState, Step, Trajectory, TrajectoryHeader,
    TrajectoryReader, TrajectoryWriter,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};

const STEPS: usize = 100_000;
const BODIES: usize = 10;
const COORDINATES: usize = 11;

/// A smooth motion, like a real demonstration (random numbers would not compress at all).
fn scene() -> Trajectory {
    let header = TrajectoryHeader {
        domain: "cafe".into(),
        seed: 0,
        provenance: Default::default(),
        bodies: (0..BODIES)
            .map(|index| BodyDescription { name: format!("can_{index}"), type_name: "can".into() })
            .collect(),
        robots: vec![RobotDescription {
            name: "fetch".into(),
            coordinates: (0..COORDINATES).map(|index| format!("joint_{index}")).collect(),
            grippers: vec!["gripper".into()],
        }],
    };
    let steps = (0..STEPS)
        .map(|index| {
            let time = index as f64 * 0.01;
            let moving = index % BODIES;
            Step {
                time_nanoseconds: index as u64 * 10_000_000,
                body_poses: (0..BODIES)
                    .map(|body| {
                        let phase = if body == moving { time } else { body as f64 };
                        Isometry3::from_parts(
                            Translation3::new(phase.cos(), phase.sin(), 0.75 + 0.01 * body as f64),
                            UnitQuaternion::from_euler_angles(0.0, 0.0, phase),
                        )
                    })
                    .collect(),
                robots: vec![RobotState {
                    positions: (0..COORDINATES).map(|joint| (time + joint as f64).sin()).collect(),
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

fn benchmark(criterion: &mut Criterion) {
    let trajectory = scene();
    let bytes = write(&trajectory);
    println!(
        "{STEPS} steps of {BODIES} bodies: {} bytes, {:.1} bytes per step",
        bytes.len(),
        bytes.len() as f64 / STEPS as f64
    );
    let mut group = criterion.benchmark_group("trajectory_100k_steps_10_bodies");
    group.sample_size(10);
    group.throughput(Throughput::Elements(STEPS as u64));
    group.bench_function("write", |bencher| bencher.iter(|| black_box(write(&trajectory))));
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

criterion_group!(benches, benchmark);
criterion_main!(benches);
