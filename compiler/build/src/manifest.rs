//! The build's manifest (`manifest.json`): what the build folder's model was built from and the
//! digest of every artifact, so that the run time can refuse a model folder whose files were
//! edited, truncated, swapped for another build's or mixed by an interrupted write.
//!
//! The manifest and the checks are values here; reading the folder is the caller's. Its errors,
//! [`BuildFolderError`], are also the ones `lampc solve` raises for the folder's layout (no model,
//! an interrupted build, an older layout), so that every refusal of a build folder has one home.

use std::path::{Component, Path};

use miette::Diagnostic;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::digest::file_digest;
use crate::error::BuildError;
use crate::model_folder::ArtifactFile;
use crate::provenance::Provenance;
use crate::samplers::SamplersFile;
use crate::spec_sources::SpecSources;

/// The manifest's path inside the model folder.
pub const MANIFEST_FILE: &str = "manifest.json";
/// The `format` field of every manifest.
pub const MANIFEST_FORMAT: &str = "lamp-build-manifest";
/// The manifest version; bumped when its shape or meaning changes.
pub const MANIFEST_VERSION: u32 = 4;
/// The name of the per-file digest: FNV-1a (64 bit) over the file's bytes (see [`file_digest`]).
pub const MANIFEST_DIGEST: &str = "fnv1a64";

/// The content of `manifest.json`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Manifest {
    /// Always [`MANIFEST_FORMAT`].
    pub format: String,
    /// Always [`MANIFEST_VERSION`] when written by this crate.
    pub version: u32,
    /// What the model was built from: spec file, domain, seed, demonstrations and their digest.
    pub provenance: Provenance,
    /// What the model and each problem file were made from in the spec ([`SpecSources`]).
    pub sources: SpecSources,
    /// The algorithm of every file's `digest`, [`MANIFEST_DIGEST`].
    pub digest: String,
    /// Every artifact but the manifest, by path.
    pub files: Vec<ManifestEntry>,
}

/// One artifact of the manifest.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ManifestEntry {
    /// The path relative to the model folder, with `/` separators.
    pub path: String,
    /// The length in bytes.
    pub bytes: u64,
    /// The digest of the bytes, `fnv1a64:<16 hex digits>`.
    pub digest: String,
}

impl Manifest {
    /// The manifest of `files`, listed by path, made from `sources`.
    pub fn new(provenance: &Provenance, sources: &SpecSources, files: &[ArtifactFile]) -> Self {
        let mut entries: Vec<ManifestEntry> = files
            .iter()
            .map(|file| ManifestEntry {
                path: slash_path(&file.path),
                bytes: file.contents.len() as u64,
                digest: file_digest(file.contents.as_bytes()).to_string(),
            })
            .collect();
        entries.sort_by(|a, b| a.path.cmp(&b.path));
        Manifest {
            format: MANIFEST_FORMAT.to_string(),
            version: MANIFEST_VERSION,
            provenance: provenance.clone(),
            sources: sources.clone(),
            digest: MANIFEST_DIGEST.to_string(),
            files: entries,
        }
    }

    /// Pretty JSON ending in a newline.
    pub fn to_json(&self) -> Result<String, BuildError> {
        let mut text = serde_json::to_string_pretty(self).map_err(|error| BuildError::Emit {
            what: MANIFEST_FILE.into(),
            reason: error.to_string(),
        })?;
        text.push('\n');
        Ok(text)
    }

