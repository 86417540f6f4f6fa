//! Cross-checks with the reference MCAP implementation in Python (`mcap` and
//! `mcap-ros2-support`): it reads our files and decodes every step to the same numbers, and the
//! conversion example in `docs/formats.md` writes files we read, and its reading example reads
//! the joint trajectories and gripper commands we write.
//! Skips when the packages are missing unless `LAMP_REQUIRE_ORACLES=1`.

// The oracle helper reports why it skipped, as the test harness shows.
#![allow(clippy::print_stdout)]

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use lamp_trajectory::{
    BASE_TRAJECTORY_TOPIC, GRIPPER_COMMAND_TOPIC, GripperCommand, JOINT_TRAJECTORY_TOPIC,
    JointTrajectoryMessage, StandardChannels, StandardStep, Trajectory, TrajectoryHeader,
    TrajectoryPoint, TrajectoryTopic,
};

/// Python's `math.sin` and Rust's `f64::sin` may differ in the last bit on some platforms.
const TRIGONOMETRY_TOLERANCE: f64 = 1e-15;

fn python_packages_available() -> bool {
    let available = Command::new("python3")
        .args(["-c", "import mcap, mcap_ros2.decoder, mcap_ros2.writer"])
        .output()
        .is_ok_and(|output| output.status.success());
    if !available {
        assert!(
            !common::oracles_required(),
            "the Python packages mcap and mcap-ros2-support are required (LAMP_REQUIRE_ORACLES=1)"
        );
        println!(
            "skipped: python3 with mcap and mcap-ros2-support is not installed (pip install mcap mcap-ros2-support)"
        );
    }
    available
}

