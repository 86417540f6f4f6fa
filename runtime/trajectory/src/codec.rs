//! Encoding a [`Step`] as a CDR `lamp_msgs/msg/WorldStep` message and decoding it back, and the
//! checks a step must pass against its file's header (shared by the writer and the reader).

use std::collections::BTreeMap;

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

use crate::cdr::{CdrReader, CdrWriter};
use crate::model::{RobotState, Step, TrajectoryHeader};

/// How far a stored quaternion's norm may be from 1.
/// Quaternions converted from single precision are within about 1e-7 of unit norm; anything
/// further off is not a rotation someone meant, and the reader returns the stored numbers
/// unchanged (so files round-trip bit for bit), so it must not accept a visible scaling.
pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-6;

const NANOSECONDS_PER_SECOND: u64 = 1_000_000_000;

/// The latest time a `builtin_interfaces/Time` (signed 32-bit seconds) can hold.
pub const MAXIMUM_TIME_NANOSECONDS: u64 =
    (i32::MAX as u64) * NANOSECONDS_PER_SECOND + (NANOSECONDS_PER_SECOND - 1);

/// Bytes of one `geometry_msgs/Pose` (seven `float64`); a lower bound used to bound sequences.
const POSE_BYTES: usize = 7 * 8;

/// What is wrong with one step, before the caller adds the file name and step index.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum StepProblem {
    /// The message bytes do not decode.
    Corrupt(String),
    /// The step disagrees with the header or with the previous step.
    Inconsistent(String),
    /// A number is not finite, a quaternion is not unit, or a time is out of range.
    InvalidValue(String),
}

/// Checks a step against the header and the previous step's time.
pub fn check_step(
    header: &TrajectoryHeader,
    step: &Step,
    previous_time: Option<u64>,
) -> Result<(), StepProblem> {
    if step.body_poses.len() != header.bodies.len() {
        return Err(StepProblem::Inconsistent(format!(
            "the step has {} body poses but the header lists {} bodies",
            step.body_poses.len(),
            header.bodies.len()
        )));
    }
    if step.robots.len() != header.robots.len() {
        return Err(StepProblem::Inconsistent(format!(
            "the step has {} robot states but the header lists {} robots",
            step.robots.len(),
            header.robots.len()
        )));
    }
    if let Some(previous) = previous_time.filter(|previous| step.time_nanoseconds < *previous) {
        return Err(StepProblem::Inconsistent(format!(
            "time goes backwards, from {previous} ns to {} ns",
            step.time_nanoseconds
        )));
    }
    if step.time_nanoseconds > MAXIMUM_TIME_NANOSECONDS {
        return Err(StepProblem::InvalidValue(format!(
            "time {} ns is beyond what builtin_interfaces/Time holds",
            step.time_nanoseconds
        )));
    }
    for (pose, body) in step.body_poses.iter().zip(&header.bodies) {
        check_pose(pose).map_err(|reason| {
            StepProblem::InvalidValue(format!("pose of body `{}`: {reason}", body.name))
        })?;
    }
    for (state, robot) in step.robots.iter().zip(&header.robots) {
        if state.positions.len() != robot.coordinates.len() {
            return Err(StepProblem::Inconsistent(format!(
                "robot `{}` has {} positions but the header lists {} coordinates",
                robot.name,
                state.positions.len(),
                robot.coordinates.len()
            )));
        }
        if state.held.len() != robot.grippers.len() {
            return Err(StepProblem::Inconsistent(format!(
                "robot `{}` has {} held entries but the header lists {} grippers",
                robot.name,
                state.held.len(),
                robot.grippers.len()
            )));
        }
        if let Some((value, coordinate)) =
            state.positions.iter().zip(&robot.coordinates).find(|(value, _)| !value.is_finite())
        {
            return Err(StepProblem::InvalidValue(format!(
                "coordinate `{coordinate}` of robot `{}` is {value}",
                robot.name
            )));
        }
        for (held, gripper) in state.held.iter().zip(&robot.grippers) {
            if let Some(index) = held.filter(|index| *index >= header.bodies.len()) {
                return Err(StepProblem::Inconsistent(format!(
                    "gripper `{gripper}` of robot `{}` holds body index {index}, but the header lists {} bodies",
                    robot.name,
                    header.bodies.len()
                )));
            }
        }
    }
    Ok(())
}

