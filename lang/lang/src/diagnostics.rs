//! Every problem the front end can report, with its stable code, wording and help.
//!
//! Diagnostics are data: they hold spans, never source text. The binary attaches the source
//! file when it renders them (`Diagnostic::with_source`).

use miette::SourceSpan;

use crate::source::{FileId, Span};

/// A problem found in a spec, located in one file.
#[derive(Debug)]
pub struct Diagnostic {
    pub file: FileId,
    /// Boxed: diagnostics travel in `Result`s and lists, and are rare.
    pub error: Box<SpecError>,
}

impl Diagnostic {
    /// The stable code, e.g. `lamp::resolve::unknown_type`.
    pub fn code(&self) -> String {
        miette::Diagnostic::code(self.error.as_ref())
            .map(|code| code.to_string())
            .unwrap_or_default()
    }

    /// The primary span's byte range.
    pub fn range(&self) -> std::ops::Range<usize> {
        let span = self.error.primary_span();
        span.offset()..span.offset() + span.len()
    }
}

/// What is wrong, with wording and help. Titles are lower case without a final period.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum SpecError {
    #[error("syntax error: expected {expected}")]
    #[diagnostic(code(lamp::parse::syntax))]
    Syntax {
        expected: String,
        #[label("unexpected here")]
        at: SourceSpan,
    },

    #[error("{kind} `{name}` is declared twice")]
    #[diagnostic(code(lamp::resolve::duplicate_name), help("Give each {kind} its own name."))]
    DuplicateName {
        kind: &'static str,
        name: String,
        #[label("declared again here")]
        at: SourceSpan,
        #[label("first declared here")]
        first: Option<SourceSpan>,
    },

    #[error("unknown type `{name}`")]
    #[diagnostic(code(lamp::resolve::unknown_type))]
    UnknownType {
        name: String,
        #[label("not a declared type")]
        at: SourceSpan,
        #[help]
        help: Option<String>,
    },

    #[error("unknown robot `{name}`")]
    #[diagnostic(code(lamp::resolve::unknown_robot))]
    UnknownRobot {
        name: String,
        #[label("not a declared robot")]
        at: SourceSpan,
        #[help]
        help: Option<String>,
    },

    #[error("unknown object `{name}`")]
    #[diagnostic(code(lamp::resolve::unknown_object))]
    UnknownObject {
        name: String,
        #[label("not in this problem's scene")]
        at: SourceSpan,
        #[help]
        help: Option<String>,
    },

    #[error("`{name}` is a robot, not an object of the scene")]
    #[diagnostic(code(lamp::resolve::robot_as_object))]
    RobotAsObject {
        name: String,
        #[label("a robot")]
        at: SourceSpan,
        #[help]
        help: String,
    },

    #[error("unknown structure `{name}`")]
    #[diagnostic(code(lamp::resolve::unknown_structure))]
    UnknownStructure {
        name: String,
        #[label("not a declared structure")]
        at: SourceSpan,
        #[help]
        help: Option<String>,
    },

    #[error("robot `{robot}` has no configuration `{name}`")]
    #[diagnostic(code(lamp::resolve::unknown_configuration))]
    UnknownConfiguration {
        robot: String,
        name: String,
        #[label("not declared with `config` in the robot")]
        at: SourceSpan,
        #[help]
        help: Option<String>,
    },

    #[error("unknown {what} `{word}`")]
    #[diagnostic(code(lamp::check::unknown_word))]
    UnknownWord {
        what: &'static str,
        word: String,
        #[label("expected one of: {expected}")]
        at: SourceSpan,
        expected: String,
        #[help]
        help: Option<String>,
    },

    #[error("{what} is missing")]
    #[diagnostic(code(lamp::check::missing_declaration))]
    MissingDeclaration {
        what: String,
        #[label("in this declaration")]
        at: SourceSpan,
        #[help]
        help: String,
    },

    #[error("{what} is given twice")]
    #[diagnostic(code(lamp::check::duplicate_setting), help("Keep one of them."))]
    DuplicateSetting {
        what: String,
        #[label("given again here")]
        at: SourceSpan,
        #[label("first given here")]
        first: SourceSpan,
    },

    #[error("{what} is out of range")]
    #[diagnostic(code(lamp::check::out_of_range), help("The value must be {expected}."))]
    OutOfRange {
        what: String,
        expected: String,
        #[label("this value")]
        at: SourceSpan,
    },

    #[error("{kind} name is {length} bytes long, more than the {max} allowed")]
    #[diagnostic(
        code(lamp::check::name_too_long),
        help(
            "A {kind}'s name names its files and folders, and a file name holds at most 255 bytes: shorten the name to at most {max} bytes."
        )
    )]
    NameTooLong {
        kind: &'static str,
        length: usize,
        max: usize,
        #[label("this name")]
        at: SourceSpan,
    },

    #[error("{dimension} needs a unit")]
    #[diagnostic(
        code(lamp::check::unit_required),
        help("Write the unit after the number, for example `{example}`.")
    )]
    UnitRequired {
        dimension: &'static str,
        example: &'static str,
        #[label("a bare number")]
        at: SourceSpan,
    },

    #[error("`{unit}` is not a unit of {dimension}")]
    #[diagnostic(code(lamp::check::wrong_unit), help("Use one of: {allowed}."))]
    WrongUnit {
        unit: String,
        dimension: &'static str,
        allowed: &'static str,
        #[label("wrong kind of unit")]
        at: SourceSpan,
    },

    #[error("{what} takes no unit")]
    #[diagnostic(
        code(lamp::check::unexpected_unit),
        help("{what} is a plain number; remove the unit.")
    )]
    UnexpectedUnit {
        what: String,
        #[label("remove this unit")]
        at: SourceSpan,
    },

    #[error("{what} must be a whole number")]
    #[diagnostic(code(lamp::check::not_integer), help("Write it without a fractional part."))]
    NotInteger {
        what: String,
        #[label("not a whole number")]
        at: SourceSpan,
    },

    #[error("file `{path}` does not exist")]
    #[diagnostic(code(lamp::check::missing_file))]
    MissingFile {
        path: String,
        #[label("no file at this path")]
        at: SourceSpan,
        #[help]
        help: String,
    },

    #[error("`{path}` is {kind}, not a file")]
    #[diagnostic(code(lamp::check::not_a_file))]
    NotAFile {
        path: String,
        /// What is there instead: "a directory", "a character device", ….
        kind: String,
        #[label("not a regular file")]
        at: SourceSpan,
        #[help]
        help: String,
    },

    #[error("robot file `{path}` does not load: {reason}")]
    #[diagnostic(
        code(lamp::check::robot_file),
        help("Fix the robot file or name another one; `lampc build` needs to load it too.")
    )]
    RobotFile {
        path: String,
        reason: String,
        #[label("this robot file")]
        at: SourceSpan,
    },

    #[error("`{file}` has no link `{name}`")]
    #[diagnostic(code(lamp::resolve::unknown_link))]
    UnknownLink {
        name: String,
        /// The robot file, as the spec names it.
        file: String,
        #[label("not a link of the robot file")]
        at: SourceSpan,
        #[help]
        help: String,
    },

    #[error("`{file}` has no joint `{name}`")]
    #[diagnostic(code(lamp::resolve::unknown_joint))]
    UnknownJoint {
        name: String,
        /// The robot file, as the spec names it.
        file: String,
        #[label("{label}")]
        at: SourceSpan,
        label: &'static str,
        #[help]
        help: String,
    },

    #[error("file `{path}` cannot be read: {reason}")]
    #[diagnostic(code(lamp::check::unreadable_file))]
    UnreadableFile {
        path: String,
        reason: String,
        #[label("referred to here")]
        at: SourceSpan,
    },

    #[error("{message}")]
    #[diagnostic(code(lamp::check::conflict))]
    Conflict {
        message: String,
        #[label("here")]
        at: SourceSpan,
        #[help]
        help: String,
    },

    #[error("unknown relation `{name}`")]
    #[diagnostic(code(lamp::goal::unknown_relation))]
    UnknownRelation {
        name: String,
        #[label("not a learned relation name or an alias")]
        at: SourceSpan,
        #[help]
        help: String,
    },

    #[error("`{relation}` takes {expected} argument(s), not {found}")]
    #[diagnostic(code(lamp::goal::arity), help("{signature}"))]
    Arity {
        relation: String,
        expected: usize,
        found: usize,
        signature: String,
        #[label("{found} argument(s) here")]
        at: SourceSpan,
    },

    #[error("`{argument}` is a {found}, but `{relation}` expects a {expected} here")]
    #[diagnostic(code(lamp::goal::argument_type), help("{signature}"))]
    ArgumentType {
        argument: String,
        relation: String,
        expected: String,
        found: String,
        signature: String,
        #[label("of type `{found}`")]
        at: SourceSpan,
    },

    #[error("`{object}` cannot be moved to a goal pose")]
    #[diagnostic(
        code(lamp::goal::not_movable),
        help("Its type `{type_name}` is {kind}; only movable objects can have `at` goals.")
    )]
    NotMovable {
        object: String,
        type_name: String,
        /// What the type is instead of movable: "static", "a marker".
        kind: &'static str,
        #[label("{label}")]
        at: SourceSpan,
        /// The object as what it is: "a static object", "a marker".
        label: &'static str,
    },

    #[error("structure `{structure}` places `{object}`, {problem}")]
    #[diagnostic(code(lamp::goal::structure_object))]
    StructureObject {
        structure: String,
        object: String,
        /// What is wrong with the scene's object, in words.
        problem: String,
        #[label("this structure goal")]
        at: SourceSpan,
        #[help]
        help: String,
    },
}

