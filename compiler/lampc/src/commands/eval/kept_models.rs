//! `--keep-models`: each run's learned model, written as a build folder.
//!
//! A run that fails is explained by what it learned: its `vocabulary.md` says which relations and
//! actions the subset taught, and `lampc solve --build <out>/models/<count>-<run>` solves one
//! problem with it again, with the solver's own messages. A run whose model could not be written
//! (an alias or a goal it cannot express) keeps its vocabulary report in the build folder's
//! `failed/`, as `lampc build` does. Runs of one count that drew the same
//! subset (a count equal to the pool's size) share a model, written under each run's name.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use lamp_build::ArtifactFile;

use super::Slot;
use super::schedule::SubsetWork;
use crate::output::OutputFolder;

/// The folder, beside the evaluation's outputs, that holds the kept models.
const MODELS_DIR: &str = "models";

/// Where each subset's model goes.
pub(super) struct KeptModels {
    /// Per subset digest, the build folders of the runs that drew it, in slot order.
    folders: BTreeMap<String, Vec<PathBuf>>,
}

impl KeptModels {
    pub(super) fn new(out: &Path, slots: &[Slot]) -> Self {
        let mut folders: BTreeMap<String, Vec<PathBuf>> = BTreeMap::new();
        for slot in slots {
            let folder = out.join(MODELS_DIR).join(format!("{}-{}", slot.demos, slot.run));
            let runs = folders.entry(slot.key.0.clone()).or_default();
            if !runs.contains(&folder) {
                runs.push(folder);
            }
        }
        KeptModels { folders }
    }

    /// Writes a subset's model into the build folder of every run that drew it. A folder that
    /// cannot be written is reported and skipped: the evaluation's figures do not depend on it.
    pub(super) fn write(
        &self,
        work: &SubsetWork,
        files: &[ArtifactFile],
        render: &dyn Fn(&dyn miette::Diagnostic) -> String,
    ) {
        let files: Vec<(&Path, &[u8])> =
            files.iter().map(|file| (file.path.as_path(), file.contents.as_bytes())).collect();
        self.replace_in_each(work, lamp_build::MODEL_DIR, &files, "the model", render);
    }

    /// Writes the vocabulary report of a subset's model that could not be written into the
    /// `failed/` folder of every run that drew it, as [`KeptModels::write`] writes a model.
    pub(super) fn write_failed(
        &self,
        work: &SubsetWork,
        report: &str,
        render: &dyn Fn(&dyn miette::Diagnostic) -> String,
    ) {
        let files = [(Path::new(lamp_build::VOCABULARY_FILE), report.as_bytes())];
        self.replace_in_each(work, lamp_build::FAILED_DIR, &files, "what the run learned", render);
    }

    /// Replaces the folder `name` of each build folder of the runs that drew the subset with
    /// `files`, reporting (as `what`) and skipping a folder that cannot be written.
    fn replace_in_each(
        &self,
        work: &SubsetWork,
        name: &str,
        files: &[(&Path, &[u8])],
        what: &str,
        render: &dyn Fn(&dyn miette::Diagnostic) -> String,
    ) {
        let digest = work.digest.to_string();
        for build in self.folders.get(&digest).into_iter().flatten() {
            let written = OutputFolder::new(&build.join(name))
                .and_then(|folder| folder.lock("eval").map(|lock| (folder, lock)))
                .and_then(|(folder, lock)| folder.replace(&lock, files));
            if let Err(error) = written {
                eprintln!("lampc eval: {what} was not kept: {}", render(&error));
            }
        }
    }
}