pub(crate) fn check_pose(pose: &Isometry3<f64>) -> Result<(), String> {
    let translation = &pose.translation.vector;
    if !translation.iter().all(|value| value.is_finite()) {
        return Err(format!("position {translation:?} is not finite"));
    }
    let coords = &pose.rotation.as_ref().coords;
    if !coords.iter().all(|value| value.is_finite()) {
        return Err(format!("quaternion {:?} is not finite", coords.as_slice()));
    }
    let norm = coords.norm();
    if (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
        return Err(format!("quaternion has norm {norm}, not 1"));
    }
    Ok(())
}

/// Encodes a step that passed [`check_step`] into `buffer`, which is cleared first and returned
/// with the message.
pub fn encode_step_into(buffer: Vec<u8>, header: &TrajectoryHeader, step: &Step) -> Vec<u8> {
    let mut writer = CdrWriter::reusing(buffer);
    let (seconds, nanoseconds) = split_time(step.time_nanoseconds);
    writer.write_i32(seconds);
    writer.write_u32(nanoseconds);
    writer.write_length(sequence_length(step.body_poses.len()));
    for pose in &step.body_poses {
        let translation = &pose.translation.vector;
        let rotation = &pose.rotation.as_ref().coords; // nalgebra stores [x, y, z, w]
        writer.write_f64s(translation.iter().chain(rotation.iter()).copied());
    }
    writer.write_length(sequence_length(step.robots.len()));
    for state in &step.robots {
        writer.write_length(sequence_length(state.positions.len()));
        writer.write_f64s(state.positions.iter().copied());
        writer.write_length(sequence_length(state.held.len()));
        for held in &state.held {
            let name = held.map_or("", |index| header.bodies[index].name.as_str());
            writer.write_string(name);
        }
    }
    writer.into_bytes()
}

/// A time that passed [`check_step`] as `builtin_interfaces/Time` seconds and nanoseconds.
pub(crate) fn split_time(time_nanoseconds: u64) -> (i32, u32) {
    let seconds = time_nanoseconds / NANOSECONDS_PER_SECOND;
    let seconds = i32::try_from(seconds).expect("check_step bounds the time to i32 seconds");
    let nanoseconds = u32::try_from(time_nanoseconds % NANOSECONDS_PER_SECOND)
        .expect("a remainder of 1e9 fits in u32");
    (seconds, nanoseconds)
}

fn sequence_length(length: usize) -> u32 {
    // A step is built in memory from a header; four billion bodies would not fit there.
    u32::try_from(length).expect("sequence lengths of an in-memory step fit in u32")
}

/// Body name → index in the header, built once per file for decoding held bodies.
pub struct BodyLookup {
    indices: BTreeMap<String, usize>,
}

impl BodyLookup {
    pub fn new(header: &TrajectoryHeader) -> Self {
        let indices = header
            .bodies
            .iter()
            .enumerate()
            .map(|(index, body)| (body.name.clone(), index))
            .collect();
        Self { indices }
    }
}

