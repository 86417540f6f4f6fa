//! Objects move only when held, and rigidly with what holds them.
//!
//! A recording says where each object is at every step, with the noise of whatever tracked it: a motion-capture
//! system or a perception pipeline adds a millimetre or two and a degree to every pose. Left in, that noise moves
//! an object resting near a region's edge in and out of the region with no robot anywhere near it, and the
//! learner induces actions that change a relation by themselves, which no refinement can produce.
//!
//! So before learning, each object's track is cut into runs by what holds it, and each run is given the one pose
//! the physics allows: resting (held by nothing), one pose in the world; held, one pose in the frame of the
//! gripper that holds it, carried along with the gripper's recorded pose. A static object is never held, so its
//! whole track is one run: a tracker jitters a box as much as the can in it, and the relation between the two is
//! as noisy as the noisier of them. The pose of a run is the
//! component-wise median of its recorded positions (and of its rotations as quaternions in one hemisphere,
//! normalised): a few frames of an object still settling after it was let go of, or of a tracking glitch, do not
//! move it. A noise-free recording, whose resting objects stand still and whose held objects are carried
//! rigidly, comes out as it went in, to rounding.

use nalgebra::{Quaternion, Translation3, UnitQuaternion, Vector3};

use crate::demo::{Demonstration, Pose, Role};

/// The demonstration with every object's pose constant over each run of steps in which one thing (or nothing)
/// holds it; robot parts, whose poses come from joint encoders, are left as recorded.
pub(crate) fn steady(demonstration: &Demonstration) -> Demonstration {
    let mut steadied = demonstration.clone();
    let steps = &demonstration.steps;
    for (object, participant) in demonstration.participants.iter().enumerate() {
        if !matches!(participant.role, Role::Object { .. }) {
            continue;
        }
        let holder = |step: usize| {
            steps[step].held.iter().find(|(_, held)| *held == object).map(|(gripper, _)| *gripper)
        };
        let mut start = 0;
        while start < steps.len() {
            let by = holder(start);
            let end = (start..steps.len()).find(|&step| holder(step) != by).unwrap_or(steps.len());
            // The object's pose in the frame it rests in: the world's, or its gripper's.
            let frame =
                |step: usize| by.map_or(Pose::identity(), |gripper| steps[step].poses[gripper]);
            let relative: Vec<Pose> = (start..end)
                .map(|step| frame(step).inverse() * steps[step].poses[object])
                .collect();
            let typical = median_pose(&relative);
            for step in start..end {
                steadied.steps[step].poses[object] = frame(step) * typical;
            }
            start = end;
        }
    }
    steadied
}

