//! Reading and checking the spec a command works on, with its diagnostics printed.

use std::path::{Path, PathBuf};

use crate::files::{DemonstrationsUnread, DiskLoader};

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

/// Whether a command reads the spec's demonstration files: only then must a `files` pattern
/// match one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Demonstrations {
    Read,
    Unread,
}

/// Checks the spec at `path`, printing every diagnostic; `None` if it has errors.
pub(crate) fn check_spec(
    path: &Path,
    colour: bool,
    demonstrations: Demonstrations,
) -> Option<CheckedSpec> {
    let outcome = match demonstrations {
        Demonstrations::Read => lamp_lang::check(path, &DiskLoader),
        Demonstrations::Unread => lamp_lang::check(path, &DemonstrationsUnread),
    };
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

/// Checks the initial scenes of `problems` (every problem when `None`) in `world`, printing each
/// finding at its line in the spec; the number of findings.
///
/// A scene the solver cannot start from (an object in the air, bodies overlapping, a robot in
/// collision) is a broken spec: every command that reads the spec refuses it at its line, before
/// learning or solving answer a world that cannot be.
pub(crate) fn refuse_scenes(
    spec: &lamp_spec::Spec,
    located: (&lamp_lang::GoalPlaces, &lamp_lang::SourceMap),
    world: &lamp_world::SpecWorld,
    problem: Option<&str>,
    colour: bool,
) -> usize {
    let mut refused = 0;
    let (places, sources) = located;
    for scene in spec.problems.iter().filter(|p| problem.is_none_or(|name| p.name == name)) {
        let issues = lamp_build::problem_scene_issues(spec, world, scene);
        refused += issues.len();
        for issue in &issues {
            eprint!("{}", crate::diagnostics::render_scene_issue(issue, places, sources, colour));
        }
    }
    refused
}
