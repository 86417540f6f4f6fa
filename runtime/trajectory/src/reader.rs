//! The streaming reader: finds the header, then yields one checked step per `/lamp/world`
//! message, in file order.
//!
//! It pulls bytes from any [`Read`] through the MCAP crate's sans-IO reader, which hands over
//! chunks whole for [`crate::chunk`] to open, so memory holds one chunk at a time (about
//! [`crate::CHUNK_SIZE`] for our files), never the whole file.
//! Only the records lamp reads (schemas, channels, messages, metadata) are parsed, by
//! [`crate::record`]; others are skipped unparsed.
//! Every checksum the file carries is verified (chunk CRCs before any of the chunk's steps are
//! returned, and the data and summary section CRCs), so damage is reported, not decoded.
//! Messages on other topics are skipped, so a lamp topic may live in a bag with other data.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufReader, Read};
use std::path::Path;

use mcap::records::{Record, op};
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};

use crate::chunk::ChunkRecords;
use crate::codec::{BodyLookup, decode_step};
use crate::error::TrajectoryError;
use crate::model::{Step, Trajectory, TrajectoryHeader};
pub use crate::record::MAXIMUM_RECORD_BYTES;
use crate::record::{error_chain, parse_chunk, parse_used_record};
use crate::schema::{
    MESSAGE_ENCODING, METADATA_NAME, MetadataProblem, SCHEMA_ENCODING, WORLD_STEP_SCHEMA_NAME,
    WORLD_TOPIC, header_from_metadata,
};

/// Pulls parsed MCAP records from a byte source, counting them for error messages.
pub(crate) struct RecordSource<R> {
    source: R,
    linear: LinearReader,
    pub(crate) file: String,
    /// Records returned so far (inside chunks included); the index of the next one.
    pub(crate) records: u64,
    /// The chunk whose records are being returned.
    chunk: Option<ChunkRecords>,
}

impl<R: Read> RecordSource<R> {
    pub(crate) fn new(source: R, file: String) -> Self {
        let options = LinearReaderOptions::default()
            .with_validate_data_section_crc(true)
            .with_validate_summary_section_crc(true)
            .with_record_length_limit(MAXIMUM_RECORD_BYTES)
            // Chunks come whole and `ChunkRecords` opens them (see the `chunk` module for why).
            .with_emit_chunks(true);
        let linear = LinearReader::new_with_options(options);
        Self { source, linear, file, records: 0, chunk: None }
    }

    /// The next record, `None` at the clean end of the file. `steps` is only for error messages.
    pub(crate) fn next_record(
        &mut self,
        steps: u64,
    ) -> Result<Option<Record<'static>>, TrajectoryError> {
        loop {
            if let Some(chunk) = &mut self.chunk {
                match chunk.next_record() {
                    Some(Ok(record)) => {
                        self.records += 1;
                        return Ok(Some(record));
                    }
                    Some(Err(reason)) => return Err(self.corrupt(steps, reason)),
                    None => self.chunk = None,
                }
            }
            match self.next_file_record(steps)? {
                None => return Ok(None),
                Some(FileRecord::Record(record)) => {
                    self.records += 1;
                    return Ok(Some(record));
                }
                Some(FileRecord::Chunk(chunk)) => self.chunk = Some(chunk),
            }
        }
    }

    fn corrupt(&self, steps: u64, reason: String) -> TrajectoryError {
        TrajectoryError::Corrupt { file: self.file.clone(), record: self.records, steps, reason }
    }

    /// The next record outside chunks, with a chunk opened; `None` at the clean end of the file.
    fn next_file_record(&mut self, steps: u64) -> Result<Option<FileRecord>, TrajectoryError> {
        while let Some(event) = self.linear.next_event() {
            match event {
                Ok(LinearReadEvent::ReadRequest(need)) => {
                    let buffer = self.linear.insert(need);
                    let read = loop {
                        match self.source.read(buffer) {
                            Ok(read) => break read,
                            Err(error) if error.kind() == io::ErrorKind::Interrupted => {}
                            Err(error) if error.kind() == io::ErrorKind::UnexpectedEof => {
                                break 0;
                            }
                            Err(source) => {
                                return Err(TrajectoryError::Io {
                                    file: self.file.clone(),
                                    action: "read",
                                    source,
                                });
                            }
                        }
                    };
                    self.linear.notify_read(read);
                }
                Ok(LinearReadEvent::Record { data, opcode }) => {
                    let record = if opcode == op::CHUNK {
                        match parse_chunk(data) {
                            Ok(Record::Chunk { header, data }) => {
                                ChunkRecords::open(&header, &data).map(FileRecord::Chunk)
                            }
                            Ok(_) => Err("a chunk record does not parse as a chunk".to_string()),
                            Err(reason) => Err(reason),
                        }
                    } else {
                        parse_used_record(opcode, data).map(FileRecord::Record)
                    };
                    let file = &self.file;
                    let records = self.records;
                    return record.map(Some).map_err(|reason| TrajectoryError::Corrupt {
                        file: file.clone(),
                        record: records,
                        steps,
                        reason,
                    });
                }
                Err(mcap::McapError::UnexpectedEof) => {
                    return Err(TrajectoryError::Truncated {
                        file: self.file.clone(),
                        record: self.records,
                        steps,
                    });
                }
                Err(error) => {
                    return Err(TrajectoryError::Corrupt {
                        file: self.file.clone(),
                        record: self.records,
                        steps,
                        reason: error_chain(&error),
                    });
                }
            }
        }
        Ok(None)
    }
}

