//! Parsing the MCAP records lamp reads, with every length inside them checked first.
//!
//! The MCAP crate's parser reserves memory for a string or a byte field as long as the field's
//! length prefix says (up to 4 GiB) before it finds that the record is shorter, so a damaged
//! prefix in a record of a few bytes could ask for gigabytes. Here every length-prefixed field of
//! a schema, channel, metadata or chunk record must fit in the record before the MCAP crate sees
//! it.

use std::borrow::Cow;

use mcap::records::{Record, op};

/// The largest record or decompressed chunk accepted: a corrupt length field cannot make the
/// reader allocate more. Our chunks are 1 MiB; other MCAP writers use a few MiB.
pub const MAXIMUM_RECORD_BYTES: usize = 64 * 1024 * 1024;

/// Parses the records lamp reads (schemas, channels, messages, metadata); any other is
/// [`Record::Unknown`] with no content. Chunks are opened by the caller, and only at the top level.
pub(crate) fn parse_used_record(opcode: u8, body: &[u8]) -> Result<Record<'static>, String> {
    match opcode {
        op::SCHEMA | op::CHANNEL | op::MESSAGE | op::METADATA => {
            check_field_lengths(opcode, body)?;
            mcap::parse_record(opcode, body)
                .map(Record::into_owned)
                .map_err(|error| error_chain(&error))
        }
        _ => Ok(Record::Unknown { opcode, data: Cow::Borrowed(&[]) }),
    }
}

/// Parses a chunk record, its compression name checked to fit in it first.
pub(crate) fn parse_chunk(body: &[u8]) -> Result<Record<'_>, String> {
    check_field_lengths(op::CHUNK, body)?;
    mcap::parse_record(op::CHUNK, body).map_err(|error| error_chain(&error))
}

/// An error and its sources on one line.
pub(crate) fn error_chain(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        text.push_str(": ");
        text.push_str(&cause.to_string());
        source = cause.source();
    }
    text
}

/// Checks that every length-prefixed field of a record fits in it (field layouts from the MCAP
/// specification; a message has none, its data is the rest of the record).
fn check_field_lengths(opcode: u8, body: &[u8]) -> Result<(), String> {
    let mut fields = Fields { rest: body };
    match opcode {
        op::SCHEMA => {
            fields.skip(2, "id")?;
            fields.prefixed("name")?;
            fields.prefixed("encoding")?;
            fields.prefixed("data")?;
        }
        op::CHANNEL => {
            fields.skip(4, "ids")?;
            fields.prefixed("topic")?;
            fields.prefixed("message encoding")?;
            fields.map()?;
        }
        op::METADATA => {
            fields.prefixed("name")?;
            fields.map()?;
        }
        op::CHUNK => {
            // Message start and end times, uncompressed size and checksum; the records follow
            // the compression name, behind a u64 length the MCAP crate checks against the rest.
            fields.skip(8 + 8 + 8 + 4, "header")?;
            fields.prefixed("compression")?;
        }
        _ => {}
    }
    Ok(())
}

/// The unread part of a record.
struct Fields<'a> {
    rest: &'a [u8],
}

impl<'a> Fields<'a> {
    fn skip(&mut self, count: usize, what: &str) -> Result<(), String> {
        self.rest = self
            .rest
            .get(count..)
            .ok_or_else(|| format!("a record ends inside its {what} field"))?;
        Ok(())
    }

    /// A field of a u32 length and that many bytes.
    fn prefixed(&mut self, what: &str) -> Result<&'a [u8], String> {
        let (length, after) = self
            .rest
            .split_first_chunk::<4>()
            .ok_or_else(|| format!("a record ends inside the length of its {what} field"))?;
        let length = u32::from_le_bytes(*length);
        let field = usize::try_from(length).ok().and_then(|length| after.get(..length));
        let field = field.ok_or_else(|| {
            format!(
                "the {what} field of a record says {length} bytes, {} are left in the record",
                after.len()
            )
        })?;
        self.rest = &after[field.len()..];
        Ok(field)
    }

    /// A string map: a u32 length in bytes, then keys and values as prefixed strings.
    fn map(&mut self) -> Result<(), String> {
        let mut map = Fields { rest: self.prefixed("map")? };
        while !map.rest.is_empty() {
            map.prefixed("map key")?;
            map.prefixed("map value")?;
        }
        Ok(())
    }
}
