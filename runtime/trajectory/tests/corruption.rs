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