    /// Reads a manifest and checks its format, version, digest algorithm and paths; `file` names
    /// it in errors.
    pub fn from_json(text: &str, file: &str) -> Result<Self, BuildFolderError> {
        let fail = |reason: String| BuildFolderError::Manifest { file: file.to_string(), reason };
        let manifest: Manifest =
            serde_json::from_str(text).map_err(|error| fail(error.to_string()))?;
        if manifest.format != MANIFEST_FORMAT {
            return Err(fail(format!(
                "its format is `{}`, not `{MANIFEST_FORMAT}`",
                manifest.format
            )));
        }
        if manifest.version != MANIFEST_VERSION {
            return Err(fail(format!(
                "it has version {}, this lampc reads version {MANIFEST_VERSION}",
                manifest.version
            )));
        }
        if manifest.digest != MANIFEST_DIGEST {
            return Err(fail(format!(
                "its digest is `{}`, this lampc checks `{MANIFEST_DIGEST}`",
                manifest.digest
            )));
        }
        if let Some(entry) = manifest.files.iter().find(|entry| !is_inside(&entry.path)) {
            return Err(fail(format!(
                "it lists `{}`, a path outside the model folder",
                entry.path
            )));
        }
        Ok(manifest)
    }

    /// Whether the manifest lists `path` (relative to the model folder, `/` separators).
    pub fn lists(&self, path: &str) -> bool {
        self.files.iter().any(|entry| entry.path == path)
    }

    /// Checks that the model and problem `problem` were made from the spec whose sources are
    /// `current`: a spec edited since the build would otherwise be answered by the old model or
    /// the old problem file (a goal the spec no longer has).
    pub fn check_sources(
        &self,
        current: &SpecSources,
        problem: &str,
    ) -> Result<(), BuildFolderError> {
        if self.sources.model != current.model {
            return Err(BuildFolderError::SpecChanged { spec: self.provenance.spec.clone() });
        }
        let changed = |parts: &str| BuildFolderError::ProblemChanged {
            problem: problem.to_string(),
            spec: self.provenance.spec.clone(),
            parts: parts.to_string(),
        };
        match (self.sources.problems.get(problem), current.problems.get(problem)) {
            (Some(built), Some(now)) => {
                let parts = built.changed_parts(now);
                match parts.split_last() {
                    None => Ok(()),
                    Some((last, [])) => Err(changed(last)),
                    Some((last, rest)) => Err(changed(&format!("{} and {last}", rest.join(", ")))),
                }
            }
            (None, None) => Ok(()),
            // Only an unchecked build gets here: a problem file the manifest does not list is
            // refused before the sources are compared.
            (None, Some(_)) => Err(changed("its whole problem, which the build did not have")),
            (Some(_), None) => Err(changed("its whole problem, which the spec no longer has")),
        }
    }

    /// Checks `bytes` read from `path` against the manifest's entry.
    pub fn check(&self, path: &str, bytes: &[u8]) -> Result<(), BuildFolderError> {
        let tampered =
            |reason: String| BuildFolderError::Tampered { file: path.to_string(), reason };
        let Some(entry) = self.files.iter().find(|entry| entry.path == path) else {
            return Err(tampered("the manifest does not list it".to_string()));
        };
        if entry.bytes != bytes.len() as u64 {
            return Err(tampered(format!(
                "it has {} bytes, the manifest says {}",
                bytes.len(),
                entry.bytes
            )));
        }
        let digest = file_digest(bytes).to_string();
        if digest != entry.digest {
            return Err(tampered(format!(
                "its digest is {digest}, the manifest says {}",
                entry.digest
            )));
        }
        Ok(())
    }
}

/// A path as the manifest writes it: relative, with `/` separators.
pub fn slash_path(path: &Path) -> String {
    path.to_string_lossy().replace('\\', "/")
}

/// Whether a manifest path stays inside the model folder (relative, no `..`).
fn is_inside(path: &str) -> bool {
    !path.is_empty()
        && Path::new(path).components().all(|component| matches!(component, Component::Normal(_)))
}

/// The demonstration digest in the provenance comment block at the top of a PDDL artifact.
pub fn pddl_demonstration_digest(text: &str) -> Option<&str> {
    text.lines()
        .take_while(|line| line.starts_with(';'))
        .find_map(|line| line.strip_prefix("; demonstration digest: "))
        .map(str::trim)
}

