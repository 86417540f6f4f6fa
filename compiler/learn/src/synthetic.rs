//! A scripted Packing-like demonstrator, in memory, for the learner's tests and benchmarks: a free-flying gripper
//! grasps a can on a table, carries it into a box and retreats; half of the demonstrations stop at a random time step.
//!
//! Poses are scripted (straight-line interpolation, no collision checking); the domains' real demonstrators live
//! with their domains and write files.

use std::f64::consts::PI;

use nalgebra::{Translation3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::capacity::ShapeOracle;
use crate::config::{LearnConfig, PairSettings, TypePair};
use crate::demo::{Demonstration, Participant, Pose, Role, Snapshot};

/// Height of the gripper frame above the can's base frame at the grasp.
pub const GRASP_HEIGHT: f64 = 0.21;

/// `count` demonstrations from one seed; odd-numbered ones are cut short.
pub fn packing_demonstrations(count: usize, seed: u64) -> Vec<Demonstration> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count).map(|index| packing_demonstration(index, index % 2 == 1, &mut rng)).collect()
}

fn participants() -> Vec<Participant> {
    gripper_object_and_fixed(("can1", "can"), ("box1", "surface"))
}

/// A gripper `gripper1`, a movable object and a fixed one, each given as (name, type), in that order.
fn gripper_object_and_fixed(object: (&str, &str), fixed: (&str, &str)) -> Vec<Participant> {
    let participant = |(name, type_name): (&str, &str), role| Participant {
        name: name.into(),
        type_name: type_name.into(),
        role,
    };
    vec![
        participant(("gripper1", "gripper"), Role::RobotPart { gripper: true }),
        participant(object, Role::Object { movable: true }),
        participant(fixed, Role::Object { movable: false }),
    ]
}

fn yaw(angle: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), angle)
}

fn grasp_offset(rng: &mut ChaCha8Rng) -> Pose {
    let noise = Vector3::from_fn(|_, _| rng.random_range(-0.003..0.003));
    Pose::from_parts(
        Translation3::from(Vector3::new(0.0, 0.0, GRASP_HEIGHT) + noise),
        yaw(-PI / 4.0),
    )
}

fn interpolate(from: &Pose, to: &Pose, steps: usize) -> Vec<Pose> {
    (1..=steps)
        .map(|step| {
            let t = step as f64 / steps as f64;
            let position = from.translation.vector.lerp(&to.translation.vector, t);
            let rotation = from.rotation.try_slerp(&to.rotation, t, 1e-9).unwrap_or(to.rotation);
            Pose::from_parts(position.into(), rotation)
        })
        .collect()
}

fn packing_demonstration(index: usize, truncated: bool, rng: &mut ChaCha8Rng) -> Demonstration {
    let box_pose = Pose::from_parts(
        Translation3::new(rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3), 0.0),
        yaw(rng.random_range(-PI..PI)),
    );
    let can_start = loop {
        let candidate = Pose::from_parts(
            Translation3::new(rng.random_range(-0.4..0.4), rng.random_range(-0.4..0.4), 0.001),
            yaw(rng.random_range(-PI..PI)),
        );
        if (candidate.translation.vector - box_pose.translation.vector).norm() > 0.3 {
            break candidate;
        }
    };
    let gripper_start = Pose::from_parts(
        Translation3::new(
            rng.random_range(-0.4..0.4),
            rng.random_range(-0.4..0.4),
            rng.random_range(0.3..0.8),
        ),
        UnitQuaternion::from_euler_angles(
            rng.random_range(-0.4..0.4),
            rng.random_range(-0.4..0.4),
            rng.random_range(-PI..PI),
        ),
    );
    // The can goes in the box turned half a turn (± a little), so its relative yaw straddles ±π.
    let placement = box_pose
        * Pose::from_parts(
            Translation3::new(rng.random_range(-0.01..0.01), rng.random_range(-0.01..0.01), 0.001),
            yaw(PI + rng.random_range(-0.15..0.15)),
        );
    let grasp = grasp_offset(rng);
    let mut steps: Vec<Snapshot> = Vec::new();
    let snapshot = |gripper: Pose, can: Pose, held: bool| Snapshot {
        poses: vec![gripper, can, box_pose],
        held: if held { vec![(0, 1)] } else { vec![] },
    };
    steps.push(snapshot(gripper_start, can_start, false));
    // Approach.
    let grasp_pose = can_start * grasp;
    for gripper in interpolate(&gripper_start, &grasp_pose, rng.random_range(6..10)) {
        steps.push(snapshot(gripper, can_start, false));
    }
    // Grasp.
    steps.push(snapshot(grasp_pose, can_start, true));
    // Lift, carry above the box, lower into it.
    let lifted = Pose::translation(0.0, 0.0, 0.3) * can_start;
    let above = Pose::translation(0.0, 0.0, 0.3) * placement;
    let mut can_path = interpolate(&can_start, &lifted, 3);
    can_path.extend(interpolate(&lifted, &above, rng.random_range(6..10)));
    can_path.extend(interpolate(&above, &placement, 2));
    for can in can_path {
        steps.push(snapshot(can * grasp, can, true));
    }
    // Release, then retreat to a random pose well above the table.
    let release_pose = placement * grasp;
    steps.push(snapshot(release_pose, placement, false));
    let retreat = Pose::from_parts(
        Translation3::new(
            rng.random_range(-0.4..0.4),
            rng.random_range(-0.4..0.4),
            rng.random_range(0.45..0.8),
        ),
        UnitQuaternion::from_euler_angles(0.0, 0.0, rng.random_range(-PI..PI)),
    );
    for gripper in interpolate(&release_pose, &retreat, rng.random_range(6..10)) {
        steps.push(snapshot(gripper, placement, false));
    }
    if truncated {
        let keep = rng.random_range(2..steps.len());
        steps.truncate(keep);
    }
    Demonstration { id: format!("packing-{index:03}"), participants: participants(), steps }
}

