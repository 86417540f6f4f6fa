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
