//! Reading the model `lampc build` wrote, for `lampc solve`: the build folder's layout (a model
//! folder, not an interrupted build or an older layout), the build's lock (not while a build
//! replaces the model), every artifact checked against the manifest before anything is used, and
//! the sampler file learned from the same demonstrations as the PDDL.

use std::path::{Path, PathBuf};

use lamp_build::{
    BuildFolderError, DOMAIN_FILE, MANIFEST_FILE, MODEL_DIR, Manifest, PROBLEMS_DIR, SAMPLERS_FILE,
    SamplersFile, SpecSources,
};
use lamp_spec::Spec;

use crate::files;
use crate::output::OutputFolder;

/// A diagnostic of any of the crates a read can fail in, for rendering.
pub(crate) type ReadError = Box<dyn miette::Diagnostic + Send + Sync>;

/// The artifacts a solve uses, read and checked.
pub(crate) struct ModelFiles {
    pub(crate) domain: String,
    pub(crate) problem: String,
    pub(crate) samplers: SamplersFile,
    /// What `--unchecked-build` let through, one line each, for the user to see.
    pub(crate) warnings: Vec<String>,
}

/// How much of the manifest a read enforces.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Check {
    /// Refuse a model whose files do not match its manifest.
    Manifest,
    /// Use the files as they are, warning about each difference (`--unchecked-build`).
    Unchecked,
}

/// The model folder of a build folder.
pub(crate) fn model_dir(build_dir: &Path) -> PathBuf {
    build_dir.join(MODEL_DIR)
}

/// Reads the domain, the problem `problem` and the sampler file of the model in `build_dir`,
/// checking that it was built from `spec` as it is now, with the robot models and object shapes
/// `world` loaded from the files it names.
pub(crate) fn read_model(
    build_dir: &Path,
    problem: &str,
    spec: &Spec,
    world: &lamp_world::SpecWorld,
    check: Check,
) -> Result<ModelFiles, ReadError> {
    let domain = spec.domain.as_str();
    let model = OutputFolder::new(&model_dir(build_dir)).map_err(boxed)?;
    let _reading = model.lock_for_reading().map_err(boxed)?;
    layout(build_dir, &model)?;
    let dir = model.path();
    let named = |relative: &str| dir.join(relative).display().to_string();
    let mut warnings = Vec::new();

    let problem_path = format!("{PROBLEMS_DIR}/{problem}.pddl");
    let read = |relative: &str| {
        let read = files::read_limited(&dir.join(relative), files::MODEL_FILE_LIMIT, "model file");
        read.map_err(|error| match error {
            files::ReadError::Io(error)
                if error.kind() == std::io::ErrorKind::NotFound && relative == problem_path =>
            {
                BuildFolderError::NoProblemFile { problem: problem.to_string() }
            }
            _ => BuildFolderError::Unreadable { file: named(relative), reason: error.to_string() },
        })
    };
    let needed = [DOMAIN_FILE, problem_path.as_str(), SAMPLERS_FILE];
    let [domain_bytes, problem_bytes, samplers_bytes] = needed.map(read);
    let contents = [domain_bytes?, problem_bytes?, samplers_bytes?];

    let manifest =
        files::read_text_limited(&dir.join(MANIFEST_FILE), files::MODEL_FILE_LIMIT, "model file")
            .map_err(|error| BuildFolderError::Manifest {
                file: named(MANIFEST_FILE),
                reason: error.to_string(),
            })
            .and_then(|text| Manifest::from_json(&text, &named(MANIFEST_FILE)));
    match manifest {
        Ok(manifest) => {
            if manifest.provenance.domain != domain {
                let error = BuildFolderError::OtherDomain {
                    found: manifest.provenance.domain.clone(),
                    expected: domain.to_string(),
                };
                refuse_or_warn(error, check, &mut warnings)?;
            }
            if check == Check::Manifest && !manifest.lists(&problem_path) {
                let problem = problem.to_string();
                return Err(Box::new(BuildFolderError::NoProblemFile { problem }));
            }
            if let Err(error) = manifest.check_sources(&SpecSources::of(spec, world), problem) {
                refuse_or_warn(error, check, &mut warnings)?;
            }
            // The files the solve uses are checked as read (so what is checked is what is used);
            // every other file of the manifest too, since a model is trusted only as a whole.
            for (path, bytes) in needed.iter().zip(&contents) {
                if let Err(error) = manifest.check(path, bytes) {
                    refuse_or_warn(in_folder(error, dir), check, &mut warnings)?;
                }
            }
            for entry in manifest.files.iter().filter(|entry| !needed.contains(&&*entry.path)) {
                let result =
                    read(&entry.path).and_then(|bytes| manifest.check(&entry.path, &bytes));
                if let Err(error) = result {
                    refuse_or_warn(in_folder(error, dir), check, &mut warnings)?;
                }
            }
        }
        Err(error) => refuse_or_warn(error, check, &mut warnings)?,
    }

    let [domain_text, problem_text, samplers_text] = {
        let [domain_bytes, problem_bytes, samplers_bytes] = contents;
        [
            (DOMAIN_FILE, domain_bytes),
            (problem_path.as_str(), problem_bytes),
            (SAMPLERS_FILE, samplers_bytes),
        ]
        .map(|(path, bytes)| {
            String::from_utf8(bytes).map_err(|_| BuildFolderError::Unreadable {
                file: named(path),
                reason: "it is not UTF-8 text".to_string(),
            })
        })
    };
    let (domain_text, problem_text, samplers_text) = (domain_text?, problem_text?, samplers_text?);
    let samplers = SamplersFile::from_json(&samplers_text).map_err(boxed)?;
    if samplers.provenance.domain != domain {
        return Err(Box::new(BuildFolderError::OtherDomain {
            found: samplers.provenance.domain.clone(),
            expected: domain.to_string(),
        }));
    }
    lamp_build::check_same_demonstrations(
        &samplers,
        &[(DOMAIN_FILE, &domain_text), (&problem_path, &problem_text)],
    )
    .map_err(boxed)?;
    Ok(ModelFiles { domain: domain_text, problem: problem_text, samplers, warnings })
}