/// Settings for the synthetic task: a fine gripper–can grid, a coarse box grid whose clear and nowhere relations
/// [`packing_shapes`] decides, gripper–box relations left out as the reference code does, and 25 rotation bins so that the upright poses of the task lie mid-cell rather than on a
/// cell boundary (see `docs/learning.md` §5).
pub fn packing_config() -> LearnConfig {
    let mut config = LearnConfig { seed: 7, ..LearnConfig::default() };
    config.pairs.insert(
        TypePair::new("gripper", "can"),
        PairSettings {
            position_bins: [15; 3],
            half_range: [0.3; 3],
            threshold: 0.4,
            rotation_bins: 25,
            max_components: 4,
            ..PairSettings::default()
        }
        .into(),
    );
    config.pairs.insert(
        TypePair::new("surface", "can"),
        PairSettings {
            position_bins: [5; 3],
            half_range: [0.1; 3],
            threshold: 0.4,
            rotation_bins: 25,
            max_components: 4,
            ..PairSettings::default()
        }
        .into(),
    );
    config.ignored.insert(TypePair::new("gripper", "surface"));
    config
}

/// The synthetic task's shapes, as upright discs: two bodies fit at once iff two of the poses are at least two
/// footprint radii apart horizontally; the gripper's shape is unknown.
#[derive(Debug, Clone)]
pub struct DiscShapes {
    /// Footprint radius (m) per type name.
    pub radii: Vec<(String, f64)>,
}

impl ShapeOracle for DiscShapes {
    fn two_fit(&self, type_name: &str, poses: &[Pose]) -> Option<bool> {
        let radius = self.radii.iter().find(|(name, _)| name == type_name)?.1;
        let apart = |a: &Pose, b: &Pose| {
            (a.translation.vector - b.translation.vector).xy().norm() >= 2.0 * radius
        };
        Some(poses.iter().enumerate().any(|(i, a)| poses[i + 1..].iter().any(|b| apart(a, b))))
    }

    /// Discs of unbounded height: the horizontal distance between their rims.
    fn gap(&self, primary: &str, secondary: &str, relative: &Pose) -> Option<f64> {
        let radius =
            |name: &str| Some(self.radii.iter().find(|(type_name, _)| type_name == name)?.1);
        let rims = radius(primary)? + radius(secondary)?;
        Some((relative.translation.vector.xy().norm() - rims).max(0.0))
    }
}

/// The synthetic task's shapes: cans 5 cm across, so that two fit in the box's 4 cm voxel corner to corner
/// (5.7 cm apart), and a box 30 cm across, of which a can is in one at a time.
pub fn packing_shapes() -> DiscShapes {
    DiscShapes { radii: vec![("can".into(), 0.025), ("surface".into(), 0.15)] }
}

/// A place-on-target task with answers known in advance, for the selection's tests: a free-flying gripper takes
/// a block from a random spot on a ring around a fixed target, carries it through one waypoint high above the
/// target (in every demonstration), lowers it onto one of `spots` (offsets in the target's frame, taken in
/// turn) and lets go. Every recorded pose is disturbed by up to `noise` (m) and `noise / 2` (rad), as a
/// motion-capture system would; half of the demonstrations stop at a random step.
#[derive(Debug, Clone)]
pub struct PlaceTask {
    /// Resting offsets of the block in the target's frame.
    pub spots: Vec<[f64; 3]>,
    /// Tracking noise: the most a recorded position is off (m); rotations are off by half as many radians.
    pub noise: f64,
    /// The most the block's yaw on the target is off zero (rad): [`PLACED_YAW`], or π for a block set down at
    /// any yaw.
    pub placed_yaw: f64,
    /// How the gripper takes the block: `None`, square, its frame as the block's; `Some(y)`, as a magnet
    /// pointing down (its frame turned half a turn about x), at a yaw about the block's axis within ±y (rad).
    pub grasp_yaw: Option<f64>,
}

