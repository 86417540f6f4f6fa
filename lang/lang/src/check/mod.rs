//! Name resolution and checks: syntax tree → `lamp_spec::Spec`, reporting every problem found.

mod declarations;
mod plugins;
mod problems;
mod robot_names;
mod robots;
mod units;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::ast::{Item, Name, Text};
use crate::diagnostics::{Diagnostic, SpecError, at, did_you_mean};
use crate::source::{FileId, FileKind, Loader, SourceMap, Span, normalize};

pub(crate) use units::Dimension;

/// The state of one check run.
pub(crate) struct Checker<'a> {
    loader: &'a dyn Loader,
    /// The spec's folder as the loader sees it; paths in the spec are relative to it.
    base_dir: PathBuf,
    pub(crate) sources: SourceMap,
    diagnostics: Vec<Diagnostic>,
    pub(crate) places: crate::GoalPlaces,
}

/// Names declared once and referred to elsewhere, with where they were declared.
#[derive(Default)]
pub(crate) struct Declared {
    /// Relation types: robot parts and object types that are not the static world.
    pub(crate) relation_types: BTreeMap<String, Span>,
    /// Object types (including the static world) → (span, movable).
    pub(crate) object_types: BTreeMap<String, (Span, bool)>,
    /// Marker types (named poses without geometry), by name.
    pub(crate) marker_types: BTreeMap<String, Span>,
    pub(crate) robots: BTreeMap<String, lamp_spec::Robot>,
    /// Robots declared with errors: already reported, so references to them stay silent.
    pub(crate) invalid_robots: std::collections::BTreeSet<String>,
    pub(crate) structures: BTreeMap<String, Span>,
    /// The objects each structure places, as (object, type), in the order written.
    pub(crate) structure_objects: BTreeMap<String, Vec<(String, String)>>,
    pub(crate) aliases: BTreeMap<String, lamp_spec::RelationAlias>,
}

impl<'a> Checker<'a> {
    pub(crate) fn new(loader: &'a dyn Loader, base_dir: PathBuf, sources: SourceMap) -> Self {
        Checker { loader, base_dir, sources, diagnostics: Vec::new(), places: Default::default() }
    }

    pub(crate) fn report(&mut self, diagnostic: Diagnostic) {
        self.diagnostics.push(diagnostic);
    }

    pub(crate) fn finish(self) -> (Vec<Diagnostic>, SourceMap, crate::GoalPlaces) {
        (self.diagnostics, self.sources, self.places)
    }

    /// A path written in the spec, normalised, relative to the spec's folder.
    pub(crate) fn spec_path(&self, text: &Text) -> PathBuf {
        normalize(Path::new(&text.text))
    }

    /// Checks that a referenced file exists and is a file (not a folder, a device, …); returns
    /// its spec-relative path.
    pub(crate) fn existing_file(&mut self, text: &Text, what: &str) -> Option<PathBuf> {
        let path = self.spec_path(text);
        let path_text = text.text.clone();
        let diagnostic = match self.loader.file_kind(&self.base_dir.join(&path)) {
            FileKind::File => return Some(path),
            FileKind::Missing => {
                let help = format!(
                    "The {what} path is relative to the folder of the spec; check the spelling or create the file."
                );
                at(text.span, |at| SpecError::MissingFile { path: path_text, at, help })
            }
            FileKind::NotAFile(kind) => {
                let help = format!(
                    "The {what} path must name a regular file; a relative path starts at the folder of the spec."
                );
                at(text.span, |at| SpecError::NotAFile { path: path_text, kind, at, help })
            }
            FileKind::Inaccessible(reason) => {
                at(text.span, |at| SpecError::UnreadableFile { path: path_text, reason, at })
            }
        };
        self.report(diagnostic);
        None
    }

    /// Reads a referenced file into the source map.
    pub(crate) fn load(&mut self, text: &Text) -> Option<(FileId, String)> {
        let path = self.existing_file(text, "scene file")?;
        let full = self.base_dir.join(path);
        match self.loader.read_to_string(&full) {
            Ok(contents) => {
                let name = normalize(&full).display().to_string();
                Some((self.sources.add(name, contents.clone()), contents))
            }
            Err(reason) => {
                self.report(at(text.span, |at| SpecError::UnreadableFile {
                    path: text.text.clone(),
                    reason,
                    at,
                }));
                None
            }
        }
    }

    /// Files matching a glob pattern relative to the spec's folder.
    pub(crate) fn glob(&self, pattern: &Path) -> Vec<PathBuf> {
        self.loader.glob(&self.base_dir.join(pattern))
    }

