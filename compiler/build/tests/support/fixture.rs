//! Synthetic demonstration files: lamp-learn's synthetic Packing demonstrations written as MCAP
//! trajectories that match `domains/packing/packing.lamp`. Real demonstrations come from
//! lamp-demonstrators; these small, hand-shaped files serve the adapter's tests and lampc's
//! command-line tests, which need files quickly and exactly known.
//!
//! Shared by lamp-build's tests and lampc's (included there with `#[path]`), so it depends only on
//! lamp-learn, lamp-robot, lamp-trajectory and nalgebra.
//!
//! Mapping: the synthetic `gripper1` (type `gripper`) is the spec robot `gripper`, a free-flying
//! magnetic gripper whose root link `gripper_link` is its `gripper` part, so its six floating
//! coordinates are the synthetic gripper pose; `can1` is a `can`; `box1` is a `surface`; a static
//! world `table1` of type `table` is added at the origin. The box frame is turned half a turn about
//! its z axis: the synthetic demonstrator puts cans in the box at a relative yaw of π ± 0.15 rad, and
//! the box is symmetric under that turn, so the same scene is described with cans at yaw 0 ± 0.15 rad
//! in the box, as the spec's `in_box` example pose `(0, 0, 0.001) m` (no rotation) expects.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use lamp_learn::synthetic::packing_demonstrations;
use lamp_robot::{Mount, Robot};
use lamp_trajectory::{
    BodyDescription, RobotDescription, RobotState, Step, Trajectory, TrajectoryHeader,
};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

/// The workspace root (both users of this file live in `compiler/<crate>`).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The Packing spec file.
pub fn packing_spec_path() -> PathBuf {
    workspace_root().join("domains/packing/packing.lamp")
}

/// The Packing robot model, with the mount its spec kind (`free_flying`) implies.
pub fn packing_gripper() -> Robot {
    let urdf = workspace_root().join("domains/robots/magnetic_gripper.urdf");
    Robot::from_urdf_file(&urdf, Mount::Floating).expect("the magnetic gripper loads")
}

/// `count` fixture files from one seed, named `demo_000.mcap`, … with their bytes.
pub fn packing_fixture(count: usize, seed: u64, gripper: &Robot) -> Vec<(String, Vec<u8>)> {
    let flip = Isometry3::from_parts(
        nalgebra::Translation3::identity(),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), PI),
    );
    packing_demonstrations(count, seed)
        .into_iter()
        .enumerate()
        .map(|(index, demonstration)| {
            let header = TrajectoryHeader {
                domain: "packing".into(),
                seed,
                provenance: BTreeMap::from([
                    ("demonstrator".to_string(), "lamp-learn synthetic packing".to_string()),
                    ("demo_index".to_string(), index.to_string()),
                ]),
                bodies: vec![
                    BodyDescription { name: "can1".into(), type_name: "can".into() },
                    BodyDescription { name: "box1".into(), type_name: "surface".into() },
                    BodyDescription { name: "table1".into(), type_name: "table".into() },
                ],
                robots: vec![RobotDescription {
                    name: "gripper".into(),
                    coordinates: gripper.coordinate_names().to_vec(),
                    grippers: vec!["gripper".into()],
                }],
            };
            let steps = demonstration
                .steps
                .iter()
                .enumerate()
                .map(|(step, snapshot)| {
                    // Synthetic participants: gripper1, can1, box1.
                    let mut q = gripper.neutral_configuration();
                    gripper.mount().write_coordinates(&snapshot.poses[0], &mut q);
                    Step {
                        time_nanoseconds: step as u64 * 100_000_000,
                        body_poses: vec![
                            snapshot.poses[1],
                            snapshot.poses[2] * flip,
                            Isometry3::identity(),
                        ],
                        robots: vec![RobotState {
                            positions: q,
                            held: vec![snapshot.held.contains(&(0, 1)).then_some(0)],
                        }],
                    }
                })
                .collect();
            let bytes = Trajectory { header, steps }.to_bytes().expect("the fixture encodes");
            (format!("demo_{index:03}.mcap"), bytes)
        })
        .collect()
}

/// Writes `count` fixture files into `dir`.
pub fn write_packing_fixture(dir: &Path, count: usize, seed: u64) {
    std::fs::create_dir_all(dir).expect("the fixture folder can be created");
    for (name, bytes) in packing_fixture(count, seed, &packing_gripper()) {
        std::fs::write(dir.join(name), bytes).expect("the fixture file can be written");
    }
}
