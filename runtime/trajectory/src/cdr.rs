//! A small little-endian CDR (OMG XCDR1, "plain CDR") encoder and decoder, the serialisation
//! ROS 2 uses on the wire and in bags.
//!
//! The rules implemented here, which `docs/formats.md` repeats for people writing files:
//! - a message starts with a 4-byte encapsulation header `00 01 00 00` (CDR, little endian,
//!   options zero); alignment is counted from the byte after it;
//! - a primitive of size n (1, 2, 4 or 8 bytes) starts at an offset that is a multiple of n,
//!   zero bytes pad the gap (so `float64` is 8-aligned, as in XCDR1);
//! - a sequence is a `uint32` element count followed by the elements, each aligned as its type;
//!   an empty sequence adds no padding;
//! - a string is a `uint32` byte count that includes a terminating NUL, the UTF-8 bytes, then
//!   the NUL; an empty string is count 1 and a NUL (count 0 is accepted when reading).
//!
//! The decoder never panics and never allocates more than the input can hold: every count is
//! checked against the bytes that remain before anything is reserved.

use std::fmt;

/// The encapsulation header of a little-endian plain-CDR message.
pub const ENCAPSULATION_CDR_LE: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// Length of the encapsulation header; alignment offsets start after it.
const ENCAPSULATION_LENGTH: usize = 4;

/// Writers (Fast DDS among them) may pad a message to a multiple of 4 bytes; a reader must
/// accept up to this many trailing bytes.
pub const MAXIMUM_TRAILING_PADDING: usize = 3;

/// Appends CDR values to a byte buffer.
pub struct CdrWriter {
    bytes: Vec<u8>,
}

impl CdrWriter {
    /// Starts a message, writing the encapsulation header into a buffer of roughly this size.
    pub fn new(capacity: usize) -> Self {
        let mut bytes = Vec::with_capacity(capacity + ENCAPSULATION_LENGTH);
        bytes.extend_from_slice(&ENCAPSULATION_CDR_LE);
        Self { bytes }
    }

    /// Starts a message in `bytes`, which is cleared first: a writer that encodes many messages
    /// hands the same buffer back each time instead of allocating one per message.
    pub fn reusing(mut bytes: Vec<u8>) -> Self {
        bytes.clear();
        bytes.extend_from_slice(&ENCAPSULATION_CDR_LE);
        Self { bytes }
    }

    /// The finished message, encapsulation header included.
    pub fn into_bytes(self) -> Vec<u8> {
        self.bytes
    }

    fn align(&mut self, size: usize) {
        let offset = self.bytes.len() - ENCAPSULATION_LENGTH;
        let padding = (size - offset % size) % size;
        self.bytes.resize(self.bytes.len() + padding, 0);
    }

    pub fn write_i32(&mut self, value: i32) {
        self.align(4);
        self.bytes.extend_from_slice(&value.to_le_bytes());
    }

    pub fn write_u32(&mut self, value: u32) {
        self.align(4);
        self.bytes.extend_from_slice(&value.to_le_bytes());
    }

    /// One `float64`; the encoders write runs with [`Self::write_f64s`].
    #[cfg(test)]
    pub fn write_f64(&mut self, value: f64) {
        self.align(8);
        self.bytes.extend_from_slice(&value.to_le_bytes());
    }

    /// Writes consecutive `float64` values: aligned once, since each keeps the next aligned;
    /// none adds no padding (an empty sequence's elements).
    pub fn write_f64s(&mut self, values: impl IntoIterator<Item = f64>) {
        let mut values = values.into_iter().peekable();
        if values.peek().is_some() {
            self.align(8);
        }
        for value in values {
            self.bytes.extend_from_slice(&value.to_le_bytes());
        }
    }

    /// Writes a sequence length; the caller has checked that it fits in a `uint32`.
    pub fn write_length(&mut self, length: u32) {
        self.write_u32(length);
    }

    /// Writes a string; the caller has checked that its length fits in a `uint32`.
    pub fn write_string(&mut self, value: &str) {
        let length = u32::try_from(value.len() + 1)
            .expect("callers reject strings longer than u32::MAX - 1 bytes");
        self.write_u32(length);
        self.bytes.extend_from_slice(value.as_bytes());
        self.bytes.push(0);
    }
}

/// Why a CDR message could not be decoded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CdrError {
    /// Byte offset in the message (encapsulation header included) where decoding failed.
    pub offset: usize,
    /// What was wrong there.
    pub reason: CdrErrorKind,
}

