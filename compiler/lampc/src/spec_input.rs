//! Reading and checking the spec a command works on, with its diagnostics printed.

use std::path::{Path, PathBuf};

use crate::files::DiskLoader;

/// A checked spec and where it lives.
pub(crate) struct CheckedSpec {
    pub(crate) spec: lamp_spec::Spec,
    /// The spec's folder: paths in the spec are relative to it.
    pub(crate) dir: PathBuf,
    /// The spec's file name, for provenance and messages.
    pub(crate) file_name: String,
    /// The files read and where goals are written, for diagnostics found later.
    pub(crate) sources: lamp_lang::SourceMap,
    pub(crate) places: lamp_lang::GoalPlaces,
}

/// Checks the spec at `path`, printing every diagnostic; `None` if it has errors.
pub(crate) fn check_spec(path: &Path, colour: bool) -> Option<CheckedSpec> {
    let outcome = lamp_lang::check(path, &DiskLoader);
    eprint!("{}", crate::diagnostics::render_all(&outcome, colour, crate::terminal_width()));
    let Some(spec) = outcome.spec else {
        let name = outcome.sources.name(lamp_lang::FileId(0)).to_string();
        eprintln!("{name}: {} error(s)", outcome.diagnostics.len());
        return None;
    };
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let file_name = path
        .file_name()
        .map_or_else(|| path.display().to_string(), |name| name.to_string_lossy().into_owned());
    Some(CheckedSpec { spec, dir, file_name, sources: outcome.sources, places: outcome.places })
}