/// A record outside chunks: a record, or a chunk ready to return its records.
enum FileRecord {
    Record(Record<'static>),
    Chunk(ChunkRecords),
}

/// Reads a trajectory file step by step; an iterator of checked steps.
///
/// After the first error the iterator ends.
pub struct TrajectoryReader<R> {
    records: RecordSource<R>,
    header: TrajectoryHeader,
    lookup: BodyLookup,
    /// Schema id → (name, encoding), for checking the world channel.
    schemas: BTreeMap<u16, (String, String)>,
    /// Channel id → whether it is the world topic.
    channels: BTreeMap<u16, bool>,
    steps: u64,
    previous_time: Option<u64>,
    done: bool,
}

impl TrajectoryReader<BufReader<File>> {
    /// Opens the file at `path` and reads its header.
    pub fn open(path: impl AsRef<Path>) -> Result<Self, TrajectoryError> {
        let path = path.as_ref();
        let file = File::open(path).map_err(|source| TrajectoryError::Io {
            file: path.display().to_string(),
            action: "open",
            source,
        })?;
        Self::new(BufReader::new(file), path.display().to_string())
    }
}

impl<'a> TrajectoryReader<&'a [u8]> {
    /// Reads a trajectory held in memory; `name` identifies it in errors.
    pub fn from_bytes(bytes: &'a [u8], name: impl Into<String>) -> Result<Self, TrajectoryError> {
        Self::new(bytes, name)
    }
}

/// What to do with a record once the header is known.
enum Outcome {
    Step(Step),
    Continue,
    End,
}

impl<R: Read> TrajectoryReader<R> {
    /// Starts reading from `source`; `name` identifies it in errors. Reads up to and including
    /// the `lamp` metadata record, which must precede the first step.
    pub fn new(source: R, name: impl Into<String>) -> Result<Self, TrajectoryError> {
        let mut records = RecordSource::new(source, name.into());
        let mut schemas = BTreeMap::new();
        let mut channels = BTreeMap::new();
        let header = loop {
            let Some(record) = records.next_record(0)? else {
                return Err(schema_error(
                    &records.file,
                    format!("it has no `{METADATA_NAME}` metadata record"),
                ));
            };
            match record {
                Record::Metadata(metadata) if metadata.name == METADATA_NAME => {
                    break header_from_metadata(&metadata.metadata).map_err(
                        |problem| match problem {
                            MetadataProblem::Schema(reason) => schema_error(&records.file, reason),
                            MetadataProblem::Header(reason) => {
                                TrajectoryError::Header { file: records.file.clone(), reason }
                            }
                        },
                    )?;
                }
                other => {
                    if note_definitions(&records.file, &other, &mut schemas, &mut channels)?
                        == Some(true)
                    {
                        return Err(schema_error(
                            &records.file,
                            format!(
                                "a `{WORLD_TOPIC}` message comes before the `{METADATA_NAME}` metadata record; write the metadata first"
                            ),
                        ));
                    }
                }
            }
        };
        let lookup = BodyLookup::new(&header);
        Ok(Self {
            records,
            header,
            lookup,
            schemas,
            channels,
            steps: 0,
            previous_time: None,
            done: false,
        })
    }

    /// The file's header.
    pub fn header(&self) -> &TrajectoryHeader {
        &self.header
    }

    /// How many steps have been returned so far.
    pub fn steps_read(&self) -> u64 {
        self.steps
    }

