//! An ordered pair of types, the unit relations are learned for.

use std::fmt;

/// An ordered pair of types: relative poses are of the secondary in the primary's frame.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TypePair {
    /// The type whose frame is used.
    pub primary: String,
    /// The type whose pose is expressed in the primary's frame.
    pub secondary: String,
}

impl TypePair {
    /// A pair from its two type names.
    pub fn new(primary: impl Into<String>, secondary: impl Into<String>) -> Self {
        TypePair { primary: primary.into(), secondary: secondary.into() }
    }

    /// The prefix of the pair's relation names, `<primary>_<secondary>`.
    pub fn stem(&self) -> String {
        format!("{}_{}", self.primary, self.secondary)
    }
}

impl fmt::Display for TypePair {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}, {})", self.primary, self.secondary)
    }
}
