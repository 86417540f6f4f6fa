//! The model folder's layout: where each artifact goes, and an artifact as a path and its text.

use std::path::PathBuf;

/// The folder inside the build folder that holds every artifact (the model); `lampc build`
/// replaces it as a whole, beside the `demos/` and `solutions/` folders it leaves alone.
pub const MODEL_DIR: &str = "model";
/// The domain file's path inside the model folder.
pub const DOMAIN_FILE: &str = "domain.pddl";
/// The folder of problem files inside the model folder.
pub const PROBLEMS_DIR: &str = "problems";
/// The sampler file's path inside the model folder.
pub const SAMPLERS_FILE: &str = "samplers.json";
/// The vocabulary report's path inside the model folder.
pub const VOCABULARY_FILE: &str = "vocabulary.md";
/// The folder inside the build folder where a build that learned a model but could not write it
/// (an alias or a goal the model cannot express) puts the model's vocabulary report, so that the
/// user can read what was learned; the model folder itself is left as it was.
pub const FAILED_DIR: &str = "failed";
/// The largest model file a solve reads, and so the largest a build writes: the bundled models'
/// are tens of KiB; 256 MiB leaves room for models a thousand times larger without letting a
/// wrong path fill the memory.
pub const MODEL_FILE_LIMIT: u64 = 256 << 20;

/// One artifact: where it goes (relative to the model folder) and its full text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ArtifactFile {
    pub path: PathBuf,
    pub contents: String,
}
