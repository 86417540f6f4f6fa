//! Damaged files give typed errors, never panics and never silently different data: a file cut
//! at every offset says "truncated", and random byte flips are caught by the checksums.

mod common;

use lamp_trajectory::{Trajectory, TrajectoryError};
use miette::Diagnostic;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const FLIPS: usize = 3000;

#[test]
fn a_file_cut_anywhere_is_truncated() {
    let original = common::trajectory(3, 12, 11);
    let bytes = original.to_bytes().unwrap();
    for length in 0..bytes.len() {
        let error = Trajectory::from_bytes(&bytes[..length], "cut.mcap").unwrap_err();
        assert!(
            matches!(error, TrajectoryError::Truncated { .. }),
            "cut at {length} of {}: {error:?}",
            bytes.len()
        );
        assert_eq!(error.code().unwrap().to_string(), "lamp::trajectory::truncated");
        assert!(error.to_string().contains("cut.mcap is truncated"), "{error}");
    }
}

#[test]
fn flipped_bytes_are_errors_or_change_nothing() {
    let original = common::trajectory(3, 40, 12);
    let bytes = original.to_bytes().unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let mut detected = 0;
    for _ in 0..FLIPS {
        let mut damaged = bytes.clone();
        let flips = rng.random_range(1..=3);
        for _ in 0..flips {
            let index = rng.random_range(0..damaged.len());
            damaged[index] ^= rng.random_range(1..=255u8);
        }
        match Trajectory::from_bytes(&damaged, "flipped.mcap") {
            Ok(read) => assert_eq!(read, original, "damage changed the data without an error"),
            Err(error) => {
                detected += 1;
                let code = error.code().unwrap().to_string();
                assert!(code.starts_with("lamp::trajectory::"), "{code}");
                assert!(error.to_string().contains("flipped.mcap"), "{error}");
            }
        }
    }
    // Every byte of the file is covered by a magic, a CRC or a structural check.
    assert_eq!(detected, FLIPS, "undetected damage");
}

#[test]
fn the_first_steps_of_a_file_damaged_late_are_still_returned() {
    let original = common::trajectory(3, 40, 14);
    let mut bytes = original.to_bytes().unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 0xff; // the end magic
    let mut reader = lamp_trajectory::TrajectoryReader::from_bytes(&bytes, "late").unwrap();
    let steps: Vec<_> = reader.by_ref().take(40).collect::<Result<_, _>>().unwrap();
    assert_eq!(steps, original.steps);
    let error = reader.next().unwrap().unwrap_err();
    assert!(matches!(error, TrajectoryError::Corrupt { steps: 40, .. }), "{error:?}");
    assert!(reader.next().is_none());
}

/// A file made of the MCAP magic and the given records (opcode, content), without an end.
fn records(list: &[(u8, Vec<u8>)]) -> Vec<u8> {
    let mut bytes = mcap::MAGIC.to_vec();
    for (opcode, content) in list {
        bytes.push(*opcode);
        bytes.extend_from_slice(&(content.len() as u64).to_le_bytes());
        bytes.extend_from_slice(content);
    }
    bytes
}

/// An uncompressed chunk (no CRC) around `data`.
fn uncompressed_chunk(data: &[u8]) -> Vec<u8> {
    let mut content = Vec::new();
    content.extend_from_slice(&0u64.to_le_bytes()); // message start time
    content.extend_from_slice(&0u64.to_le_bytes()); // message end time
    content.extend_from_slice(&(data.len() as u64).to_le_bytes()); // uncompressed size
    content.extend_from_slice(&0u32.to_le_bytes()); // uncompressed CRC: none
    content.extend_from_slice(&0u32.to_le_bytes()); // compression: "" (none)
    content.extend_from_slice(&(data.len() as u64).to_le_bytes()); // compressed size
    content.extend_from_slice(data);
    content
}

