//! The lifted vocabulary of induced actions: atoms over parameters, and typed parameters.

/// An atom over action parameters.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LiftedAtom {
    /// The predicate name.
    pub predicate: String,
    /// Parameter names, each starting with `?`.
    pub arguments: Vec<String>,
}

impl std::fmt::Display for LiftedAtom {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "({}", self.predicate)?;
        for argument in &self.arguments {
            write!(f, " {argument}")?;
        }
        write!(f, ")")
    }
}

/// A typed action parameter.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Parameter {
    /// The name, starting with `?`.
    pub name: String,
    /// The type name.
    pub type_name: String,
}
