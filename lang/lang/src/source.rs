//! Source files, spans and the loader through which the front end reads files.
//!
//! The front end never touches the file system itself: the binary passes a loader over the
//! real disk, tests pass an in-memory one.

use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

use crate::source_file::SourceFile;

/// Index of a file in a [`SourceMap`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FileId(pub u32);

/// A byte range in one file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Span {
    pub file: FileId,
    pub start: usize,
    pub end: usize,
}

impl Span {
    /// The span as miette wants it (the file is attached at render time).
    pub fn source_span(self) -> miette::SourceSpan {
        (self.start, self.end - self.start).into()
    }
}

/// What is at a path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A regular file (or a link to one).
    File,
    /// Nothing.
    Missing,
    /// Something a spec cannot name as a file, described for a message: "a directory",
    /// "a character device", ….
    NotAFile(String),
    /// The path cannot be examined; the reason, e.g. "permission denied".
    Inaccessible(String),
}

/// Reads the files a spec refers to.
pub trait Loader {
    /// The text of a file, or a message saying why it cannot be read.
    fn read_to_string(&self, path: &Path) -> Result<String, String>;
    /// What is at `path`: a file, nothing, or something else.
    fn file_kind(&self, path: &Path) -> FileKind;
    /// Paths of existing files matching a glob pattern (for demonstration sources).
    fn glob(&self, pattern: &Path) -> Vec<PathBuf>;
    /// The names the robot file at `path` defines, loaded as a robot of `kind` (whose mount adds
    /// coordinates); `Ok(None)` when this loader does not read robot files, and then the names a
    /// spec uses are not checked. An error is the loader's reason the file does not load.
    fn robot_names(
        &self,
        path: &Path,
        kind: lamp_spec::RobotKind,
    ) -> Result<Option<lamp_spec::RobotNames>, String>;
}

/// An in-memory loader for tests and tools: path → contents, and the names of the robot files
/// it was given names for ([`MemoryLoader::with_robot`]); a folder is any path that holds files.
#[derive(Clone, Debug, Default)]
pub struct MemoryLoader {
    files: BTreeMap<PathBuf, String>,
    robots: BTreeMap<PathBuf, lamp_spec::RobotNames>,
}

impl MemoryLoader {
    /// A loader holding the given files.
    pub fn new<P: Into<PathBuf>, S: Into<String>>(files: impl IntoIterator<Item = (P, S)>) -> Self {
        let files = files.into_iter().map(|(p, s)| (normalize(&p.into()), s.into())).collect();
        MemoryLoader { files, robots: BTreeMap::new() }
    }

    /// The loader with the names of the robot file at `path` (whatever the robot's kind); the
    /// file itself must be one of the loader's files to be found at all.
    #[must_use]
    pub fn with_robot(mut self, path: impl Into<PathBuf>, names: lamp_spec::RobotNames) -> Self {
        self.robots.insert(normalize(&path.into()), names);
        self
    }
}

impl Loader for MemoryLoader {
    fn read_to_string(&self, path: &Path) -> Result<String, String> {
        self.files.get(&normalize(path)).cloned().ok_or_else(|| "no such file".to_string())
    }

    fn file_kind(&self, path: &Path) -> FileKind {
        let path = normalize(path);
        if self.files.contains_key(&path) {
            FileKind::File
        } else if self.files.keys().any(|file| file.starts_with(&path)) {
            FileKind::NotAFile("a directory".to_string())
        } else {
            FileKind::Missing
        }
    }

    fn robot_names(
        &self,
        path: &Path,
        _kind: lamp_spec::RobotKind,
    ) -> Result<Option<lamp_spec::RobotNames>, String> {
        Ok(self.robots.get(&normalize(path)).cloned())
    }

    fn glob(&self, pattern: &Path) -> Vec<PathBuf> {
        let pattern = normalize(pattern).to_string_lossy().into_owned();
        self.files
            .keys()
            .filter(|path| wildcard_match(&pattern, &path.to_string_lossy()))
            .cloned()
            .collect()
    }
}

/// `*` matches any run of characters except `/`; everything else matches itself.
fn wildcard_match(pattern: &str, text: &str) -> bool {
    match pattern.split_once('*') {
        None => pattern == text,
        Some((head, tail)) => {
            let Some(rest) = text.strip_prefix(head) else { return false };
            (0..=rest.len())
                .take_while(|&i| !rest[..i].contains('/'))
                .any(|i| rest.is_char_boundary(i) && wildcard_match(tail, &rest[i..]))
        }
    }
}

/// Removes `.` and resolves `..` lexically, so `a/../b/./c` becomes `b/c`.
pub fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                let after_parent =
                    matches!(out.components().next_back(), Some(Component::ParentDir));
                if out.as_os_str().is_empty() || after_parent {
                    out.push("..");
                } else {
                    out.pop();
                }
            }
            other => out.push(other),
        }
    }
    out
}

/// The files read while checking a spec, for rendering diagnostics.
#[derive(Clone, Debug, Default)]
pub struct SourceMap {
    files: Vec<SourceFile>,
}

impl SourceMap {
    /// Adds a file (display name, text) and returns its id.
    pub fn add(&mut self, name: String, text: String) -> FileId {
        self.files.push(SourceFile::new(name, text));
        FileId(u32::try_from(self.files.len() - 1).expect("fewer than 2^32 source files"))
    }

    /// The display name of a file.
    pub fn name(&self, file: FileId) -> &str {
        self.files[file.0 as usize].name()
    }

    /// The text of a file.
    pub fn text(&self, file: FileId) -> &str {
        self.files[file.0 as usize].text()
    }

    /// The file as miette reads it for a report, without copying its text.
    pub(crate) fn source_file(&self, file: FileId) -> &SourceFile {
        &self.files[file.0 as usize]
    }

    /// The text a span covers.
    pub fn slice(&self, span: Span) -> &str {
        &self.text(span.file)[span.start..span.end]
    }

    /// The file as a miette source, for attaching to a report.
    pub fn named_source(&self, file: FileId) -> miette::NamedSource<String> {
        miette::NamedSource::new(self.name(file), self.text(file).to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wildcards_stay_inside_one_folder() {
        assert!(wildcard_match("demos/*.mcap", "demos/a.mcap"));
        assert!(!wildcard_match("demos/*.mcap", "demos/x/a.mcap"));
        assert!(!wildcard_match("demos/*.mcap", "demos/a.bag"));
    }

    #[test]
    fn normalize_resolves_dots() {
        assert_eq!(normalize(Path::new("a/../b/./c")), PathBuf::from("b/c"));
        assert_eq!(normalize(Path::new("../robots/x.urdf")), PathBuf::from("../robots/x.urdf"));
        assert_eq!(normalize(Path::new("../../x")), PathBuf::from("../../x"));
        assert_eq!(normalize(Path::new("d/p/../robots/x")), PathBuf::from("d/robots/x"));
    }
}