    /// Reads every remaining step.
    pub fn read_all(self) -> Result<Trajectory, TrajectoryError> {
        let header = self.header.clone();
        let steps = self.collect::<Result<Vec<_>, _>>()?;
        Ok(Trajectory { header, steps })
    }

    fn next_outcome(&mut self) -> Result<Outcome, TrajectoryError> {
        let record_index = self.records.records;
        let Some(record) = self.records.next_record(self.steps)? else {
            return Ok(Outcome::End);
        };
        let file = &self.records.file;
        match record {
            Record::Metadata(metadata) if metadata.name == METADATA_NAME => Err(schema_error(
                file,
                format!("it has a second `{METADATA_NAME}` metadata record"),
            )),
            Record::Message { header, data } => {
                let is_world = self.channels.get(&header.channel_id).copied().ok_or_else(|| {
                    TrajectoryError::Corrupt {
                        file: file.clone(),
                        record: record_index,
                        steps: self.steps,
                        reason: format!("a message uses undeclared channel {}", header.channel_id),
                    }
                })?;
                if !is_world {
                    return Ok(Outcome::Continue);
                }
                let step = decode_step(&self.header, &self.lookup, &data, self.previous_time)
                    .map_err(|problem| {
                        TrajectoryError::from_step(file, self.steps, record_index, problem)
                    })?;
                self.steps += 1;
                self.previous_time = Some(step.time_nanoseconds);
                Ok(Outcome::Step(step))
            }
            other => {
                note_definitions(file, &other, &mut self.schemas, &mut self.channels)?;
                Ok(Outcome::Continue)
            }
        }
    }
}

impl<R: Read> Iterator for TrajectoryReader<R> {
    type Item = Result<Step, TrajectoryError>;

    fn next(&mut self) -> Option<Self::Item> {
        while !self.done {
            match self.next_outcome() {
                Ok(Outcome::Step(step)) => return Some(Ok(step)),
                Ok(Outcome::Continue) => {}
                Ok(Outcome::End) => self.done = true,
                Err(error) => {
                    self.done = true;
                    return Some(Err(error));
                }
            }
        }
        None
    }
}

fn schema_error(file: &str, reason: String) -> TrajectoryError {
    TrajectoryError::Schema { file: file.to_string(), reason }
}

/// Records schema and channel definitions, checking the world channel's schema and encodings.
/// For a message, returns whether it is on the world channel (`None` for other records).
fn note_definitions(
    file: &str,
    record: &Record<'_>,
    schemas: &mut BTreeMap<u16, (String, String)>,
    channels: &mut BTreeMap<u16, bool>,
) -> Result<Option<bool>, TrajectoryError> {
    match record {
        Record::Schema { header, .. } => {
            schemas.insert(header.id, (header.name.clone(), header.encoding.clone()));
            Ok(None)
        }
        Record::Channel(channel) => {
            let is_world = channel.topic == WORLD_TOPIC;
            if is_world {
                let schema = schemas.get(&channel.schema_id);
                let expected = (WORLD_STEP_SCHEMA_NAME, SCHEMA_ENCODING);
                if schema.map(|(name, encoding)| (name.as_str(), encoding.as_str()))
                    != Some(expected)
                {
                    return Err(schema_error(
                        file,
                        format!(
                            "topic `{WORLD_TOPIC}` has schema {schema:?}, expected `{WORLD_STEP_SCHEMA_NAME}` in `{SCHEMA_ENCODING}`"
                        ),
                    ));
                }
                if channel.message_encoding != MESSAGE_ENCODING {
                    return Err(schema_error(
                        file,
                        format!(
                            "topic `{WORLD_TOPIC}` has message encoding `{}`, expected `{MESSAGE_ENCODING}`",
                            channel.message_encoding
                        ),
                    ));
                }
            }
            channels.insert(channel.id, is_world);
            Ok(None)
        }
        Record::Message { header, .. } => Ok(channels.get(&header.channel_id).copied()),
        _ => Ok(None),
    }
}

impl Trajectory {
    /// Reads the whole file at `path`.
    pub fn read_file(path: impl AsRef<Path>) -> Result<Self, TrajectoryError> {
        TrajectoryReader::open(path)?.read_all()
    }

    /// Reads a whole trajectory from bytes in memory; `name` identifies it in errors.
    pub fn from_bytes(bytes: &[u8], name: impl Into<String>) -> Result<Self, TrajectoryError> {
        TrajectoryReader::from_bytes(bytes, name)?.read_all()
    }
}