/// Decodes a message into a step and checks it against the header.
pub fn decode_step(
    header: &TrajectoryHeader,
    lookup: &BodyLookup,
    bytes: &[u8],
    previous_time: Option<u64>,
) -> Result<Step, StepProblem> {
    let corrupt = |error: crate::cdr::CdrError| StepProblem::Corrupt(error.to_string());
    let mut reader = CdrReader::new(bytes).map_err(corrupt)?;
    let seconds = reader.read_i32().map_err(corrupt)?;
    let nanoseconds = reader.read_u32().map_err(corrupt)?;
    let (Ok(seconds), true) =
        (u64::try_from(seconds), u64::from(nanoseconds) < NANOSECONDS_PER_SECOND)
    else {
        return Err(StepProblem::InvalidValue(format!(
            "stamp {seconds} s {nanoseconds} ns is negative or has nanoseconds of 1e9 or more"
        )));
    };
    let time_nanoseconds = seconds * NANOSECONDS_PER_SECOND + u64::from(nanoseconds);

    let body_count = reader.read_length(POSE_BYTES).map_err(corrupt)?;
    if body_count != header.bodies.len() {
        return Err(StepProblem::Inconsistent(format!(
            "the step has {body_count} body poses but the header lists {} bodies",
            header.bodies.len()
        )));
    }
    let mut body_poses = Vec::with_capacity(body_count);
    for _ in 0..body_count {
        let mut values = [0.0; 7];
        for value in &mut values {
            *value = reader.read_f64().map_err(corrupt)?;
        }
        let [x, y, z, qx, qy, qz, qw] = values;
        // Stored numbers are returned unchanged (check_step bounds the norm), so a file
        // round-trips bit for bit.
        let rotation = UnitQuaternion::new_unchecked(Quaternion::new(qw, qx, qy, qz));
        body_poses.push(Isometry3::from_parts(Translation3::new(x, y, z), rotation));
    }

    let robot_count = reader.read_length(8).map_err(corrupt)?;
    if robot_count != header.robots.len() {
        return Err(StepProblem::Inconsistent(format!(
            "the step has {robot_count} robot states but the header lists {} robots",
            header.robots.len()
        )));
    }
    let mut robots = Vec::with_capacity(robot_count);
    for robot in &header.robots {
        let position_count = reader.read_length(8).map_err(corrupt)?;
        let mut positions = Vec::with_capacity(position_count);
        for _ in 0..position_count {
            positions.push(reader.read_f64().map_err(corrupt)?);
        }
        let held_count = reader.read_length(4).map_err(corrupt)?;
        let mut held = Vec::with_capacity(held_count);
        for gripper in 0..held_count {
            let name = reader.read_string().map_err(corrupt)?;
            if name.is_empty() {
                held.push(None);
                continue;
            }
            let Some(index) = lookup.indices.get(name) else {
                let gripper = robot.grippers.get(gripper).map_or("?", String::as_str);
                return Err(StepProblem::Inconsistent(format!(
                    "gripper `{gripper}` of robot `{}` holds `{name}`, which the header does not list",
                    robot.name
                )));
            };
            held.push(Some(*index));
        }
        robots.push(RobotState { positions, held });
    }
    reader.finish().map_err(corrupt)?;

    let step = Step { time_nanoseconds, body_poses, robots };
    check_step(header, &step, previous_time)?;
    Ok(step)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{BodyDescription, RobotDescription};

    fn header() -> TrajectoryHeader {
        TrajectoryHeader {
            domain: "test".into(),
            seed: 0,
            provenance: BTreeMap::new(),
            bodies: vec![BodyDescription { name: "can".into(), type_name: "can".into() }],
            robots: vec![RobotDescription {
                name: "arm".into(),
                coordinates: vec!["q".into()],
                grippers: vec!["hand".into()],
            }],
        }
    }

    fn step() -> Step {
        Step {
            time_nanoseconds: 1_500_000_000,
            body_poses: vec![Isometry3::translation(1.0, 2.0, 3.0)],
            robots: vec![RobotState { positions: vec![0.25], held: vec![Some(0)] }],
        }
    }

    /// Known answer, laid out by hand from the XCDR1 rules in `docs/formats.md`.
    #[test]
    fn world_step_layout_is_known() {
        let f64_bytes = |value: f64| value.to_le_bytes().to_vec();
        let expected: Vec<u8> = [
            vec![0x00, 0x01, 0x00, 0x00],       // encapsulation: CDR little endian
            vec![1, 0, 0, 0],                   // 0: stamp.sec = 1
            vec![0x00, 0x65, 0xcd, 0x1d],       // 4: stamp.nanosec = 500 000 000
            vec![1, 0, 0, 0],                   // 8: one body pose
            vec![0, 0, 0, 0],                   // 12: padding to 8 for float64
            f64_bytes(1.0),                     // 16: position.x
            f64_bytes(2.0),                     // 24: position.y
            f64_bytes(3.0),                     // 32: position.z
            f64_bytes(0.0),                     // 40: orientation.x
            f64_bytes(0.0),                     // 48: orientation.y
            f64_bytes(0.0),                     // 56: orientation.z
            f64_bytes(1.0),                     // 64: orientation.w
            vec![1, 0, 0, 0],                   // 72: one robot
            vec![1, 0, 0, 0],                   // 76: one position, already 8-aligned after
            vec![0, 0, 0, 0, 0, 0, 0xd0, 0x3f], // 80: 0.25
            vec![1, 0, 0, 0],                   // 88: one held entry
            vec![4, 0, 0, 0, b'c', b'a', b'n', 0], // 92: "can" with its NUL
        ]
        .concat();
        let header = header();
        let bytes = encode_step_into(Vec::new(), &header, &step());
        assert_eq!(bytes, expected);
        let decoded = decode_step(&header, &BodyLookup::new(&header), &bytes, None).unwrap();
        assert_eq!(decoded, step());
    }

    #[test]
    fn damaged_messages_are_errors_never_panics() {
        let header = header();
        let lookup = BodyLookup::new(&header);
        let bytes = encode_step_into(Vec::new(), &header, &step());
        for length in 0..bytes.len() {
            assert!(decode_step(&header, &lookup, &bytes[..length], None).is_err(), "{length}");
        }
        for index in 0..bytes.len() {
            for bit in 0..8 {
                let mut damaged = bytes.clone();
                damaged[index] ^= 1 << bit;
                // Any outcome but a panic is acceptable; a changed float may still decode.
                let _ = decode_step(&header, &lookup, &damaged, None);
            }
        }
    }

    #[test]
    fn count_mismatches_are_inconsistent() {
        let header = header();
        let mut two_bodies = header.clone();
        two_bodies.bodies.push(BodyDescription { name: "box".into(), type_name: "box".into() });
        let bytes = encode_step_into(Vec::new(), &header, &step());
        let problem = decode_step(&two_bodies, &BodyLookup::new(&two_bodies), &bytes, None);
        assert!(
            matches!(&problem, Err(StepProblem::Inconsistent(reason)) if reason.contains("1 body poses but the header lists 2")),
            "{problem:?}"
        );
        let mut renamed = header.clone();
        renamed.bodies[0].name = "cup".into();
        let problem = decode_step(&renamed, &BodyLookup::new(&renamed), &bytes, None);
        assert!(matches!(problem, Err(StepProblem::Inconsistent(_))), "{problem:?}");
        let problem = decode_step(&header, &BodyLookup::new(&header), &bytes, Some(2_000_000_000));
        assert!(matches!(problem, Err(StepProblem::Inconsistent(_))), "{problem:?}");
    }

    #[test]
    fn invalid_values_are_rejected() {
        let header = header();
        let mut bad = step();
        bad.robots[0].positions[0] = f64::NAN;
        assert!(matches!(check_step(&header, &bad, None), Err(StepProblem::InvalidValue(_))));
        let mut bad = step();
        bad.body_poses[0].rotation =
            UnitQuaternion::new_unchecked(Quaternion::new(1.1, 0.0, 0.0, 0.0));
        assert!(matches!(check_step(&header, &bad, None), Err(StepProblem::InvalidValue(_))));
        let mut bad = step();
        bad.time_nanoseconds = MAXIMUM_TIME_NANOSECONDS + 1;
        assert!(matches!(check_step(&header, &bad, None), Err(StepProblem::InvalidValue(_))));
        let mut bad = step();
        bad.robots[0].held[0] = Some(1);
        assert!(matches!(check_step(&header, &bad, None), Err(StepProblem::Inconsistent(_))));
        let mut latest = step();
        latest.time_nanoseconds = MAXIMUM_TIME_NANOSECONDS;
        let bytes = encode_step_into(Vec::new(), &header, &latest);
        assert_eq!(decode_step(&header, &BodyLookup::new(&header), &bytes, None).unwrap(), latest);
    }
}
