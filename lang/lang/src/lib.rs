//! The `.lamp` language: grammar, syntax tree, name resolution, checks and diagnostics.
//!
//! [`check`] turns a spec file into a [`lamp_spec::Spec`] and every problem found on the way.
//! The front end reads files only through a [`Loader`], so it is a pure function of its inputs.
//! pest stays inside this crate.

mod ast;
mod check;
mod diagnostics;
mod parse;
mod source;
mod source_file;

use std::path::Path;

pub use diagnostics::{Diagnostic, SpecError, WithSource};
pub use source::{FileId, FileKind, Loader, MemoryLoader, SourceMap, Span, normalize};

/// The result of checking a spec.
#[derive(Debug)]
pub struct CheckOutcome {
    /// The checked spec, present exactly when there are no diagnostics.
    pub spec: Option<lamp_spec::Spec>,
    /// Every problem found, in the order found.
    pub diagnostics: Vec<Diagnostic>,
    /// The files read, for rendering the diagnostics.
    pub sources: SourceMap,
    /// Where goals are written, for diagnostics found after checking (by the build).
    pub places: GoalPlaces,
}

/// Where goals, and the settings the build checks against the demonstrations, are written in the
/// spec's files.
#[derive(Debug, Clone, Default)]
pub struct GoalPlaces {
    /// Each `at` goal by (problem, object).
    at_goals: std::collections::BTreeMap<(String, String), Span>,
    /// Each structure goal by problem.
    structure_goals: std::collections::BTreeMap<String, Span>,
    /// Each structure's objects by (structure, object): the whole placement line.
    structure_objects: std::collections::BTreeMap<(String, String), Span>,
    /// Each robot's `grab distance` clause, by robot.
    grab_distances: std::collections::BTreeMap<String, Span>,
    /// Each object's and robot's line in a problem's scene by (problem, name): the type or robot
    /// name to the end of the pose.
    scene_placements: std::collections::BTreeMap<(String, String), Span>,
    /// Each `object` line of a `files … as ros2 { … }` mapping by (the source's pattern as the
    /// spec stores it, object): its type to its frame.
    mapped_objects: std::collections::BTreeMap<(String, String), Span>,
}

impl GoalPlaces {
    /// Where the `at` goal on `object` of problem `problem` is written.
    pub fn at_goal(&self, problem: &str, object: &str) -> Option<Span> {
        self.at_goals.get(&(problem.to_string(), object.to_string())).copied()
    }

    /// Where the structure goal of problem `problem` is written.
    pub fn structure_goal(&self, problem: &str) -> Option<Span> {
        self.structure_goals.get(problem).copied()
    }

    /// Where structure `structure` places `object`.
    pub fn structure_object(&self, structure: &str, object: &str) -> Option<Span> {
        self.structure_objects.get(&(structure.to_string(), object.to_string())).copied()
    }

    /// Where robot `robot`'s `grab distance` is written.
    pub fn grab_distance(&self, robot: &str) -> Option<Span> {
        self.grab_distances.get(robot).copied()
    }

    /// Where problem `problem`'s scene places the object or robot `name`.
    pub fn scene_placement(&self, problem: &str, name: &str) -> Option<Span> {
        self.scene_placements.get(&(problem.to_string(), name.to_string())).copied()
    }

    /// Where the ros2 mapping of the source with pattern `pattern` (as `lamp_spec::DemoSource`
    /// stores it) maps `object`.
    pub fn mapped_object(&self, pattern: &str, object: &str) -> Option<Span> {
        self.mapped_objects.get(&(pattern.to_string(), object.to_string())).copied()
    }

    pub(crate) fn add_mapped_object(&mut self, pattern: &str, object: &str, span: Span) {
        self.mapped_objects.insert((pattern.to_string(), object.to_string()), span);
    }

    pub(crate) fn add_scene_placement(&mut self, problem: &str, name: &str, span: Span) {
        self.scene_placements.insert((problem.to_string(), name.to_string()), span);
    }

    pub(crate) fn add_grab_distance(&mut self, robot: &str, span: Span) {
        self.grab_distances.insert(robot.to_string(), span);
    }

    pub(crate) fn add_structure_goal(&mut self, problem: &str, span: Span) {
        self.structure_goals.insert(problem.to_string(), span);
    }

    pub(crate) fn add_structure_object(&mut self, structure: &str, object: &str, span: Span) {
        self.structure_objects.insert((structure.to_string(), object.to_string()), span);
    }

    pub(crate) fn add_at_goal(&mut self, problem: &str, object: &str, span: Span) {
        self.at_goals.insert((problem.to_string(), object.to_string()), span);
    }
}

/// Checks the spec at `path`; files it refers to are resolved against its folder.
pub fn check(path: &Path, loader: &dyn Loader) -> CheckOutcome {
    let display = path.display().to_string();
    match loader.read_to_string(path) {
        Ok(text) => check_source(&display, &text, path.parent().unwrap_or(Path::new("")), loader),
        Err(reason) => {
            let mut sources = SourceMap::default();
            let file = sources.add(display.clone(), String::new());
            let error = SpecError::UnreadableFile { path: display, reason, at: (0, 0).into() };
            CheckOutcome {
                places: GoalPlaces::default(),
                spec: None,
                diagnostics: vec![Diagnostic { file, error: Box::new(error) }],
                sources,
            }
        }
    }
}

/// Checks spec text named `name`, whose referenced files are relative to `base_dir`.
pub fn check_source(name: &str, text: &str, base_dir: &Path, loader: &dyn Loader) -> CheckOutcome {
    let mut sources = SourceMap::default();
    let file = sources.add(name.to_string(), text.to_string());
    match parse::parse_spec(file, text) {
        Err(diagnostic) => CheckOutcome {
            spec: None,
            diagnostics: vec![diagnostic],
            sources,
            places: GoalPlaces::default(),
        },
        Ok(items) => {
            let mut checker = check::Checker::new(loader, base_dir.to_path_buf(), sources);
            let spec = check::check_items(&mut checker, file, &items);
            let (diagnostics, sources, places) = checker.finish();
            CheckOutcome { spec, diagnostics, sources, places }
        }
    }
}
