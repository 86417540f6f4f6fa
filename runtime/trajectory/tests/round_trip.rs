//! Writing and reading back: byte-exact round trips, determinism, the empty file, file entry
//! points, and the checks a writer and a reader apply to steps.

mod common;

use std::collections::BTreeMap;
use std::io::Cursor;

use lamp_trajectory::{
    IN_MEMORY_NAME, Step, Trajectory, TrajectoryError, TrajectoryReader, TrajectoryWriter,
};
use miette::Diagnostic;
use nalgebra::Isometry3;

#[test]
fn write_read_write_gives_identical_bytes_and_bit_identical_values() {
    let original = common::trajectory(5, 300, 1);
    let bytes = original.to_bytes().unwrap();
    let read = Trajectory::from_bytes(&bytes, "first").unwrap();
    common::assert_bit_identical(&original, &read);
    assert_eq!(read, original);
    let again = read.to_bytes().unwrap();
    assert_eq!(bytes, again, "a re-written file differs from the original");
}

#[test]
fn output_depends_only_on_the_data() {
    let a = common::trajectory(3, 50, 9).to_bytes().unwrap();
    let b = common::trajectory(3, 50, 9).to_bytes().unwrap();
    let c = common::trajectory(3, 50, 10).to_bytes().unwrap();
    assert_eq!(a, b);
    assert_ne!(a, c);
}

#[test]
fn several_chunks_round_trip() {
    // About 1.5 kB a step: 2000 steps span three 1 MiB chunks.
    let original = common::trajectory(25, 2000, 2);
    let bytes = original.to_bytes().unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().expect("a summary section");
    assert!(summary.chunk_indexes.len() >= 3, "{} chunks", summary.chunk_indexes.len());
    let read = Trajectory::from_bytes(&bytes, "chunks").unwrap();
    common::assert_bit_identical(&original, &read);
}

#[test]
fn a_header_only_file_reads_as_no_steps() {
    let empty = Trajectory { header: common::header(2), steps: vec![] };
    let bytes = empty.to_bytes().unwrap();
    let reader = TrajectoryReader::from_bytes(&bytes, "empty").unwrap();
    assert_eq!(reader.header(), &empty.header);
    assert_eq!(reader.read_all().unwrap(), empty);
}

#[test]
fn the_reader_streams_steps_in_order() {
    let original = common::trajectory(2, 40, 3);
    let bytes = original.to_bytes().unwrap();
    let mut reader = TrajectoryReader::new(Cursor::new(&bytes), "stream").unwrap();
    for (index, expected) in original.steps.iter().enumerate() {
        assert_eq!(reader.steps_read(), index as u64);
        assert_eq!(&reader.next().unwrap().unwrap(), expected);
    }
    assert!(reader.next().is_none());
}

#[test]
fn files_round_trip_and_errors_name_the_path() {
    let directory = tempfile::tempdir().unwrap();
    let path = directory.path().join("demo.mcap");
    let original = common::trajectory(2, 10, 4);
    original.write_file(&path).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), original.to_bytes().unwrap());
    assert_eq!(Trajectory::read_file(&path).unwrap(), original);

    let missing = directory.path().join("missing.mcap");
    let error = Trajectory::read_file(&missing).unwrap_err();
    assert!(matches!(error, TrajectoryError::Io { action: "open", .. }), "{error:?}");
    assert!(error.to_string().contains("missing.mcap"), "{error}");
    assert_eq!(error.code().unwrap().to_string(), "lamp::trajectory::io");

    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
    let error = Trajectory::read_file(&path).unwrap_err();
    assert!(error.to_string().contains("demo.mcap"), "{error}");
    assert!(error.to_string().contains("truncated"), "{error}");
}