impl SpecError {
    /// The span of the main label.
    pub fn primary_span(&self) -> SourceSpan {
        match self {
            SpecError::Syntax { at, .. }
            | SpecError::DuplicateName { at, .. }
            | SpecError::UnknownType { at, .. }
            | SpecError::UnknownRobot { at, .. }
            | SpecError::UnknownObject { at, .. }
            | SpecError::RobotAsObject { at, .. }
            | SpecError::UnknownStructure { at, .. }
            | SpecError::UnknownConfiguration { at, .. }
            | SpecError::UnknownWord { at, .. }
            | SpecError::MissingDeclaration { at, .. }
            | SpecError::DuplicateSetting { at, .. }
            | SpecError::OutOfRange { at, .. }
            | SpecError::NameTooLong { at, .. }
            | SpecError::UnitRequired { at, .. }
            | SpecError::WrongUnit { at, .. }
            | SpecError::UnexpectedUnit { at, .. }
            | SpecError::NotInteger { at, .. }
            | SpecError::MissingFile { at, .. }
            | SpecError::NotAFile { at, .. }
            | SpecError::RobotFile { at, .. }
            | SpecError::UnknownLink { at, .. }
            | SpecError::UnknownJoint { at, .. }
            | SpecError::UnreadableFile { at, .. }
            | SpecError::Conflict { at, .. }
            | SpecError::UnknownRelation { at, .. }
            | SpecError::Arity { at, .. }
            | SpecError::ArgumentType { at, .. }
            | SpecError::NotMovable { at, .. }
            | SpecError::StructureObject { at, .. } => *at,
        }
    }
}