/// The component-wise median of the positions, and of the rotations as quaternions turned into the first one's
/// hemisphere, normalised. For an even count, the mean of the two middle values.
fn median_pose(poses: &[Pose]) -> Pose {
    // A run whose poses are all equal keeps that pose exactly.
    if poses.iter().all(|pose| *pose == poses[0]) {
        return poses[0];
    }
    let first = poses[0].rotation.coords;
    let mut positions: [Vec<f64>; 3] = Default::default();
    let mut rotations: [Vec<f64>; 4] = Default::default();
    for pose in poses {
        for (axis, values) in positions.iter_mut().enumerate() {
            values.push(pose.translation.vector[axis]);
        }
        let coords = pose.rotation.coords;
        let sign = if coords.dot(&first) < 0.0 { -1.0 } else { 1.0 };
        for (component, values) in rotations.iter_mut().enumerate() {
            values.push(sign * coords[component]);
        }
    }
    let [x, y, z] = positions.map(median);
    let [i, j, k, w] = rotations.map(median);
    let rotation = UnitQuaternion::new_normalize(Quaternion::new(w, i, j, k));
    Pose::from_parts(Translation3::from(Vector3::new(x, y, z)), rotation)
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let middle = values.len() / 2;
    if values.len() % 2 == 1 { values[middle] } else { 0.5 * (values[middle - 1] + values[middle]) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::{Participant, Snapshot};

    fn participant(name: &str, role: Role) -> Participant {
        Participant { name: name.into(), type_name: name.into(), role }
    }

    fn at(x: f64, y: f64, z: f64, yaw: f64) -> Pose {
        Pose::from_parts(
            Translation3::new(x, y, z),
            UnitQuaternion::from_euler_angles(0.0, 0.0, yaw),
        )
    }

    /// A gripper that comes down to a can, carries it 30 cm along x and leaves it; the can's and the table's
    /// recorded poses jitter by `noise` (m and rad), one way at odd steps and the other at even ones.
    fn carry(noise: f64) -> Demonstration {
        let jitter = |step: usize| if step % 2 == 1 { noise } else { -noise };
        let grasp = at(0.0, 0.0, -0.1, 0.0);
        let mut steps = Vec::new();
        for step in 0..30 {
            let x = if step < 10 {
                0.0
            } else if step < 20 {
                0.03 * (step - 10) as f64
            } else {
                0.3
            };
            let gripper = at(x, 0.0, 0.2, 0.0);
            let held = (10..20).contains(&step);
            let can = if held { gripper * grasp } else { at(x, 0.0, 0.1, 0.0) };
            let noisy = at(jitter(step), -jitter(step), 0.0, jitter(step)) * can;
            let table = at(-jitter(step), jitter(step), 0.0, -jitter(step));
            steps.push(Snapshot {
                poses: vec![gripper, noisy, table],
                held: if held { vec![(0, 1)] } else { Vec::new() },
            });
        }
        Demonstration {
            id: "carry".into(),
            participants: vec![
                participant("gripper", Role::RobotPart { gripper: true }),
                participant("can", Role::Object { movable: true }),
                participant("table", Role::Object { movable: false }),
            ],
            steps,
        }
    }

    #[test]
    fn a_noise_free_recording_is_unchanged() {
        let demonstration = carry(0.0);
        let steadied = steady(&demonstration);
        for (before, after) in demonstration.steps.iter().zip(&steadied.steps) {
            for (a, b) in before.poses.iter().zip(&after.poses) {
                assert!((a.translation.vector - b.translation.vector).norm() < 1e-12);
                assert!(a.rotation.angle_to(&b.rotation) < 1e-12);
            }
        }
    }

    #[test]
    fn a_resting_object_keeps_one_pose_and_a_held_one_its_grasp() {
        let steadied = steady(&carry(0.002));
        let can = |step: usize| steadied.steps[step].poses[1];
        let gripper = |step: usize| steadied.steps[step].poses[0];
        // Resting before the grasp: one pose, within the noise of the true one.
        for step in 1..10 {
            assert_eq!(can(step), can(0));
        }
        assert!((can(0).translation.vector - Vector3::new(0.0, 0.0, 0.1)).norm() < 0.003);
        // Held: one pose in the gripper's frame, as the gripper moves.
        let grasp = gripper(10).inverse() * can(10);
        for step in 11..20 {
            let relative = gripper(step).inverse() * can(step);
            assert!((relative.translation.vector - grasp.translation.vector).norm() < 1e-12);
            assert!(relative.rotation.angle_to(&grasp.rotation) < 1e-12);
        }
        // Let go of: one pose again, where it was put.
        for step in 21..30 {
            assert_eq!(can(step), can(20));
        }
        assert!((can(20).translation.vector - Vector3::new(0.3, 0.0, 0.1)).norm() < 0.003);
        // Robot parts are left as recorded; a static object keeps one pose throughout.
        assert_eq!(steadied.steps[5].poses[0], carry(0.002).steps[5].poses[0]);
        assert_ne!(carry(0.002).steps[5].poses[2], carry(0.002).steps[6].poses[2]);
        for step in 1..30 {
            assert_eq!(steadied.steps[step].poses[2], steadied.steps[0].poses[2]);
        }
        let table = steadied.steps[0].poses[2];
        assert!(table.translation.vector.norm() < 0.003 && table.rotation.angle() < 0.003);
    }

    #[test]
    fn a_few_frames_of_settling_do_not_move_the_resting_pose() {
        let mut demonstration = carry(0.0);
        // The can is still falling for two frames after it is let go of.
        for (step, drop) in [(20, 0.004), (21, 0.001)] {
            demonstration.steps[step].poses[1] = at(0.3, 0.0, 0.1 + drop, 0.0);
        }
        let steadied = steady(&demonstration);
        let rest = steadied.steps[20].poses[1].translation.vector;
        assert!((rest - Vector3::new(0.3, 0.0, 0.1)).norm() < 1e-12, "{rest:?}");
    }
}