#[test]
fn the_writer_rejects_steps_that_disagree_with_the_header() {
    let trajectory = common::trajectory(2, 3, 5);
    let mut writer =
        TrajectoryWriter::new(Cursor::new(Vec::new()), "out", trajectory.header.clone()).unwrap();
    writer.write_step(&trajectory.steps[0]).unwrap();

    let mut missing_body = trajectory.steps[1].clone();
    missing_body.body_poses.pop();
    let error = writer.write_step(&missing_body).unwrap_err();
    assert!(matches!(error, TrajectoryError::Inconsistent { step: 1, .. }), "{error:?}");
    assert_eq!(error.code().unwrap().to_string(), "lamp::trajectory::inconsistent");

    let mut earlier: Step = trajectory.steps[1].clone();
    earlier.time_nanoseconds = 0;
    writer.write_step(&earlier).unwrap(); // equal times are allowed
    writer.write_step(&trajectory.steps[2]).unwrap();
    assert!(writer.write_step(&earlier).is_err(), "time went backwards");

    let mut nan = trajectory.steps[2].clone();
    nan.body_poses[0].translation.vector.x = f64::INFINITY;
    let error = writer.write_step(&nan).unwrap_err();
    assert_eq!(error.code().unwrap().to_string(), "lamp::trajectory::invalid_value");
    assert_eq!(writer.steps_written(), 3);
    let bytes = writer.finish().unwrap().into_inner();
    assert_eq!(Trajectory::from_bytes(&bytes, "out").unwrap().steps.len(), 3);
}

#[test]
fn the_writer_rejects_headers_it_cannot_store() {
    let mut header = common::header(1);
    header.bodies[0].name = "can 0".into();
    let error =
        TrajectoryWriter::new(Cursor::new(Vec::new()), IN_MEMORY_NAME, header).err().unwrap();
    assert_eq!(error.code().unwrap().to_string(), "lamp::trajectory::header");
    let mut header = common::header(1);
    header.robots[0].coordinates.push("base_x".into());
    assert!(TrajectoryWriter::new(Cursor::new(Vec::new()), IN_MEMORY_NAME, header).is_err());
}

/// Writes an MCAP file by hand, as another tool would: the documented metadata entries and a
/// hand-encoded message, so the reader is checked against the documentation, not the writer.
fn hand_written_file(bodies: &str, message: &[u8], metadata_first: bool) -> Vec<u8> {
    let metadata: BTreeMap<String, String> = [
        ("format", "lamp-trajectory"),
        ("format_version", "1"),
        ("domain", "hand"),
        ("seed", "5"),
        ("bodies", bodies),
        ("robots", ""),
    ]
    .into_iter()
    .map(|(key, value)| (key.to_string(), value.to_string()))
    .collect();
    let metadata = mcap::records::Metadata { name: "lamp".into(), metadata };
    let mut writer = mcap::Writer::new(Cursor::new(Vec::new()))
        .expect("writing an MCAP file to memory succeeds");
    if metadata_first {
        writer.write_metadata(&metadata).expect("writing an MCAP file to memory succeeds");
    }
    let schema = writer
        .add_schema(
            "lamp_msgs/msg/WorldStep",
            "ros2msg",
            lamp_trajectory::WORLD_STEP_SCHEMA.as_bytes(),
        )
        .expect("writing an MCAP file to memory succeeds");
    let channel = writer
        .add_channel(schema, "/lamp/world", "cdr", &BTreeMap::new())
        .expect("writing an MCAP file to memory succeeds");
    let header = mcap::records::MessageHeader {
        channel_id: channel,
        sequence: 0,
        log_time: 7,
        publish_time: 7,
    };
    writer
        .write_to_known_channel(&header, message)
        .expect("writing an MCAP file to memory succeeds");
    writer.flush().expect("writing an MCAP file to memory succeeds");
    if !metadata_first {
        writer.write_metadata(&metadata).expect("writing an MCAP file to memory succeeds");
    }
    writer.finish().expect("writing an MCAP file to memory succeeds");
    writer.into_inner().into_inner()
}

/// stamp 0 s 7 ns, one identity pose at (0, 0, 0), no robots.
fn one_pose_message() -> Vec<u8> {
    let mut message = vec![0, 1, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0];
    for value in [0.0f64, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0] {
        message.extend_from_slice(&value.to_le_bytes());
    }
    message.extend_from_slice(&[0, 0, 0, 0]);
    message
}