fn run_python(script: &str, arguments: &[&Path]) -> String {
    let output = Command::new("python3")
        .arg("-c")
        .arg(script)
        .args(arguments)
        .output()
        .expect("python3 runs");
    assert!(output.status.success(), "python failed:\n{}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8(output.stdout).expect("python prints UTF-8")
}

/// Prints one line per fact; floats as `repr`, which round-trips exactly.
const READ_SCRIPT: &str = r#"
import sys
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

with open(sys.argv[1], "rb") as stream:
    reader = make_reader(stream, validate_crcs=True, decoder_factories=[DecoderFactory()])
    header = reader.get_header()
    print("profile", header.profile)
    print("library", header.library)
    summary = reader.get_summary()
    print("message_count", summary.statistics.message_count)
    for channel in summary.channels.values():
        schema = summary.schemas[channel.schema_id]
        print("channel", channel.topic, channel.message_encoding, schema.name, schema.encoding)
    for record in reader.iter_metadata():
        for key, value in sorted(record.metadata.items()):
            print("metadata", record.name, key, repr(value))
    for _, _, message, step in reader.iter_decoded_messages(topics=["/lamp/world"]):
        values = [message.log_time, message.sequence, step.stamp.sec, step.stamp.nanosec]
        for pose in step.body_poses:
            p, q = pose.position, pose.orientation
            values += [repr(v) for v in (p.x, p.y, p.z, q.x, q.y, q.z, q.w)]
        for robot in step.robots:
            values += [repr(v) for v in robot.positions] + ["held=" + ",".join(robot.held)]
        print("step", *values)
"#;

fn expected_lines(trajectory: &Trajectory) -> Vec<String> {
    let header: &TrajectoryHeader = &trajectory.header;
    let mut lines = vec![
        "profile ros2".to_string(),
        "library lamp-trajectory format 1".to_string(),
        format!("message_count {}", trajectory.steps.len()),
        "channel /lamp/world cdr lamp_msgs/msg/WorldStep ros2msg".to_string(),
    ];
    let mut metadata = vec![
        (
            "bodies".to_string(),
            header
                .bodies
                .iter()
                .map(|b| format!("{} {}", b.name, b.type_name))
                .collect::<Vec<_>>()
                .join("\n"),
        ),
        ("domain".to_string(), header.domain.clone()),
        ("format".to_string(), "lamp-trajectory".to_string()),
        ("format_version".to_string(), "1".to_string()),
        (
            "robots".to_string(),
            header.robots.iter().map(|r| r.name.clone()).collect::<Vec<_>>().join("\n"),
        ),
        ("seed".to_string(), header.seed.to_string()),
    ];
    for robot in &header.robots {
        metadata.push((format!("robot.{}.coordinates", robot.name), robot.coordinates.join(" ")));
        metadata.push((format!("robot.{}.grippers", robot.name), robot.grippers.join(" ")));
    }
    for (key, value) in &header.provenance {
        metadata.push((format!("provenance.{key}"), value.clone()));
    }
    metadata.sort();
    for (key, value) in metadata {
        lines.push(format!("metadata lamp {key} {}", python_repr(&value)));
    }
    for (index, step) in trajectory.steps.iter().enumerate() {
        let mut values = vec![
            step.time_nanoseconds.to_string(),
            index.to_string(),
            (step.time_nanoseconds / 1_000_000_000).to_string(),
            (step.time_nanoseconds % 1_000_000_000).to_string(),
        ];
        for pose in &step.body_poses {
            let coords = pose.rotation.as_ref().coords;
            for value in pose.translation.vector.iter().chain(coords.iter()) {
                values.push(format!("{value:?}"));
            }
        }
        for robot in &step.robots {
            values.extend(robot.positions.iter().map(|value| format!("{value:?}")));
            let held: Vec<&str> = robot
                .held
                .iter()
                .map(|held| held.map_or("", |index| header.bodies[index].name.as_str()))
                .collect();
            values.push(format!("held={}", held.join(",")));
        }
        lines.push(format!("step {}", values.join(" ")));
    }
    lines
}

/// Python's `repr` of a string without quotes or backslashes in it.
fn python_repr(text: &str) -> String {
    format!("'{}'", text.replace('\n', "\\n"))
}

/// Compares a Rust and a Python float spelling by value, bit for bit.
fn same_line(rust: &str, python: &str) -> bool {
    let rust: Vec<&str> = rust.split(' ').collect();
    let python: Vec<&str> = python.split(' ').collect();
    rust.len() == python.len()
        && rust.iter().zip(&python).all(|(a, b)| match (a.parse::<f64>(), b.parse::<f64>()) {
            (Ok(a), Ok(b)) => a.to_bits() == b.to_bits(),
            _ => a == b,
        })
}

#[test]
fn the_python_reader_decodes_our_files_to_the_same_numbers() {
    if !python_packages_available() {
        return;
    }
    let directory = tempfile::tempdir().unwrap();
    for (name, trajectory) in [
        ("steps.mcap", common::trajectory(4, 120, 21)),
        ("empty.mcap", Trajectory { header: common::header(1), steps: vec![] }),
    ] {
        let path = directory.path().join(name);
        trajectory.write_file(&path).unwrap();
        let output = run_python(READ_SCRIPT, &[&path]);
        let actual: Vec<&str> = output.lines().collect();
        let expected = expected_lines(&trajectory);
        assert_eq!(actual.len(), expected.len(), "{name}:\n{output}");
        for (rust, python) in expected.iter().zip(&actual) {
            assert!(same_line(rust, python), "{name}: rust `{rust}`\npython `{python}`");
        }
    }
}

/// The `index`th ```python block of `docs/formats.md`.
fn python_example(index: usize) -> String {
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/formats.md");
    let text = std::fs::read_to_string(&docs).expect("docs/formats.md is readable");
    let mut blocks = text.split("```python\n").skip(1);
    let block = blocks.nth(index).expect("the python example in docs/formats.md");
    block[..block.find("```").expect("the example block is closed")].to_string()
}

/// The first ```python block of `docs/formats.md`: writing a trajectory.
fn conversion_example() -> String {
    python_example(0)
}

#[test]
fn the_documented_reading_example_reads_joint_trajectories_gripper_commands_and_approaches() {
    if !python_packages_available() {
        return;
    }
    let trajectory = common::trajectory(1, 30, 5);
    let joints = ["torso", "j1", "j2", "j3"].map(String::from).to_vec();
    let base = ["base_x", "base_y", "base_yaw"].map(String::from).to_vec();
    let channels = StandardChannels {
        trajectory_topics: vec![
            TrajectoryTopic { topic: JOINT_TRAJECTORY_TOPIC.into(), joints },
            TrajectoryTopic { topic: BASE_TRAJECTORY_TOPIC.into(), joints: base },
        ],
        gripper_topics: vec![GRIPPER_COMMAND_TOPIC.into()],
        approaches: true,
        ..StandardChannels::rooted_at("world")
    };
    let steps = &trajectory.steps;
    let mut values: Vec<StandardStep> = steps
        .iter()
        .map(|_| StandardStep {
            frame_poses: vec![],
            joint_positions: vec![],
            label: None,
            approach: None,
            held: vec![],
            trajectories: vec![],
            gripper_commands: vec![],
        })
        .collect();
    // A motion of the arm over steps 0..=9 and of the base over 10..=19; a grasp at step 9 and a
    // release at step 19.
    let motion = |topic: usize, range: std::ops::RangeInclusive<usize>, coordinates: &[usize]| {
        let start = steps[*range.start()].time_nanoseconds;
        let points = steps[range]
            .iter()
            .map(|step| TrajectoryPoint {
                positions: coordinates.iter().map(|c| step.robots[0].positions[*c]).collect(),
                velocities: vec![0.25; coordinates.len()],
                time_from_start_nanoseconds: step.time_nanoseconds - start,
            })
            .collect();
        JointTrajectoryMessage { topic, points }
    };
    values[0].trajectories.push(motion(0, 0..=9, &[3, 4, 5, 6]));
    values[10].trajectories.push(motion(1, 10..=19, &[0, 1, 2]));
    values[5].approach = Some(r#"{"kind":"put_down","object":"can1","to_seconds":1.25}"#.into());
    values[9].gripper_commands.push(GripperCommand { topic: 0, position: 0.0, max_effort: 0.0 });
    values[19].gripper_commands.push(GripperCommand { topic: 0, position: 0.05, max_effort: 0.0 });
    let directory = tempfile::tempdir().unwrap();
    let path = directory.path().join("solution.mcap");
    std::fs::write(&path, trajectory.to_bytes_with(&channels, &values).unwrap()).unwrap();
    let output = run_python(&python_example(1), &[&path]);
    let seconds = |from: usize, to: usize| {
        let nanoseconds = steps[to].time_nanoseconds - steps[from].time_nanoseconds;
        nanoseconds as f64 / 1e9
    };
    let expected = [
        "robots fetch camera_mast".to_string(),
        format!(
            "/lamp/joint_trajectory {} torso j1 j2 j3 10 {} {}",
            steps[0].time_nanoseconds,
            steps[9].robots[0].positions[3],
            seconds(0, 9)
        ),
        format!("approach {} put_down can1 1.25", steps[5].time_nanoseconds),
        format!("gripper {} 0.0 0.0", steps[9].time_nanoseconds),
        format!(
            "/lamp/base_trajectory {} base_x base_y base_yaw 10 {} {}",
            steps[10].time_nanoseconds,
            steps[19].robots[0].positions[0],
            seconds(10, 19)
        ),
        format!("gripper {} 0.05 0.0", steps[19].time_nanoseconds),
        "steps 30".to_string(),
    ];
    let actual: Vec<&str> = output.lines().collect();
    assert_eq!(actual.len(), expected.len(), "{output}");
    for (rust, python) in expected.iter().zip(&actual) {
        assert!(same_line(rust, python), "rust `{rust}`\npython `{python}`");
    }
}

#[test]
fn the_documented_conversion_example_writes_files_we_read() {
    if !python_packages_available() {
        return;
    }
    let directory = tempfile::tempdir().unwrap();
    let path: PathBuf = directory.path().join("converted.mcap");
    run_python(&conversion_example(), &[&path]);
    let trajectory = Trajectory::read_file(&path).unwrap();
    let header = &trajectory.header;
    assert_eq!(header.domain, "packing");
    assert_eq!(header.bodies.len(), 2);
    assert_eq!(header.bodies[1].type_name, "surface");
    assert_eq!(header.robots[0].coordinates, ["x", "y", "z", "yaw"]);
    assert_eq!(header.provenance["source"], "my recording");
    assert_eq!(trajectory.steps.len(), 100);
    for (index, step) in trajectory.steps.iter().enumerate() {
        let holding = index >= 50;
        let lift = 0.1 + 0.002 * index as f64;
        assert_eq!(step.time_nanoseconds, index as u64 * 10_000_000);
        let can = &step.body_poses[0];
        assert_eq!(can.translation.z.to_bits(), if holding { lift } else { 0.1 }.to_bits());
        let yaw = 0.01 * index as f64;
        assert!((can.rotation.angle() - yaw).abs() < TRIGONOMETRY_TOLERANCE * 10.0, "{index}");
        assert!((can.rotation.quaternion().k - (yaw / 2.0).sin()).abs() <= TRIGONOMETRY_TOLERANCE);
        assert_eq!(step.robots[0].positions[2].to_bits(), (lift + 0.05).to_bits());
        assert_eq!(step.robots[0].held, [holding.then_some(0)]);
    }
}
