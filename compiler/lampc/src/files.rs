//! The real file system, as the language front end's loader.

use std::path::{Path, PathBuf};

use lamp_lang::FileKind;
use lamp_spec::{RobotKind, RobotNames};

/// Reads files from disk.
pub(crate) struct DiskLoader;

impl lamp_lang::Loader for DiskLoader {
    fn read_to_string(&self, path: &Path) -> Result<String, String> {
        std::fs::read_to_string(path).map_err(|error| error.to_string())
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