#[test]
fn a_record_longer_than_its_uncompressed_chunk_is_corrupt() {
    // A metadata record that claims 100 bytes in a chunk of 12 (found by the `trajectory` fuzz
    // target: the MCAP crate's own chunk reading subtracted past zero).
    let mut inner = vec![mcap::records::op::METADATA];
    inner.extend_from_slice(&100u64.to_le_bytes());
    inner.extend_from_slice(b"abc");
    // What follows the chunk (here a record of an unknown kind) is what an overrun would read.
    let after = (0x80, vec![0; 120]);
    let bytes = records(&[(mcap::records::op::CHUNK, uncompressed_chunk(&inner)), after.clone()]);
    let error = Trajectory::from_bytes(&bytes, "overrun.mcap").unwrap_err();
    assert!(matches!(error, TrajectoryError::Corrupt { record: 0, .. }), "{error:?}");
    assert!(error.to_string().contains("of 100 bytes overruns its chunk"), "{error}");
    // A record header cut off by the chunk's end.
    let bytes = records(&[(mcap::records::op::CHUNK, uncompressed_chunk(&inner[..5])), after]);
    let error = Trajectory::from_bytes(&bytes, "cut.mcap").unwrap_err();
    assert!(error.to_string().contains("cut off at the end of a chunk"), "{error}");
}

#[test]
fn records_lamp_does_not_read_are_not_parsed() {
    // An attachment without its CRC: the MCAP crate's attachment parser slices past its end.
    let mut attachment = Vec::new();
    attachment.extend_from_slice(&0u64.to_le_bytes()); // log time
    attachment.extend_from_slice(&0u64.to_le_bytes()); // create time
    attachment.extend_from_slice(&0u32.to_le_bytes()); // name: ""
    attachment.extend_from_slice(&0u32.to_le_bytes()); // media type: ""
    attachment.extend_from_slice(&0u64.to_le_bytes()); // data length; no data, no CRC
    for bytes in [
        records(&[(mcap::records::op::ATTACHMENT, attachment.clone())]),
        records(&[(
            mcap::records::op::CHUNK,
            uncompressed_chunk(&records(&[(mcap::records::op::ATTACHMENT, attachment)])[8..]),
        )]),
    ] {
        let error = Trajectory::from_bytes(&bytes, "attachment.mcap").unwrap_err();
        assert!(matches!(error, TrajectoryError::Truncated { .. }), "{error:?}");
    }
}

/// `text` as an MCAP string: a u32 length and the bytes.
fn string(text: &[u8]) -> Vec<u8> {
    let mut bytes = (text.len() as u32).to_le_bytes().to_vec();
    bytes.extend_from_slice(text);
    bytes
}

#[test]
fn a_field_longer_than_its_record_is_corrupt_before_memory_is_reserved_for_it() {
    // A metadata name that says 4 GiB in a record of 8 bytes (found by the `trajectory` fuzz
    // target under AddressSanitizer: the MCAP crate reserved the 4 GiB before reading).
    let mut metadata = 0xffff_fff0_u32.to_le_bytes().to_vec();
    metadata.extend_from_slice(b"lamp");
    let bytes = records(&[(mcap::records::op::METADATA, metadata)]);
    let error = Trajectory::from_bytes(&bytes, "long.mcap").unwrap_err();
    assert!(matches!(error, TrajectoryError::Corrupt { record: 0, .. }), "{error:?}");
    let expected = "the name field of a record says 4294967280 bytes, 4 are left in the record";
    assert!(error.to_string().contains(expected), "{error}");
    // A chunk whose compression name says 4 GiB (found the same way, in a chunk header).
    let mut chunk = vec![0; 8 + 8 + 8 + 4];
    chunk.extend_from_slice(&0xffff_fff0_u32.to_le_bytes());
    chunk.extend_from_slice(b"zstd");
    chunk.extend_from_slice(&0u64.to_le_bytes());
    let bytes = records(&[(mcap::records::op::CHUNK, chunk)]);
    let error = Trajectory::from_bytes(&bytes, "chunk.mcap").unwrap_err();
    assert!(matches!(error, TrajectoryError::Corrupt { record: 0, .. }), "{error:?}");
    let expected = "the compression field of a record says 4294967280 bytes, 12 are left";
    assert!(error.to_string().contains(expected), "{error}");
    // A key of a channel's metadata map that runs past the map.
    let mut channel = vec![1, 0, 1, 0];
    channel.extend(string(b"/lamp/world"));
    channel.extend(string(b"cdr"));
    let mut map = 0xffff_u32.to_le_bytes().to_vec();
    map.extend_from_slice(b"key");
    channel.extend(string(&map));
    let bytes = records(&[(mcap::records::op::CHANNEL, channel)]);
    let error = Trajectory::from_bytes(&bytes, "map.mcap").unwrap_err();
    assert!(
        error.to_string().contains("the map key field of a record says 65535 bytes"),
        "{error}"
    );
}
