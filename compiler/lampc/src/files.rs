//! The real file system, as the language front end's loader.

use std::path::{Path, PathBuf};

/// Reads files from disk.
pub(crate) struct DiskLoader;

impl lamp_lang::Loader for DiskLoader {
    fn read_to_string(&self, path: &Path) -> Result<String, String> {
        std::fs::read_to_string(path).map_err(|error| error.to_string())
    }

    fn exists(&self, path: &Path) -> bool {
        path.is_file()
    }

    fn glob(&self, pattern: &Path) -> Vec<PathBuf> {
        let Some(pattern) = pattern.to_str() else { return Vec::new() };
        let Ok(paths) = glob::glob(pattern) else { return Vec::new() };
        let mut found: Vec<PathBuf> = paths.flatten().filter(|path| path.is_file()).collect();
        found.sort();
        found
    }
}

/// Writes each `(relative path, contents)` under `dir` through a temporary file renamed into
/// place, so that a failure never leaves a partly written file behind.
pub(crate) fn write_atomically(dir: &Path, files: &[(&Path, &[u8])]) -> Result<(), String> {
    for (relative, contents) in files {
        let path = dir.join(relative);
        let folder = path.parent().unwrap_or(dir);
        std::fs::create_dir_all(folder)
            .map_err(|error| format!("cannot create {}: {error}", folder.display()))?;
        let file_name = path.file_name().map(|name| name.to_string_lossy().into_owned());
        let temporary = folder.join(format!(".{}.tmp", file_name.unwrap_or_default()));
        std::fs::write(&temporary, contents)
            .map_err(|error| format!("cannot write {}: {error}", temporary.display()))?;
        std::fs::rename(&temporary, &path).map_err(|error| {
            let _ = std::fs::remove_file(&temporary);
            format!("cannot move {} to {}: {error}", temporary.display(), path.display())
        })?;
    }
    Ok(())
}
