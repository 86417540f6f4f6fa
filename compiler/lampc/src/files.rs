//! The real file system, as the language front end's loader.

use std::path::{Path, PathBuf};

use lamp_lang::FileKind;
use lamp_spec::{RobotKind, RobotNames};

/// Reads files from disk.
pub(crate) struct DiskLoader;

/// Reads files from disk, but takes a demonstration pattern as the files it would match: for a
/// command that does not read the spec's demonstrations (`lampc solve` works from the model, and
/// `lampc build --demos DIR` reads DIR instead), recordings that were moved or deleted, or never
/// were where the spec looks, are no error in the spec.
pub(crate) struct DemonstrationsUnread;

impl lamp_lang::Loader for DemonstrationsUnread {
    fn read_to_string(&self, path: &Path) -> Result<String, String> {
        DiskLoader.read_to_string(path)
    }

    fn file_kind(&self, path: &Path) -> FileKind {
        DiskLoader.file_kind(path)
    }

    fn glob(&self, pattern: &Path) -> Vec<PathBuf> {
        vec![pattern.to_path_buf()]
    }

    fn robot_names(&self, path: &Path, kind: RobotKind) -> Result<Option<RobotNames>, String> {
        DiskLoader.robot_names(path, kind)
    }
}

impl lamp_lang::Loader for DiskLoader {
    fn read_to_string(&self, path: &Path) -> Result<String, String> {
        read_text_limited(path, SPEC_FILE_LIMIT, "spec file").map_err(|error| error.to_string())
    }

    fn file_kind(&self, path: &Path) -> FileKind {
        match std::fs::metadata(path) {
            Ok(metadata) if metadata.is_file() => FileKind::File,
            Ok(metadata) => FileKind::NotAFile(describe(&metadata.file_type()).to_string()),
            // A link whose target is missing is not nothing: say so.
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => {
                match std::fs::symlink_metadata(path) {
                    Ok(_) => FileKind::NotAFile("a symbolic link to nothing".to_string()),
                    Err(_) => FileKind::Missing,
                }
            }
            Err(error) => FileKind::Inaccessible(error.to_string()),
        }
    }

    fn glob(&self, pattern: &Path) -> Vec<PathBuf> {
        let Some(pattern) = pattern.to_str() else { return Vec::new() };
        let Ok(paths) = glob::glob(pattern) else { return Vec::new() };
        let mut found: Vec<PathBuf> = paths.flatten().filter(|path| path.is_file()).collect();
        found.sort();
        found
    }

    fn robot_names(&self, path: &Path, kind: RobotKind) -> Result<Option<RobotNames>, String> {
        lamp_world::robot_names(path, kind).map(Some).map_err(|error| with_causes(&error))
    }
}

