//! The demonstration and trajectory reader: `Trajectory::from_bytes` and the streaming
//! `TrajectoryReader` on arbitrary bytes.
//!
//! The whole-file read and a streaming read through a source that hands out a few bytes per call
//! must agree (same trajectory, or the same error); a trajectory the reader accepts must be
//! writable and read back equal.

use std::io::Read;

use lamp_trajectory::{Trajectory, TrajectoryReader};

/// The name inputs go by in errors.
const NAME: &str = "fuzz.mcap";

/// Bytes per `read` call of the streaming source: small and odd, so that records, chunk headers
/// and CDR fields straddle reads.
const SHORT_READ: usize = 7;

/// Reads the trajectory in `data` whole and streamed.
///
/// # Panics
/// When the reader panics, the two reads disagree, or an accepted trajectory does not survive
/// writing and reading back.
pub fn trajectory(data: &[u8]) {
    let whole = Trajectory::from_bytes(data, NAME);
    let streamed = streamed(data);
    match (&whole, &streamed) {
        (Ok(whole), Ok(streamed)) => assert_eq!(whole, streamed, "whole and streamed reads differ"),
        (Err(whole), Err(streamed)) => assert_eq!(
            whole.to_string(),
            streamed.to_string(),
            "whole and streamed reads fail differently"
        ),
        _ => panic!("one read fails, the other does not: {whole:?} versus {streamed:?}"),
    }
    if let Ok(trajectory) = whole {
        let bytes = trajectory
            .to_bytes()
            .unwrap_or_else(|error| panic!("an accepted trajectory cannot be written: {error}"));
        let back = Trajectory::from_bytes(&bytes, NAME)
            .unwrap_or_else(|error| panic!("a written trajectory cannot be read: {error}"));
        assert_eq!(back, trajectory, "a trajectory changes when written and read back");
    }
}

/// Reads step by step from a source of short reads; after the first error the reader must end.
fn streamed(data: &[u8]) -> Result<Trajectory, lamp_trajectory::TrajectoryError> {
    let mut reader = TrajectoryReader::new(ShortReads(data), NAME)?;
    let header = reader.header().clone();
    let mut steps = Vec::new();
    while let Some(step) = reader.next() {
        match step {
            Ok(step) => steps.push(step),
            Err(error) => {
                assert!(reader.next().is_none(), "the reader goes on after an error");
                return Err(error);
            }
        }
    }
    assert_eq!(reader.steps_read(), steps.len() as u64, "the reader miscounts its steps");
    Ok(Trajectory { header, steps })
}

/// A byte source that returns at most [`SHORT_READ`] bytes per call.
struct ShortReads<'a>(&'a [u8]);

impl Read for ShortReads<'_> {
    fn read(&mut self, buffer: &mut [u8]) -> std::io::Result<usize> {
        let count = buffer.len().min(SHORT_READ).min(self.0.len());
        buffer[..count].copy_from_slice(&self.0[..count]);
        self.0 = &self.0[count..];
        Ok(count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lamp_trajectory::{BodyDescription, Step, TrajectoryHeader};

    fn example() -> Vec<u8> {
        let header = TrajectoryHeader {
            domain: "packing".into(),
            seed: 1,
            provenance: Default::default(),
            bodies: vec![BodyDescription { name: "can_0".into(), type_name: "can".into() }],
            robots: vec![],
        };
        let steps = (0..3)
            .map(|index| Step {
                time_nanoseconds: index * 1_000_000,
                body_poses: vec![nalgebra::Isometry3::translation(0.1 * index as f64, 0.0, 0.0)],
                robots: vec![],
            })
            .collect();
        Trajectory { header, steps }.to_bytes().expect("the example writes")
    }

    #[test]
    fn short_reads_give_the_same_trajectory() {
        let bytes = example();
        let whole = Trajectory::from_bytes(&bytes, NAME).expect("the example reads");
        assert_eq!(streamed(&bytes).expect("the example streams"), whole);
        assert_eq!(whole.steps.len(), 3);
        trajectory(&bytes);
    }

    #[test]
    fn truncated_and_damaged_files_fail_alike_both_ways() {
        let bytes = example();
        for cut in [0, 8, bytes.len() / 2, bytes.len() - 1] {
            assert!(streamed(&bytes[..cut]).is_err());
            trajectory(&bytes[..cut]);
        }
        let mut damaged = bytes.clone();
        let middle = damaged.len() / 2;
        damaged[middle] ^= 0x55;
        trajectory(&damaged);
    }
}