/// The kinds of CDR decoding failure.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CdrErrorKind {
    /// The message is shorter than the encapsulation header.
    MissingEncapsulation,
    /// The encapsulation is not little-endian plain CDR.
    UnsupportedEncapsulation([u8; 2]),
    /// A value runs past the end of the message.
    UnexpectedEnd,
    /// A sequence or string length exceeds the bytes that remain.
    LengthTooLarge(u32),
    /// A string is not NUL-terminated or not UTF-8.
    InvalidString,
    /// Bytes remain after the last field.
    TrailingBytes(usize),
}

impl fmt::Display for CdrError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.reason {
            CdrErrorKind::MissingEncapsulation => {
                write!(f, "message of {} bytes has no CDR encapsulation header", self.offset)
            }
            CdrErrorKind::UnsupportedEncapsulation(kind) => write!(
                f,
                "encapsulation {:02x} {:02x} is not little-endian plain CDR (00 01)",
                kind[0], kind[1]
            ),
            CdrErrorKind::UnexpectedEnd => {
                write!(f, "message ends inside a value at byte {}", self.offset)
            }
            CdrErrorKind::LengthTooLarge(length) => {
                write!(f, "length {length} at byte {} exceeds the message", self.offset)
            }
            CdrErrorKind::InvalidString => {
                write!(f, "string at byte {} is not NUL-terminated UTF-8", self.offset)
            }
            CdrErrorKind::TrailingBytes(count) => {
                write!(f, "{count} unexpected bytes after the last field at byte {}", self.offset)
            }
        }
    }
}

/// Reads CDR values from a message, checking bounds on every read.
pub struct CdrReader<'a> {
    bytes: &'a [u8],
    position: usize,
}

impl<'a> CdrReader<'a> {
    /// Checks the encapsulation header and positions the reader after it.
    pub fn new(bytes: &'a [u8]) -> Result<Self, CdrError> {
        let Some(header) = bytes.get(..ENCAPSULATION_LENGTH) else {
            return Err(CdrError {
                offset: bytes.len(),
                reason: CdrErrorKind::MissingEncapsulation,
            });
        };
        if header[..2] != ENCAPSULATION_CDR_LE[..2] {
            return Err(CdrError {
                offset: 0,
                reason: CdrErrorKind::UnsupportedEncapsulation([header[0], header[1]]),
            });
        }
        Ok(Self { bytes, position: ENCAPSULATION_LENGTH })
    }

    fn error(&self, reason: CdrErrorKind) -> CdrError {
        CdrError { offset: self.position, reason }
    }

    fn align(&mut self, size: usize) -> Result<(), CdrError> {
        let offset = self.position - ENCAPSULATION_LENGTH;
        let padding = (size - offset % size) % size;
        if self.position + padding > self.bytes.len() {
            return Err(self.error(CdrErrorKind::UnexpectedEnd));
        }
        self.position += padding;
        Ok(())
    }

    fn take<const N: usize>(&mut self) -> Result<[u8; N], CdrError> {
        self.align(N)?;
        let slice = self
            .bytes
            .get(self.position..self.position + N)
            .ok_or_else(|| self.error(CdrErrorKind::UnexpectedEnd))?;
        let mut array = [0; N];
        array.copy_from_slice(slice);
        self.position += N;
        Ok(array)
    }

    pub fn read_i32(&mut self) -> Result<i32, CdrError> {
        self.take::<4>().map(i32::from_le_bytes)
    }

    pub fn read_u32(&mut self) -> Result<u32, CdrError> {
        self.take::<4>().map(u32::from_le_bytes)
    }

    pub fn read_f64(&mut self) -> Result<f64, CdrError> {
        self.take::<8>().map(f64::from_le_bytes)
    }

    /// Reads a sequence length and checks that `length` elements of at least
    /// `minimum_element_size` bytes each fit in what remains, so callers may reserve it.
    pub fn read_length(&mut self, minimum_element_size: usize) -> Result<usize, CdrError> {
        let start = self.position;
        let length = self.read_u32()?;
        let remaining = self.bytes.len() - self.position;
        let needed = (length as usize).checked_mul(minimum_element_size);
        if needed.is_none_or(|needed| needed > remaining) {
            return Err(CdrError { offset: start, reason: CdrErrorKind::LengthTooLarge(length) });
        }
        Ok(length as usize)
    }

