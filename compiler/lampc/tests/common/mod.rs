//! What the command-line tests share: looking at the folders a command leaves behind.

use std::path::Path;

/// The names in `dir`, sorted, hidden ones (locks, staging folders) included.
pub fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("a folder")
        .flatten()
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}
