//! The build's inputs as values: demonstration files already read into memory, and where to
//! look for them (the caller does the globbing and reading, so the pipeline stays pure).

use std::path::{Path, PathBuf};

use lamp_spec::{DemoSource, Spec};

/// One demonstration file: a stable name (used as the demonstration's id and in the digest) and
/// its bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DemoFile {
    /// A name that identifies the file in messages and provenance, e.g. `demos/demo_000.mcap`.
    pub name: String,
    /// The MCAP bytes.
    pub bytes: Vec<u8>,
}

/// The folder `lampc demos` writes simulated demonstrations into, inside the build folder.
pub const SIMULATED_DEMOS_DIR: &str = "demos";

/// The default build folder, inside the spec's folder.
pub const DEFAULT_BUILD_DIR: &str = "build";

/// The glob patterns of a spec's demonstration files.
///
/// `demos_override` (`--demos DIR`) replaces every source of the spec with `DIR/*.mcap`.
/// Otherwise a `files` source contributes its pattern (relative to `spec_dir`), and any simulated
/// source contributes `<build_dir>/demos/*.mcap` once, where `lampc demos` writes its files.
pub fn demo_patterns(
    spec: &Spec,
    spec_dir: &Path,
    build_dir: &Path,
    demos_override: Option<&Path>,
) -> Vec<PathBuf> {
    if let Some(dir) = demos_override {
        return vec![dir.join("*.mcap")];
    }
    let mut patterns = Vec::new();
    let simulated = build_dir.join(SIMULATED_DEMOS_DIR).join("*.mcap");
    for source in &spec.demonstrations {
        let pattern = match source {
            DemoSource::Files { pattern, .. } => spec_dir.join(pattern),
            DemoSource::Simulated { .. } => simulated.clone(),
        };
        if !patterns.contains(&pattern) {
            patterns.push(pattern);
        }
    }
    patterns
}

/// The name of a demonstration file in provenance: its path relative to `base` when it lies
/// inside, else the path as given (so names do not depend on where the build runs from).
pub fn demo_name(path: &Path, base: &Path) -> String {
    let relative = path.strip_prefix(base).unwrap_or(path);
    relative.to_string_lossy().replace('\\', "/")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_relative_to_the_base_when_inside() {
        assert_eq!(demo_name(Path::new("/a/b/demos/x.mcap"), Path::new("/a/b")), "demos/x.mcap");
        assert_eq!(demo_name(Path::new("/c/x.mcap"), Path::new("/a/b")), "/c/x.mcap");
    }
}
