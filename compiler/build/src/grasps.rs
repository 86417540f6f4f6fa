//! The recorded grasps against each robot's `grab distance`: a grab succeeds only within it, so a
//! range that no recorded grasp falls in builds a model whose grasps no solve can take.

use lamp_learn::Demonstration;
use lamp_participants::part_participant_name;
use lamp_spec::Spec;
use miette::Diagnostic;
use thiserror::Error;

/// Recorded grasps that the robot's `grab distance` would not allow, located by robot so that
/// `lampc` can point at the clause.
#[derive(Debug, Clone, PartialEq, Error, Diagnostic)]
#[error(
    "robot `{robot}`: {outside} of {grasps} recorded grasps are outside its `grab distance` {low:.3} m .. {high:.3} m; the recorded ones are {recorded_low:.3} m .. {recorded_high:.3} m from the gripper"
)]
#[diagnostic(
    code(lamp::build::grab_distance),
    severity(Warning),
    help(
        "A grab succeeds only within the `grab distance` (the gripper link's origin to the object's origin), so a solve cannot take the grasps this model learned; write a range that holds the recorded ones, such as `grab distance {suggested_low:.3} m .. {suggested_high:.3} m`."
    )
)]
pub struct GrabDistanceWarning {
    pub robot: String,
    /// The grasps recorded (a gripper starting to hold an object), over every demonstration.
    pub grasps: usize,
    /// How many of them lie outside the spec's range.
    pub outside: usize,
    /// The spec's range (m).
    pub low: f64,
    pub high: f64,
    /// The nearest and farthest recorded grasp (m).
    pub recorded_low: f64,
    pub recorded_high: f64,
    /// A range holding every recorded grasp with a margin (m).
    pub suggested_low: f64,
    pub suggested_high: f64,
}

/// How much wider than the recorded grasps the suggested range is, each way (m): what a robot's
/// grasp of an object varies by.
const SUGGESTED_MARGIN: f64 = 0.01;

/// A warning per robot with a `grab distance` that some recorded grasp lies outside, in spec
/// order. A grasp is a step at which the robot's gripper starts to hold an object; its distance
/// is the gripper link's origin to the object's origin.
pub fn grasps_outside_grab_distance(
    spec: &Spec,
    demonstrations: &[Demonstration],
) -> Vec<GrabDistanceWarning> {
    outside_grab_distance(&spec.robots, demonstrations)
}

fn outside_grab_distance(
    robots: &[lamp_spec::Robot],
    demonstrations: &[Demonstration],
) -> Vec<GrabDistanceWarning> {
    let mut warnings = Vec::new();
    for robot in robots {
        let (Some((low, high)), Some(gripper)) = (robot.grab_distance, robot.gripper_part()) else {
            continue;
        };
        let name = part_participant_name(&robot.name, &gripper.type_name);
        let distances: Vec<f64> =
            demonstrations.iter().flat_map(|demonstration| grasps(demonstration, &name)).collect();
        let outside = distances.iter().filter(|&&d| d < low || d > high).count();
        if outside == 0 {
            continue;
        }
        let recorded_low = distances.iter().copied().fold(f64::INFINITY, f64::min);
        let recorded_high = distances.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        warnings.push(GrabDistanceWarning {
            robot: robot.name.clone(),
            grasps: distances.len(),
            outside,
            low,
            high,
            recorded_low,
            recorded_high,
            suggested_low: (recorded_low - SUGGESTED_MARGIN).max(0.0),
            suggested_high: recorded_high + SUGGESTED_MARGIN,
        });
    }
    warnings
}

/// The distance of every grasp by participant `gripper` in one demonstration.
fn grasps(demonstration: &Demonstration, gripper: &str) -> Vec<f64> {
    let Some(index) = demonstration.participants.iter().position(|p| p.name == gripper) else {
        return Vec::new();
    };
    let held = |step: usize| {
        demonstration.steps[step]
            .held
            .iter()
            .filter(|(holder, _)| *holder == index)
            .map(|(_, object)| *object)
            .collect::<Vec<_>>()
    };
    let mut distances = Vec::new();
    for step in 1..demonstration.steps.len() {
        let before = held(step - 1);
        for object in held(step) {
            if !before.contains(&object) {
                let poses = &demonstration.steps[step].poses;
                let gap = poses[object].translation.vector - poses[index].translation.vector;
                distances.push(gap.norm());
            }
        }
    }
    distances
}

#[cfg(test)]
mod tests {
    use super::*;
    use lamp_abstraction::{Participant, Pose, Role, Snapshot};

    /// A gripper that closes on a can `distance` below it at step 1 and carries it.
    fn demonstration(distance: f64) -> Demonstration {
        let participants = vec![
            Participant {
                name: "arm_gripper".into(),
                type_name: "gripper".into(),
                role: Role::RobotPart { gripper: true },
            },
            Participant {
                name: "can1".into(),
                type_name: "can".into(),
                role: Role::Object { movable: true },
            },
        ];
        let step = |held: bool, z: f64| Snapshot {
            poses: vec![Pose::translation(0.0, 0.0, z + distance), Pose::translation(0.0, 0.0, z)],
            held: if held { vec![(0, 1)] } else { Vec::new() },
        };
        Demonstration {
            id: "one".into(),
            participants,
            steps: vec![step(false, 0.0), step(true, 0.0), step(true, 0.1)],
        }
    }

    fn arm(grab: (f64, f64)) -> Vec<lamp_spec::Robot> {
        vec![lamp_spec::Robot {
            name: "arm".into(),
            urdf: "arm.urdf".into(),
            kind: lamp_spec::RobotKind::FreeFlying,
            mount: Pose::identity(),
            parts: vec![lamp_spec::RobotPart { type_name: "gripper".into(), link: "hand".into() }],
            grab_distance: Some(grab),
            groups: Vec::new(),
            configurations: Vec::new(),
            ignored_collisions: Vec::new(),
        }]
    }

    #[test]
    fn grasps_outside_the_grab_distance_are_named_with_the_recorded_range() {
        let demos = [demonstration(0.077), demonstration(0.078)];
        let warnings = outside_grab_distance(&arm((0.21, 0.23)), &demos);
        assert_eq!(warnings.len(), 1);
        let warning = &warnings[0];
        assert_eq!((warning.grasps, warning.outside), (2, 2));
        assert!((warning.recorded_low - 0.077).abs() < 1e-9, "{warning:?}");
        assert!((warning.recorded_high - 0.078).abs() < 1e-9, "{warning:?}");
        assert!(warning.suggested_low <= 0.077 && warning.suggested_high >= 0.078);
        // The carry after the grasp is not another grasp, and a range that holds them is quiet.
        assert!(outside_grab_distance(&arm((0.07, 0.09)), &demos).is_empty());
    }
}
