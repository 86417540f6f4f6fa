//! The streaming writer: a header, then one message per step, then the MCAP summary.
//!
//! Output is a pure function of the header and the steps: no wall-clock time is written (message
//! times are the steps' times), the metadata map is sorted, the chunk size, compression level
//! and compressor threading are fixed, and the library string does not carry a crate version.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Cursor, Seek, Write};
use std::path::Path;

use mcap::records::{MessageHeader, Metadata};
use mcap::{Compression, WriteOptions};

use crate::codec::{check_step, encode_step};
use crate::error::TrajectoryError;
use crate::model::{Step, Trajectory, TrajectoryHeader};
use crate::schema::{
    MESSAGE_ENCODING, METADATA_NAME, PROFILE, SCHEMA_ENCODING, WORLD_STEP_SCHEMA,
    WORLD_STEP_SCHEMA_NAME, WORLD_TOPIC, header_to_metadata,
};

/// The MCAP `library` field; no crate version, so a release does not change every file.
pub const LIBRARY: &str = "lamp-trajectory format 1";

/// Target uncompressed chunk size: big enough for zstd to find the repetition between steps,
/// small enough that a reader holds little in memory (and the MCAP writers' common default).
pub const CHUNK_SIZE: u64 = 1024 * 1024;

/// zstd's own default level: fast to write, and trajectories compress well at it.
const ZSTD_LEVEL: u32 = 3;

/// Single-threaded zstd: multi-threaded zstd emits different bytes than single-threaded, and the
/// default thread count follows the machine's cores, which would make output machine-dependent.
const ZSTD_THREADS: u32 = 0;

/// The name in errors of a trajectory written to memory.
pub const IN_MEMORY_NAME: &str = "<in-memory trajectory>";

/// Writes a trajectory file step by step.
///
/// Dropping the writer without [`TrajectoryWriter::finish`] still completes the file, but
/// ignores any error in doing so.
pub struct TrajectoryWriter<W: Write + Seek> {
    mcap: mcap::Writer<W>,
    header: TrajectoryHeader,
    file: String,
    channel_id: u16,
    steps: u64,
    previous_time: Option<u64>,
}

impl TrajectoryWriter<BufWriter<File>> {
    /// Creates (or truncates) the file at `path` and writes the header.
    pub fn create(
        path: impl AsRef<Path>,
        header: TrajectoryHeader,
    ) -> Result<Self, TrajectoryError> {
        let path = path.as_ref();
        let file = File::create(path).map_err(|source| TrajectoryError::Io {
            file: path.display().to_string(),
            action: "create",
            source,
        })?;
        Self::new(BufWriter::new(file), path.display().to_string(), header)
    }
}

impl<W: Write + Seek> TrajectoryWriter<W> {
    /// Starts a trajectory on `sink`; `name` identifies it in errors. Writes the MCAP header, the
    /// `lamp` metadata record, the schema and the channel.
    pub fn new(
        sink: W,
        name: impl Into<String>,
        header: TrajectoryHeader,
    ) -> Result<Self, TrajectoryError> {
        let file = name.into();
        header.check().map_err(|reason| TrajectoryError::Header { file: file.clone(), reason })?;
        let write_error = |error| mcap_write_error(&file, error);
        let options = WriteOptions::new()
            .profile(PROFILE)
            .library(LIBRARY)
            .compression(Some(Compression::Zstd))
            .compression_level(ZSTD_LEVEL)
            .compression_threads(ZSTD_THREADS)
            .chunk_size(Some(CHUNK_SIZE));
        let mut mcap = options.create(sink).map_err(write_error)?;
        mcap.write_metadata(&Metadata {
            name: METADATA_NAME.to_string(),
            metadata: header_to_metadata(&header),
        })
        .map_err(write_error)?;
        let schema_id = mcap
            .add_schema(WORLD_STEP_SCHEMA_NAME, SCHEMA_ENCODING, WORLD_STEP_SCHEMA.as_bytes())
            .map_err(write_error)?;
        let channel_id = mcap
            .add_channel(schema_id, WORLD_TOPIC, MESSAGE_ENCODING, &BTreeMap::new())
            .map_err(write_error)?;
        Ok(Self { mcap, header, file, channel_id, steps: 0, previous_time: None })
    }

    /// The header this file was started with.
    pub fn header(&self) -> &TrajectoryHeader {
        &self.header
    }

    /// How many steps have been written.
    pub fn steps_written(&self) -> u64 {
        self.steps
    }

    /// Checks a step against the header and the previous step, and appends it.
    pub fn write_step(&mut self, step: &Step) -> Result<(), TrajectoryError> {
        check_step(&self.header, step, self.previous_time)
            .map_err(|problem| TrajectoryError::from_step(&self.file, self.steps, 0, problem))?;
        let sequence = u32::try_from(self.steps).map_err(|_| TrajectoryError::InvalidValue {
            file: self.file.clone(),
            step: self.steps,
            reason: "a file holds at most 2^32 steps (the MCAP sequence number is 32 bits)".into(),
        })?;
        let data = encode_step(&self.header, step);
        let message = MessageHeader {
            channel_id: self.channel_id,
            sequence,
            log_time: step.time_nanoseconds,
            publish_time: step.time_nanoseconds,
        };
        self.mcap
            .write_to_known_channel(&message, &data)
            .map_err(|error| mcap_write_error(&self.file, error))?;
        self.steps += 1;
        self.previous_time = Some(step.time_nanoseconds);
        Ok(())
    }

    /// Writes the summary and footer, flushes, and returns the sink.
    pub fn finish(mut self) -> Result<W, TrajectoryError> {
        self.mcap.finish().map_err(|error| mcap_write_error(&self.file, error))?;
        let mut sink = self.mcap.into_inner();
        sink.flush().map_err(|source| TrajectoryError::Io {
            file: self.file.clone(),
            action: "write",
            source,
        })?;
        Ok(sink)
    }
}

fn mcap_write_error(file: &str, error: mcap::McapError) -> TrajectoryError {
    let source = match error {
        mcap::McapError::Io(source) => source,
        other => std::io::Error::other(other),
    };
    TrajectoryError::Io { file: file.to_string(), action: "write", source }
}

impl Trajectory {
    /// Writes the whole trajectory to `sink`.
    pub fn write_to<W: Write + Seek>(
        &self,
        sink: W,
        name: impl Into<String>,
    ) -> Result<W, TrajectoryError> {
        let mut writer = TrajectoryWriter::new(sink, name, self.header.clone())?;
        for step in &self.steps {
            writer.write_step(step)?;
        }
        writer.finish()
    }

    /// The file's bytes.
    pub fn to_bytes(&self) -> Result<Vec<u8>, TrajectoryError> {
        Ok(self.write_to(Cursor::new(Vec::new()), IN_MEMORY_NAME)?.into_inner())
    }

    /// Writes the trajectory to the file at `path`.
    pub fn write_file(&self, path: impl AsRef<Path>) -> Result<(), TrajectoryError> {
        let path = path.as_ref();
        let mut writer = TrajectoryWriter::create(path, self.header.clone())?;
        for step in &self.steps {
            writer.write_step(step)?;
        }
        writer.finish()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schema::FORMAT_VERSION;

    #[test]
    fn library_string_names_the_format_version() {
        assert!(LIBRARY.ends_with(&format!(" {FORMAT_VERSION}")));
    }
}