#[test]
fn a_hand_written_file_reads() {
    let bytes = hand_written_file("cup mug", &one_pose_message(), true);
    let trajectory = Trajectory::from_bytes(&bytes, "hand").unwrap();
    assert_eq!(trajectory.header.bodies[0].type_name, "mug");
    assert_eq!(trajectory.steps.len(), 1);
    assert_eq!(trajectory.steps[0].time_nanoseconds, 7);
    assert_eq!(trajectory.steps[0].body_poses[0], Isometry3::identity());
}

#[test]
fn a_step_with_another_body_count_than_the_header_is_inconsistent() {
    let bytes = hand_written_file("cup mug\nplate dish", &one_pose_message(), true);
    let error = Trajectory::from_bytes(&bytes, "hand.mcap").unwrap_err();
    assert!(matches!(error, TrajectoryError::Inconsistent { step: 0, .. }), "{error:?}");
    assert_eq!(error.code().unwrap().to_string(), "lamp::trajectory::inconsistent");
    assert!(error.to_string().contains("hand.mcap, step 0"), "{error}");
    assert!(error.to_string().contains("1 body poses but the header lists 2 bodies"), "{error}");
}

#[test]
fn steps_before_the_header_or_foreign_files_are_schema_errors() {
    let bytes = hand_written_file("cup mug", &one_pose_message(), false);
    let error = Trajectory::from_bytes(&bytes, "late").unwrap_err();
    assert_eq!(error.code().unwrap().to_string(), "lamp::trajectory::schema");
    assert!(error.to_string().contains("before the `lamp` metadata record"), "{error}");

    let mut writer = mcap::Writer::new(Cursor::new(Vec::new())).unwrap();
    writer.finish().unwrap();
    let bytes = writer.into_inner().into_inner();
    let error = Trajectory::from_bytes(&bytes, "bare").err().unwrap();
    assert!(matches!(error, TrajectoryError::Schema { .. }), "{error:?}");
}

#[test]
fn a_world_topic_with_another_schema_is_a_schema_error() {
    let mut writer = mcap::Writer::new(Cursor::new(Vec::new())).unwrap();
    let header = common::header(1);
    // Reuse a valid header by copying a real file's metadata record.
    let real = Trajectory { header, steps: vec![] }.to_bytes().unwrap();
    let summary = mcap::Summary::read(&real).unwrap().unwrap();
    let metadata = mcap::read::metadata(&real, &summary.metadata_indexes[0]).unwrap();
    writer.write_metadata(&metadata).unwrap();
    let schema = writer.add_schema("std_msgs/msg/String", "ros2msg", b"string data").unwrap();
    writer.add_channel(schema, "/lamp/world", "cdr", &BTreeMap::new()).unwrap();
    writer.finish().unwrap();
    let bytes = writer.into_inner().into_inner();
    let error = Trajectory::from_bytes(&bytes, "foreign").unwrap_err();
    assert!(matches!(error, TrajectoryError::Schema { .. }), "{error:?}");
    assert!(error.to_string().contains("std_msgs/msg/String"), "{error}");
}

#[test]
fn uncompressed_chunks_read_like_compressed_ones() {
    // Other writers may leave chunks uncompressed: copy a lamp file with the MCAP crate's writer
    // and no compression (metadata first, as lamp requires), then read both.
    let original = common::trajectory(3, 20, 15);
    let bytes = original.to_bytes().unwrap();
    let mut copy = Cursor::new(Vec::new());
    let mut writer = mcap::WriteOptions::new()
        .compression(None)
        .profile(lamp_trajectory::PROFILE)
        .create(&mut copy)
        .unwrap();
    for record in mcap::read::ChunkFlattener::new(&bytes).unwrap() {
        if let mcap::records::Record::Metadata(metadata) = record.unwrap() {
            writer.write_metadata(&metadata).unwrap();
        }
    }
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        writer.write(&message.unwrap()).unwrap();
    }
    writer.finish().unwrap();
    drop(writer);
    let copy = copy.into_inner();
    let summary = mcap::Summary::read(&copy).unwrap().expect("a summary section");
    assert!(!summary.chunk_indexes.is_empty(), "the copy has chunks");
    assert!(summary.chunk_indexes.iter().all(|index| index.compression.is_empty()));
    assert_eq!(Trajectory::from_bytes(&copy, "uncompressed").unwrap(), original);
}