/// Builds a diagnostic located at `span`.
pub(crate) fn at(span: Span, make: impl FnOnce(SourceSpan) -> SpecError) -> Diagnostic {
    Diagnostic { file: span.file, error: Box::new(make(span.source_span())) }
}

/// "Did you mean `x`?" for the closest candidate within a small edit distance.
pub(crate) fn did_you_mean<'a>(
    word: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<String> {
    let length = word.chars().count();
    let limit = (length / 3).max(1);
    candidates
        .into_iter()
        // The distance is at least the difference in length: skip the sure misses unmeasured.
        .filter(|candidate| candidate.chars().count().abs_diff(length) <= limit)
        .map(|candidate| (edit_distance(word, candidate), candidate))
        .filter(|(distance, _)| *distance <= limit)
        .min()
        .map(|(_, candidate)| format!("Did you mean `{candidate}`?"))
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut previous = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitution = previous + usize::from(ca != *cb);
            previous = row[j + 1];
            row[j + 1] = substitution.min(row[j] + 1).min(previous + 1);
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_pick_the_closest_name() {
        assert_eq!(did_you_mean("cann", ["can", "surface"]), Some("Did you mean `can`?".into()));
        assert_eq!(did_you_mean("zzzz", ["can", "surface"]), None);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }
}

/// A diagnostic together with its source file, ready for a miette report handler.
#[derive(Debug)]
pub struct WithSource<'a> {
    diagnostic: &'a Diagnostic,
    /// Borrowed: a report reads only the lines it shows, and copies nothing.
    source: &'a crate::source_file::SourceFile,
}

impl Diagnostic {
    /// Attaches the diagnostic's file from `sources`, so a handler can show the code.
    pub fn with_source<'a>(&'a self, sources: &'a crate::source::SourceMap) -> WithSource<'a> {
        WithSource { diagnostic: self, source: sources.source_file(self.file) }
    }
}

impl std::fmt::Display for WithSource<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.diagnostic.error.fmt(f)
    }
}

impl std::error::Error for WithSource<'_> {}

impl miette::Diagnostic for WithSource<'_> {
    fn code<'b>(&'b self) -> Option<Box<dyn std::fmt::Display + 'b>> {
        self.diagnostic.error.code()
    }

    fn help<'b>(&'b self) -> Option<Box<dyn std::fmt::Display + 'b>> {
        self.diagnostic.error.help()
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = miette::LabeledSpan> + '_>> {
        self.diagnostic.error.labels()
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        Some(self.source)
    }
}