    pub fn read_string(&mut self) -> Result<&'a str, CdrError> {
        let start = self.position;
        let length = self.read_length(1)?;
        let bytes = &self.bytes[self.position..self.position + length];
        self.position += length;
        let text = match bytes.split_last() {
            None => &[][..],
            Some((0, text)) => text,
            Some(_) => return Err(CdrError { offset: start, reason: CdrErrorKind::InvalidString }),
        };
        std::str::from_utf8(text)
            .map_err(|_| CdrError { offset: start, reason: CdrErrorKind::InvalidString })
    }

    /// Checks that nothing but permitted padding follows the last field.
    pub fn finish(self) -> Result<(), CdrError> {
        let remaining = self.bytes.len() - self.position;
        if remaining > MAXIMUM_TRAILING_PADDING {
            return Err(self.error(CdrErrorKind::TrailingBytes(remaining)));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Known answer: `int32 -2; float64 1.5; string "ab"; float64[] {}; uint32 7` laid out by hand
    /// from the XCDR1 rules (alignment counted after the 4-byte header).
    #[test]
    fn layout_matches_the_rules_byte_for_byte() {
        let mut writer = CdrWriter::new(0);
        writer.write_i32(-2);
        writer.write_f64(1.5);
        writer.write_string("ab");
        writer.write_length(0);
        writer.write_u32(7);
        let expected: Vec<u8> = [
            &[0x00, 0x01, 0x00, 0x00][..],   // encapsulation
            &[0xfe, 0xff, 0xff, 0xff],       // offset 0: int32 -2
            &[0, 0, 0, 0],                   // pad to 8
            &[0, 0, 0, 0, 0, 0, 0xf8, 0x3f], // offset 8: 1.5
            &[3, 0, 0, 0, b'a', b'b', 0],    // offset 16: "ab" + NUL
            &[0],                            // pad to 24
            &[0, 0, 0, 0],                   // offset 24: empty sequence
            &[7, 0, 0, 0],                   // offset 28: no padding after it
        ]
        .concat();
        assert_eq!(writer.into_bytes(), expected);
    }

    #[test]
    fn a_run_of_float64_is_aligned_once_and_an_empty_run_not_at_all() {
        let (mut one_by_one, mut run) = (CdrWriter::new(0), CdrWriter::new(0));
        for writer in [&mut one_by_one, &mut run] {
            writer.write_u32(2);
        }
        one_by_one.write_f64(1.0);
        one_by_one.write_f64(-2.5);
        run.write_f64s([1.0, -2.5]);
        assert_eq!(one_by_one.into_bytes(), run.into_bytes());
        let mut empty = CdrWriter::new(0);
        empty.write_u32(0);
        empty.write_f64s([]);
        empty.write_u32(7);
        assert_eq!(empty.into_bytes(), [0, 1, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0]);
    }

    #[test]
    fn values_round_trip() {
        let mut writer = CdrWriter::new(0);
        writer.write_u32(1);
        writer.write_f64(f64::MIN_POSITIVE);
        writer.write_string("");
        writer.write_f64(-0.0);
        let bytes = writer.into_bytes();
        let mut reader = CdrReader::new(&bytes).unwrap();
        assert_eq!(reader.read_u32().unwrap(), 1);
        assert_eq!(reader.read_f64().unwrap().to_bits(), f64::MIN_POSITIVE.to_bits());
        assert_eq!(reader.read_string().unwrap(), "");
        assert_eq!(reader.read_f64().unwrap().to_bits(), (-0.0f64).to_bits());
        reader.finish().unwrap();
    }

    #[test]
    fn an_empty_string_may_be_written_with_length_zero() {
        let bytes = [0, 1, 0, 0, 0, 0, 0, 0];
        let mut reader = CdrReader::new(&bytes).unwrap();
        assert_eq!(reader.read_string().unwrap(), "");
    }

    #[test]
    fn bad_input_is_an_error_with_its_offset() {
        assert_eq!(
            CdrReader::new(&[0, 1]).err().unwrap().reason,
            CdrErrorKind::MissingEncapsulation
        );
        assert_eq!(
            CdrReader::new(&[0, 0, 0, 0]).err().unwrap().reason,
            CdrErrorKind::UnsupportedEncapsulation([0, 0])
        );
        let short = [0, 1, 0, 0, 1, 2];
        let error = CdrReader::new(&short).unwrap().read_u32().unwrap_err();
        assert_eq!(error, CdrError { offset: 4, reason: CdrErrorKind::UnexpectedEnd });

        let huge = [0, 1, 0, 0, 0xff, 0xff, 0xff, 0xff, 0];
        let error = CdrReader::new(&huge).unwrap().read_length(8).unwrap_err();
        assert_eq!(error.reason, CdrErrorKind::LengthTooLarge(u32::MAX));

        let unterminated = [0, 1, 0, 0, 2, 0, 0, 0, b'a', b'b'];
        let error = CdrReader::new(&unterminated).unwrap().read_string().unwrap_err();
        assert_eq!(error.reason, CdrErrorKind::InvalidString);

        let trailing = [0, 1, 0, 0, 1, 2, 3, 4];
        assert_eq!(
            CdrReader::new(&trailing).unwrap().finish().unwrap_err().reason,
            CdrErrorKind::TrailingBytes(4)
        );
        let padded = [0, 1, 0, 0, 0, 0, 0];
        CdrReader::new(&padded).unwrap().finish().unwrap();
    }
}