/// Refuses a folder that has no model: an interrupted build, an older layout, or nothing.
fn layout(build_dir: &Path, model: &OutputFolder) -> Result<(), ReadError> {
    let folder = build_dir.display().to_string();
    if model.path().is_dir() {
        return Ok(());
    }
    let leftovers = model.leftovers();
    if !leftovers.is_empty() {
        let names: Vec<String> = leftovers
            .iter()
            .filter_map(|path| path.file_name())
            .map(|name| name.to_string_lossy().into_owned())
            .collect();
        return Err(Box::new(BuildFolderError::Interrupted { folder, leftover: names.join(", ") }));
    }
    if build_dir.join(DOMAIN_FILE).exists() {
        return Err(Box::new(BuildFolderError::OldLayout { folder }));
    }
    Err(Box::new(BuildFolderError::NoBuild { folder }))
}

fn refuse_or_warn(
    error: BuildFolderError,
    check: Check,
    warnings: &mut Vec<String>,
) -> Result<(), ReadError> {
    match check {
        Check::Manifest => Err(Box::new(error)),
        Check::Unchecked => {
            warnings.push(format!("{error} (used as it is)"));
            Ok(())
        }
    }
}

/// The error with a file named by its path in `dir` instead of its path relative to it.
fn in_folder(error: BuildFolderError, dir: &Path) -> BuildFolderError {
    match error {
        BuildFolderError::Tampered { file, reason } => {
            BuildFolderError::Tampered { file: dir.join(file).display().to_string(), reason }
        }
        other => other,
    }
}

fn boxed(error: impl miette::Diagnostic + Send + Sync + 'static) -> ReadError {
    Box::new(error)
}