/// What a file type that is not a regular file is, for "… is X, not a file".
pub(crate) fn describe(file_type: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_fifo() {
            return "a named pipe";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_dir() {
        "a directory"
    } else if file_type.is_symlink() {
        "a symbolic link"
    } else {
        "something other than a regular file"
    }
}

/// An error and its causes, as one line: "cannot read robot file x: permission denied".
fn with_causes(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut cause = error.source();
    while let Some(inner) = cause {
        text.push_str(&format!(": {inner}"));
        cause = inner.source();
    }
    text
}

/// The largest spec or scene file read: the bundled specs are under 25 KiB, so 16 MiB is far
/// beyond any hand-written spec, while checking that much still takes seconds, not minutes.
pub(crate) const SPEC_FILE_LIMIT: u64 = 16 << 20;
/// The largest file of a build folder read (`domain.pddl`, a problem, `samplers.json`,
/// `manifest.json`): the build's own limit, so that a build never writes what a solve refuses.
pub(crate) const MODEL_FILE_LIMIT: u64 = lamp_build::MODEL_FILE_LIMIT;
/// The largest demonstration or trajectory file read (MCAP): a bundled demonstration is about
/// 40 KiB, a recorded one with many objects may be far longer; every file is held in memory
/// while it is read.
pub(crate) const DEMONSTRATION_FILE_LIMIT: u64 = 2 << 30;

/// Why a file was not read.
#[derive(Debug)]
pub(crate) enum ReadError {
    /// The operating system's reason.
    Io(std::io::Error),
    /// Something else than a regular file is at the path: "a directory", "a character device".
    NotAFile(&'static str),
    /// The file is larger than what a file of its kind may be.
    TooLarge { size: u64, limit: u64, what: &'static str },
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReadError::Io(error) => error.fmt(f),
            ReadError::NotAFile(kind) => write!(f, "it is {kind}, not a file"),
            ReadError::TooLarge { size, limit, what } => write!(
                f,
                "it is {} ({size} bytes), more than the {} a {what} may be",
                bytes(*size),
                bytes(*limit)
            ),
        }
    }
}

/// A size in the unit that reads best: "3.2 MiB".
fn bytes(size: u64) -> String {
    const UNITS: [&str; 4] = ["bytes", "KiB", "MiB", "GiB"];
    let mut value = size as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 { format!("{size} bytes") } else { format!("{value:.1} {}", UNITS[unit]) }
}

/// The bytes of the regular file at `path`, refused when it is something else (a folder, a
/// device such as `/dev/zero`, a named pipe, whose reading might never end) or larger than
/// `limit` bytes; `what` names the kind of file for the message ("spec file").
pub(crate) fn read_limited(
    path: &Path,
    limit: u64,
    what: &'static str,
) -> Result<Vec<u8>, ReadError> {
    use std::io::Read as _;
    // Looked at before opening: opening a named pipe waits for a writer.
    let regular = |metadata: &std::fs::Metadata| {
        if !metadata.is_file() {
            return Err(ReadError::NotAFile(describe(&metadata.file_type())));
        }
        match metadata.len() {
            size if size > limit => Err(ReadError::TooLarge { size, limit, what }),
            _ => Ok(()),
        }
    };
    regular(&std::fs::metadata(path).map_err(ReadError::Io)?)?;
    let file = std::fs::File::open(path).map_err(ReadError::Io)?;
    // Again on the open file, which may not be the one looked at.
    let metadata = file.metadata().map_err(ReadError::Io)?;
    regular(&metadata)?;
    let mut contents = Vec::with_capacity(usize::try_from(metadata.len()).unwrap_or_default());
    // A file growing while it is read stops one byte past the limit.
    file.take(limit.saturating_add(1)).read_to_end(&mut contents).map_err(ReadError::Io)?;
    match contents.len() as u64 {
        size if size > limit => Err(ReadError::TooLarge { size, limit, what }),
        _ => Ok(contents),
    }
}

/// [`read_limited`] for a text file.
pub(crate) fn read_text_limited(
    path: &Path,
    limit: u64,
    what: &'static str,
) -> Result<String, ReadError> {
    String::from_utf8(read_limited(path, limit, what)?).map_err(|_| {
        ReadError::Io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "stream did not contain valid UTF-8",
        ))
    })
}

/// The regular files matching a glob pattern, sorted, each once, and a warning for everything
/// else that matches: a folder, a link to something that is not a file, a device, a path that
/// cannot be examined. A link to a regular file is followed (the link's path is kept).
pub(crate) fn glob_files(pattern: &Path) -> (Vec<PathBuf>, Vec<String>) {
    let mut files = Vec::new();
    let mut warnings = Vec::new();
    let shown = pattern.display();
    let Some(text) = pattern.to_str() else {
        warnings.push(format!("the pattern {shown} is not UTF-8 text; nothing read from it"));
        return (files, warnings);
    };
    let paths = match glob::glob(text) {
        Ok(paths) => paths,
        Err(error) => {
            warnings
                .push(format!("the pattern {shown} is not valid ({error}); nothing read from it"));
            return (files, warnings);
        }
    };
    for entry in paths {
        let path = match entry {
            Ok(path) => path,
            Err(error) => {
                let reason = error.error().to_string();
                warnings.push(format!(
                    "{} cannot be examined ({reason}); skipped",
                    error.path().display()
                ));
                continue;
            }
        };
        let skipped = match std::fs::symlink_metadata(&path) {
            Ok(metadata) if metadata.is_file() => None,
            Ok(metadata) if metadata.file_type().is_symlink() => match std::fs::metadata(&path) {
                Ok(target) if target.is_file() => None,
                Ok(target) => {
                    Some(format!("is a symbolic link to {}", describe(&target.file_type())))
                }
                Err(_) => Some("is a symbolic link to nothing".to_string()),
            },
            Ok(metadata) => Some(format!("is {}, not a file", describe(&metadata.file_type()))),
            Err(error) => Some(format!("cannot be examined ({error})")),
        };
        match skipped {
            None => files.push(path),
            Some(reason) => warnings.push(format!("{} {reason}; skipped", path.display())),
        }
    }
    files.sort();
    files.dedup();
    (files, warnings)
}