/// The yaw spread of a block set down square on the target (rad).
pub const PLACED_YAW: f64 = 0.02;

/// The block's offset below the gripper's frame while held.
pub const PLACE_GRASP_DEPTH: f64 = 0.1;
/// The waypoint every carry passes, in the target's frame.
pub const PLACE_WAYPOINT: [f64; 3] = [0.0, 0.0, 0.3];

/// The participants of a [`PlaceTask`]: a gripper, a block and a target, in that order.
pub fn place_participants() -> Vec<Participant> {
    gripper_object_and_fixed(("block1", "block"), ("target1", "target"))
}

/// `count` demonstrations of a [`PlaceTask`] from one seed.
pub fn place_demonstrations(task: &PlaceTask, count: usize, seed: u64) -> Vec<Demonstration> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count).map(|index| place_demonstration(task, index, &mut rng)).collect()
}

fn place_demonstration(task: &PlaceTask, index: usize, rng: &mut ChaCha8Rng) -> Demonstration {
    let participants = place_participants();
    let target = Pose::identity();
    let angle = rng.random_range(-PI..PI);
    let radius = rng.random_range(0.4..0.6);
    let start = Pose::from_parts(
        Translation3::new(radius * angle.cos(), radius * angle.sin(), 0.0),
        yaw(rng.random_range(-PI..PI)),
    );
    // Pairs of demonstrations (one whole, one cut) share a spot, so every spot is reached as often.
    let spot = task.spots[(index / 2) % task.spots.len()];
    let placed = Pose::from_parts(
        Translation3::new(
            spot[0] + rng.random_range(-0.001..0.001),
            spot[1] + rng.random_range(-0.001..0.001),
            spot[2],
        ),
        yaw(rng.random_range(-task.placed_yaw..task.placed_yaw)),
    );
    let grasp = match task.grasp_yaw {
        None => Pose::translation(0.0, 0.0, PLACE_GRASP_DEPTH),
        Some(spread) => Pose::from_parts(
            Translation3::new(0.0, 0.0, PLACE_GRASP_DEPTH),
            yaw(rng.random_range(-spread..=spread))
                * UnitQuaternion::from_euler_angles(PI, 0.0, 0.0),
        ),
    };
    let home = Pose::translation(rng.random_range(-0.2..0.2), rng.random_range(-0.2..0.2), 0.6);
    let waypoint = Pose::translation(PLACE_WAYPOINT[0], PLACE_WAYPOINT[1], PLACE_WAYPOINT[2]);
    // (gripper, block, held) per step, before noise.
    let mut script: Vec<(Pose, Pose, bool)> = Vec::new();
    let rest = |script: &mut Vec<(Pose, Pose, bool)>, frames: usize| {
        let last = *script.last().expect("a first step");
        script.extend(std::iter::repeat_n(last, frames));
    };
    script.push((home, start, false));
    rest(&mut script, 3);
    let above_start = Pose::translation(0.0, 0.0, 0.2) * start * grasp;
    for gripper in interpolate(&home, &above_start, 6) {
        script.push((gripper, start, false));
    }
    for gripper in interpolate(&above_start, &(start * grasp), 5) {
        script.push((gripper, start, false));
    }
    rest(&mut script, 2);
    script.push((start * grasp, start, true));
    let lifted = Pose::translation(0.0, 0.0, 0.2) * start;
    let mut carried = interpolate(&start, &lifted, 4);
    carried.extend(interpolate(&lifted, &waypoint, 8));
    carried.extend(interpolate(&waypoint, &placed, 12));
    for block in carried {
        script.push((block * grasp, block, true));
    }
    script.push((placed * grasp, placed, false));
    rest(&mut script, 3);
    for gripper in interpolate(&(placed * grasp), &home, 6) {
        script.push((gripper, placed, false));
    }
    rest(&mut script, 3);
    if index % 2 == 1 {
        let keep = rng.random_range(2..script.len());
        script.truncate(keep);
    }
    let mut disturb = |pose: Pose| {
        if task.noise == 0.0 {
            return pose;
        }
        let shift = Vector3::from_fn(|_, _| rng.random_range(-task.noise..task.noise));
        let turn = Vector3::from_fn(|_, _| rng.random_range(-task.noise..task.noise) / 2.0);
        Pose::from_parts(
            Translation3::from(pose.translation.vector + shift),
            UnitQuaternion::from_scaled_axis(turn) * pose.rotation,
        )
    };
    let steps = script
        .into_iter()
        .map(|(gripper, block, held)| Snapshot {
            poses: vec![disturb(gripper), disturb(block), disturb(target)],
            held: if held { vec![(0, 1)] } else { vec![] },
        })
        .collect();
    Demonstration { id: format!("place-{index:03}"), participants, steps }
}
