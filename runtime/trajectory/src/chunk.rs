//! The records inside one MCAP chunk: decompressed, checked against the chunk's CRC, and framed
//! with checked lengths.
//!
//! The MCAP crate's linear reader hands over chunks whole and this module opens them, because its
//! own reading of an uncompressed chunk trusts the lengths of the records inside: a record longer
//! than what is left of the chunk makes it subtract past zero (a panic where overflow is checked,
//! records read from beyond the chunk where it is not).

use mcap::records::{ChunkHeader, Record};

use crate::record::{MAXIMUM_RECORD_BYTES, parse_used_record};

/// Bytes before a record's content: the opcode and the little-endian u64 length.
const RECORD_PREFIX: usize = 1 + 8;

/// The decompressed records of one chunk, read front to back.
pub(crate) struct ChunkRecords {
    bytes: Vec<u8>,
    /// Offset of the next record in `bytes`.
    next: usize,
}

impl ChunkRecords {
    /// Decompresses a chunk's data (zstd or none) and checks its size and CRC.
    pub(crate) fn open(header: &ChunkHeader, data: &[u8]) -> Result<Self, String> {
        let size = usize::try_from(header.uncompressed_size)
            .ok()
            .filter(|size| *size <= MAXIMUM_RECORD_BYTES)
            .ok_or_else(|| {
                format!(
                    "a chunk of {} bytes uncompressed is larger than the limit of {MAXIMUM_RECORD_BYTES} bytes",
                    header.uncompressed_size
                )
            })?;
        let bytes = match header.compression.as_str() {
            "" => data.to_vec(),
            "zstd" => zstd::bulk::decompress(data, size)
                .map_err(|error| format!("a zstd chunk does not decompress: {error}"))?,
            other => {
                return Err(format!(
                    "a chunk is compressed with `{other}`; lamp reads zstd and uncompressed chunks"
                ));
            }
        };
        if bytes.len() != size {
            return Err(format!(
                "a chunk holds {} bytes uncompressed, its header says {size}",
                bytes.len()
            ));
        }
        let calculated = crc32fast::hash(&bytes);
        if header.uncompressed_crc != 0 && header.uncompressed_crc != calculated {
            return Err(format!(
                "chunk CRC mismatch: saved {:#010x}, calculated {calculated:#010x}",
                header.uncompressed_crc
            ));
        }
        Ok(Self { bytes, next: 0 })
    }

    /// The next record, `None` after the last; after an error, `None` too.
    ///
    /// Records lamp does not read are returned as [`Record::Unknown`] without their content, so
    /// that no parser of the MCAP crate sees bytes lamp has no use for.
    pub(crate) fn next_record(&mut self) -> Option<Result<Record<'static>, String>> {
        let rest = &self.bytes[self.next..];
        if rest.is_empty() {
            return None;
        }
        let framed = rest.split_first().and_then(|(&opcode, after)| {
            let (length, after) = after.split_first_chunk::<8>()?;
            let length = u64::from_le_bytes(*length);
            let body = usize::try_from(length).ok().and_then(|length| after.get(..length));
            Some((opcode, length, body))
        });
        let Some((opcode, _, Some(body))) = framed else {
            self.next = self.bytes.len();
            return Some(Err(match framed {
                Some((opcode, length, None)) => format!(
                    "record (opcode {opcode:#04x}) of {length} bytes overruns its chunk, which has {} bytes left",
                    rest.len() - RECORD_PREFIX
                ),
                _ => format!(
                    "a record header is cut off at the end of a chunk ({} bytes)",
                    rest.len()
                ),
            }));
        };
        self.next += RECORD_PREFIX + body.len();
        Some(parse_used_record(opcode, body))
    }
}