    /// Reports a name declared twice within one namespace; returns whether it was new.
    pub(crate) fn declare(
        &mut self,
        seen: &mut BTreeMap<String, Span>,
        kind: &'static str,
        name: &Name,
    ) -> bool {
        if let Some(first) = seen.get(&name.text) {
            let first = (first.file == name.span.file).then(|| first.source_span());
            self.report(at(name.span, |at| SpecError::DuplicateName {
                kind,
                name: name.text.clone(),
                at,
                first,
            }));
            return false;
        }
        seen.insert(name.text.clone(), name.span);
        true
    }

    /// Reports a type name that is not a relation type (robot part or non-world object type).
    pub(crate) fn relation_type(&mut self, declared: &Declared, name: &Name) -> bool {
        if declared.relation_types.contains_key(&name.text) {
            return true;
        }
        let help = if declared.object_types.contains_key(&name.text) {
            Some(format!("`{}` is the static world, which takes part in no relation.", name.text))
        } else {
            did_you_mean(&name.text, declared.relation_types.keys().map(String::as_str))
        };
        self.report(at(name.span, |at| SpecError::UnknownType {
            name: name.text.clone(),
            at,
            help,
        }));
        false
    }

    /// Reports a name that is not a declared object type.
    pub(crate) fn object_type(&mut self, declared: &Declared, name: &Name) -> bool {
        if declared.object_types.contains_key(&name.text) {
            return true;
        }
        let help = did_you_mean(&name.text, declared.object_types.keys().map(String::as_str));
        self.report(at(name.span, |at| SpecError::UnknownType {
            name: name.text.clone(),
            at,
            help,
        }));
        false
    }

    /// Reports a setting given twice in one block; returns whether this is the first.
    pub(crate) fn once(&mut self, first: &mut Option<Span>, what: &str, span: Span) -> bool {
        if let Some(first) = *first {
            self.report(at(span, |at| SpecError::DuplicateSetting {
                what: what.to_string(),
                at,
                first: first.source_span(),
            }));
            return false;
        }
        *first = Some(span);
        true
    }
}

/// Checks a parsed spec. Returns a spec only when no problem was found.
pub(crate) fn check_items(
    checker: &mut Checker<'_>,
    file: FileId,
    items: &[Item],
) -> Option<lamp_spec::Spec> {
    let whole_file = Span { file, start: 0, end: 0 };
    let mut domain = None;
    let mut domain_span = None;
    let mut seed = None;
    let mut seed_span = None;
    let mut declared = Declared::default();

    for item in items {
        match item {
            Item::Domain(name) if checker.once(&mut domain_span, "`domain`", name.span) => {
                domain = Some(name.text.clone());
            }
            Item::Seed { value, span } if checker.once(&mut seed_span, "`seed`", *span) => {
                seed = checker.plain(value, "the seed").and_then(|v| {
                    // Read from the literal: past 2^53 its f64 value is rounded, and 2^53 + 1
                    // would silently become another seed.
                    let seed = match checker.sources.slice(value.span).trim().parse::<u64>() {
                        Ok(seed) => (seed <= 1 << 53).then_some(seed),
                        // `7.0` or `1e3`: whole, and below 2^53 where every whole f64 is exact.
                        Err(_) => {
                            (v >= 0.0 && v.fract() == 0.0 && v < 2f64.powi(53)).then_some(v as u64)
                        }
                    };
                    checker
                        .require(
                            seed.is_some(),
                            value.span,
                            "the seed",
                            "a whole number from 0 to 2^53",
                        )
                        .then_some(seed)
                        .flatten()
                });
            }
            _ => {}
        }
    }
    if domain_span.is_none() {
        checker.missing(
            whole_file,
            "the `domain` declaration",
            "Start the spec with `domain NAME`.",
        );
    }
    if seed_span.is_none() {
        checker.missing(
            whole_file,
            "the `seed` declaration",
            "Add `seed 1` (any whole number): one seed drives all randomness.",
        );
    }

    let robots = checker.robots(items, &mut declared);
    let object_types = checker.object_types(items, &mut declared);
    let demonstrations = checker.demonstrations(items, &declared);
    let learning = checker.learning(items, &declared);
    let relation_aliases = checker.relation_aliases(items, &mut declared);
    let structures = checker.structures(items, &mut declared);
    let problems = checker.problems(items, &declared);
    let plugins = checker.plugins(items);

    if !checker.diagnostics.is_empty() {
        return None;
    }
    Some(lamp_spec::Spec {
        domain: domain?,
        seed: seed?,
        robots,
        object_types,
        demonstrations,
        learning: learning?,
        relation_aliases,
        structures,
        problems,
        plugins: plugins?,
    })
}

impl Checker<'_> {
    /// Reports a missing declaration or setting.
    pub(crate) fn missing(&mut self, span: Span, what: &str, help: &str) {
        self.report(at(span, |at| SpecError::MissingDeclaration {
            what: what.to_string(),
            at,
            help: help.to_string(),
        }));
    }
}
