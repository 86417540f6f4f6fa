//! Stable digests: of a demonstration set, written into every artifact's provenance so that an
//! artifact can be traced to the exact files it was learned from, and of one file's bytes, written
//! into the build's manifest.
//!
//! FNV-1a (64 bit): for a demonstration set over, per file in name order, the name, a NUL, the
//! byte length (little-endian u64) and the bytes; for one file over its bytes alone. It is not
//! cryptographic: it detects changed inputs and accidental edits, it does not resist forgery.

use std::fmt;

use crate::input::DemoFile;

const OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;
const PRIME: u64 = 0x0000_0100_0000_01b3;

/// The digest of a set of demonstration files.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Digest(pub u64);

impl fmt::Display for Digest {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "fnv1a64:{:016x}", self.0)
    }
}

struct Fnv(u64);

impl Fnv {
    fn update(&mut self, bytes: &[u8]) {
        for byte in bytes {
            self.0 ^= u64::from(*byte);
            self.0 = self.0.wrapping_mul(PRIME);
        }
    }
}

/// The digest of one file's bytes.
pub fn file_digest(bytes: &[u8]) -> Digest {
    let mut hash = Fnv(OFFSET_BASIS);
    hash.update(bytes);
    Digest(hash.0)
}

/// The digest of `files`, independent of the order they are given in.
pub fn demonstration_digest(files: &[DemoFile]) -> Digest {
    let mut sorted: Vec<&DemoFile> = files.iter().collect();
    sorted.sort_by(|a, b| a.name.cmp(&b.name));
    let mut hash = Fnv(OFFSET_BASIS);
    for file in sorted {
        hash.update(file.name.as_bytes());
        hash.update(&[0]);
        hash.update(&(file.bytes.len() as u64).to_le_bytes());
        hash.update(&file.bytes);
    }
    Digest(hash.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(name: &str, bytes: &[u8]) -> DemoFile {
        DemoFile { name: name.into(), bytes: bytes.to_vec() }
    }

    #[test]
    fn matches_the_published_fnv1a_vectors() {
        let mut empty = Fnv(OFFSET_BASIS);
        empty.update(b"");
        assert_eq!(empty.0, 0xcbf2_9ce4_8422_2325);
        let mut a = Fnv(OFFSET_BASIS);
        a.update(b"a");
        assert_eq!(a.0, 0xaf63_dc4c_8601_ec8c);
        assert_eq!(file_digest(b"a"), Digest(0xaf63_dc4c_8601_ec8c));
        assert_eq!(file_digest(b"foobar").to_string(), "fnv1a64:85944171f73967e8");
    }

    #[test]
    fn order_free_but_sensitive_to_names_and_bytes() {
        let one = demonstration_digest(&[file("a", b"xy"), file("b", b"z")]);
        assert_eq!(one, demonstration_digest(&[file("b", b"z"), file("a", b"xy")]));
        assert_ne!(one, demonstration_digest(&[file("a", b"xy"), file("c", b"z")]));
        assert_ne!(one, demonstration_digest(&[file("a", b"x"), file("b", b"yz")]));
        assert!(one.to_string().starts_with("fnv1a64:"));
        assert_eq!(one.to_string().len(), "fnv1a64:".len() + 16);
    }
}