/// Refuses PDDL artifacts (`(name, text)`) whose provenance names other demonstrations than the
/// sampler file's; a file without a provenance block (edited by hand) is not compared.
pub fn check_same_demonstrations(
    samplers: &SamplersFile,
    pddl: &[(&str, &str)],
) -> Result<(), BuildFolderError> {
    let expected = &samplers.provenance.digest;
    for (name, text) in pddl {
        match pddl_demonstration_digest(text) {
            Some(found) if found != expected => {
                return Err(BuildFolderError::Mismatched {
                    file: crate::model_folder::SAMPLERS_FILE.to_string(),
                    found: expected.clone(),
                    other: (*name).to_string(),
                    expected: found.to_string(),
                });
            }
            _ => {}
        }
    }
    Ok(())
}

/// Why a build folder cannot be solved with: its layout, its manifest, or files that do not match.
#[derive(Debug, Error, Diagnostic)]
pub enum BuildFolderError {
    /// The folder has no model at all.
    #[error(
        "{folder} holds no build (no model/ folder with domain.pddl, problems and samplers.json)"
    )]
    #[diagnostic(
        code(lamp::solve::no_build),
        help("Run `lampc build SPEC` first, or point `--build DIR` at the folder it wrote.")
    )]
    NoBuild { folder: String },

    /// The folder holds artifacts of the layout before the model folder and the manifest.
    #[error(
        "{folder} holds a build of an older lampc (domain.pddl at the top, no model/ folder and no manifest)"
    )]
    #[diagnostic(
        code(lamp::solve::old_build),
        help("Run `lampc build SPEC` again; it writes the model into `model/` with a manifest.")
    )]
    OldLayout { folder: String },

    /// A build stopped between moving the old model aside and moving the new one in.
    #[error(
        "{folder} holds no model/ folder but what an interrupted `lampc build` left: {leftover}"
    )]
    #[diagnostic(
        code(lamp::solve::interrupted_build),
        help("Run `lampc build SPEC` again; it removes the leftovers and writes a whole model.")
    )]
    Interrupted { folder: String, leftover: String },

    /// The manifest is missing, not JSON, or of another format or version.
    #[error("the build's manifest {file} cannot be used: {reason}")]
    #[diagnostic(
        code(lamp::solve::manifest),
        help("Run `lampc build SPEC` again to write the model folder and its manifest anew.")
    )]
    Manifest { file: String, reason: String },

    /// An artifact the solve needs cannot be read.
    #[error("{file} cannot be read: {reason}")]
    #[diagnostic(
        code(lamp::solve::unreadable_artifact),
        help("Run `lampc build SPEC` again to write the model folder anew.")
    )]
    Unreadable { file: String, reason: String },

    /// An artifact differs from what the build wrote.
    #[error("{file} does not match the build's manifest: {reason}")]
    #[diagnostic(
        code(lamp::solve::tampered),
        help(
            "Run `lampc build SPEC` again to rewrite the model folder; to solve with a file edited by hand on purpose, pass `--unchecked-build`."
        )
    )]
    Tampered { file: String, reason: String },

    /// The problem asked for has no file in the build.
    #[error("the build has no problem file for `{problem}`")]
    #[diagnostic(
        code(lamp::solve::no_problem_file),
        help(
            "`lampc build` skips a problem whose goal it cannot write (its summary says why); run it again if the problem was added to the spec after the build."
        )
    )]
    NoProblemFile { problem: String },

    /// Two artifacts were learned from different demonstrations.
    #[error("{file} was learned from other demonstrations ({found}) than {other} ({expected})")]
    #[diagnostic(
        code(lamp::solve::mismatched_build),
        help(
            "Run `lampc build SPEC` again so that every artifact comes from the same demonstrations."
        )
    )]
    Mismatched { file: String, found: String, other: String, expected: String },

    /// The build was made for another spec's domain.
    #[error(
        "the build folder was built for domain `{found}`, but the spec's domain is `{expected}`"
    )]
    #[diagnostic(
        code(lamp::solve::other_domain),
        help(
            "Point `--build DIR` at this spec's build folder, or run `lampc build` on this spec."
        )
    )]
    OtherDomain { found: String, expected: String },

    /// The spec's robots, object types, demonstration sources, learning settings or seed, or a
    /// robot model or mesh file it names, changed since the build.
    #[error(
        "the build is stale: {spec}'s seed, robots, object types, demonstration sources or learning settings, or a robot model or mesh file it names, changed since it was built"
    )]
    #[diagnostic(
        code(lamp::solve::stale_build),
        help(
            "Run `lampc build SPEC` again to learn the model from the spec as it is now. A build made by another version of lampc, which may read the same spec otherwise, is refused the same way."
        )
    )]
    SpecChanged { spec: String },

    /// The problem's scene or goal, a relation alias or a structure changed since the build;
    /// `parts` says which.
    #[error(
        "problem `{problem}` changed in {spec} since the build ({parts}): its problem file answers the old one"
    )]
    #[diagnostic(
        code(lamp::solve::changed_problem),
        help(
            "Run `lampc build SPEC` again to write the problem files from the spec as it is now."
        )
    )]
    ProblemChanged { problem: String, spec: String, parts: String },
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::digest::Digest;
    use crate::spec_sources::ProblemSources;

    fn provenance(digest: u64) -> Provenance {
        Provenance::new("packing.lamp", "packing", 1, 3, Digest(digest))
    }

    fn sources(problem_digest: &str) -> SpecSources {
        with_goal(problem_digest, "goal")
    }

    fn with_goal(scene: &str, goal: &str) -> SpecSources {
        let problem = ProblemSources {
            scene: scene.to_string(),
            goal: goal.to_string(),
            aliases: "aliases".to_string(),
            structures: "structures".to_string(),
        };
        SpecSources {
            model: "fnv1a64:0000000000000001".to_string(),
            problems: [("p1".to_string(), problem)].into(),
        }
    }

    fn files() -> Vec<ArtifactFile> {
        vec![
            ArtifactFile { path: "problems/p1.pddl".into(), contents: "(problem)".into() },
            ArtifactFile { path: "domain.pddl".into(), contents: "(domain)".into() },
        ]
    }

    #[test]
    fn lists_every_file_by_path_with_length_and_digest_and_reads_back() {
        let manifest = Manifest::new(&provenance(7), &sources("p1"), &files());
        let paths: Vec<&str> = manifest.files.iter().map(|entry| entry.path.as_str()).collect();
        assert_eq!(paths, ["domain.pddl", "problems/p1.pddl"]);
        assert_eq!(manifest.files[0].bytes, 8);
        assert_eq!(manifest.files[0].digest, file_digest(b"(domain)").to_string());
        let text = manifest.to_json().expect("serialises");
        assert!(text.contains("\"digest\": \"fnv1a64\""), "the algorithm is named: {text}");
        assert_eq!(Manifest::from_json(&text, "manifest.json").expect("reads back"), manifest);
        assert!(manifest.check("domain.pddl", b"(domain)").is_ok());
    }

    #[test]
    fn an_edited_truncated_or_unlisted_file_is_tampered_and_named() {
        let manifest = Manifest::new(&provenance(7), &sources("p1"), &files());
        for (path, bytes, reason) in [
            ("domain.pddl", &b"(domaiN)"[..], "its digest is fnv1a64:"),
            ("domain.pddl", b"(dom", "it has 4 bytes, the manifest says 8"),
            ("problems/p2.pddl", b"(problem)", "the manifest does not list it"),
        ] {
            let error = manifest.check(path, bytes).expect_err("refused");
            let message = error.to_string();
            assert!(message.starts_with(&format!("{path} does not match")), "{message}");
            assert!(message.contains(reason), "{message}");
            let code = miette::Diagnostic::code(&error).map(|code| code.to_string());
            assert_eq!(code.as_deref(), Some("lamp::solve::tampered"));
        }
    }

    #[test]
    fn refuses_another_format_version_algorithm_or_a_path_outside() {
        let manifest = Manifest::new(&provenance(7), &sources("p1"), &files());
        let text = manifest.to_json().expect("serialises");
        for (edited, reason) in [
            (text.replace(MANIFEST_FORMAT, "other"), "its format is `other`"),
            (
                text.replace(&format!("\"version\": {MANIFEST_VERSION}"), "\"version\": 9"),
                "version 9",
            ),
            (text.replace("\"digest\": \"fnv1a64\"", "\"digest\": \"md5\""), "`md5`"),
            (text.replace("problems/p1.pddl", "../p1.pddl"), "outside the model folder"),
            ("{".to_string(), "EOF"),
        ] {
            let error = Manifest::from_json(&edited, "m.json").expect_err("refused");
            assert!(error.to_string().contains(reason), "{error}");
        }
    }

    #[test]
    fn a_spec_or_problem_changed_since_the_build_is_named() {
        let manifest = Manifest::new(&provenance(7), &sources("p1"), &files());
        assert!(manifest.check_sources(&sources("p1"), "p1").is_ok());
        let code = |error: &BuildFolderError| {
            miette::Diagnostic::code(error).map(|code| code.to_string()).unwrap_or_default()
        };
        let changed = manifest.check_sources(&sources("edited"), "p1").expect_err("refused");
        assert_eq!(code(&changed), "lamp::solve::changed_problem");
        assert!(
            changed
                .to_string()
                .starts_with("problem `p1` changed in packing.lamp since the build (its scene):"),
            "{changed}"
        );
        // Which parts changed is said, so that a user knows which edit the build has not seen.
        let goal = manifest.check_sources(&with_goal("p1", "trimmed"), "p1").expect_err("refused");
        assert!(goal.to_string().contains("since the build (its goal):"), "{goal}");
        let mut all = with_goal("edited", "trimmed");
        let problem = all.problems.get_mut("p1").expect("p1");
        problem.aliases = "renamed".to_string();
        let three = manifest.check_sources(&all, "p1").expect_err("refused");
        assert!(
            three.to_string().contains("(its scene, its goal and the relation aliases)"),
            "{three}"
        );
        let relearn =
            SpecSources { model: "fnv1a64:0000000000000002".to_string(), ..sources("p1") };
        let stale = manifest.check_sources(&relearn, "p1").expect_err("refused");
        assert_eq!(code(&stale), "lamp::solve::stale_build");
    }

    #[test]
    fn pddl_from_other_demonstrations_than_the_samplers_is_refused() {
        let artifact = lamp_abstraction::SamplerArtifact {
            version: lamp_abstraction::SAMPLER_ARTIFACT_VERSION,
            seed: 1,
            pairs: Vec::new(),
        };
        let samplers = SamplersFile::new(provenance(1), artifact);
        let same = provenance(1).pddl_comment() + "(define)";
        let other = provenance(2).pddl_comment() + "(define)";
        assert_eq!(pddl_demonstration_digest(&same), Some("fnv1a64:0000000000000001"));
        assert!(check_same_demonstrations(&samplers, &[("domain.pddl", &same)]).is_ok());
        assert!(check_same_demonstrations(&samplers, &[("domain.pddl", "(define)")]).is_ok());
        let error =
            check_same_demonstrations(&samplers, &[("domain.pddl", &other)]).expect_err("refused");
        assert_eq!(
            error.to_string(),
            "samplers.json was learned from other demonstrations (fnv1a64:0000000000000001) than \
             domain.pddl (fnv1a64:0000000000000002)"
        );
    }
}
