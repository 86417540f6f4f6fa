//! The build pipeline as values: demonstration files → demonstrations → model → every artifact's
//! text, with a summary. Nothing here touches the file system; the caller writes the artifacts.
//!
//! The stages are separate functions so that a front end can show progress between them:
//! [`Adapter::demonstration`] per file, [`learn_model`], then [`artifacts`]; [`build`] runs them all.

use std::collections::BTreeMap;
use std::path::PathBuf;

use lamp_learn::{Demonstration, Model};
use lamp_spec::Spec;
use lamp_world::SpecWorld;

use crate::adapter::Adapter;
use crate::aliases::resolve_aliases;
use crate::config::learn_config;
use crate::digest::{Digest, demonstration_digest};
use crate::error::BuildError;
use crate::goal_warning::GoalWarning;
use crate::grasps::{GrabDistanceWarning, grasps_outside_grab_distance};
use crate::initial_scene::check_initial_scenes;
use crate::input::DemoFile;
use crate::manifest::{MANIFEST_FILE, Manifest};
use crate::problems::{ProblemContext, ProblemOutcome, problem_pddl};
use crate::provenance::Provenance;
use crate::samplers::SamplersFile;
use crate::shapes::SpecShapes;
use crate::spec_sources::SpecSources;

pub use crate::model_folder::{
    ArtifactFile, DOMAIN_FILE, FAILED_DIR, MODEL_DIR, MODEL_FILE_LIMIT, PROBLEMS_DIR,
    SAMPLERS_FILE, VOCABULARY_FILE,
};

/// What a build learned and wrote, for the front end to report.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Summary {
    /// Demonstrations learned from.
    pub demonstrations: usize,
    /// Time steps over all demonstrations.
    pub steps: usize,
    /// Learned regions over all type pairs.
    pub regions: usize,
    /// Predicates of the domain (region, `_0` and clear relations).
    pub relations: usize,
    /// Induced actions.
    pub actions: usize,
    /// Type pairs seen in demonstrations without any region, as `primary_secondary`.
    pub pairs_without_regions: Vec<String>,
    /// Alias → the learned relation it was bound to, by alias name.
    pub aliases: BTreeMap<String, String>,
    /// Problems written, in spec order.
    pub problems_written: Vec<String>,
    /// Problems not written, with the reason, in spec order.
    pub problems_skipped: Vec<(String, String)>,
    /// Warnings about the goals of written problems, in spec order.
    pub warnings: Vec<GoalWarning>,
    /// Robots whose `grab distance` some recorded grasp lies outside, in spec order.
    pub grab_warnings: Vec<GrabDistanceWarning>,
    /// The demonstration digest.
    pub digest: String,
}

/// Every artifact in memory, and the summary.
#[derive(Debug, Clone, PartialEq)]
pub struct Artifacts {
    /// Every artifact by path, the manifest of all the others included.
    pub files: Vec<ArtifactFile>,
    pub summary: Summary,
}

/// What the artifacts are built for: the checked spec, its file name and its loaded world.
pub struct BuildContext<'a> {
    pub spec: &'a Spec,
    /// The spec's file name (e.g. `packing.lamp`), written into provenance.
    pub spec_file: &'a str,
    pub world: &'a SpecWorld,
    pub adapter: &'a Adapter,
    /// The largest model file written ([`MODEL_FILE_LIMIT`] for a solve to read it): a problem
    /// whose PDDL is larger is skipped, saying why.
    pub model_file_limit: u64,
}

/// Learns a model from demonstrations with the spec's settings and seed; the world's object shapes decide the
/// `auto` clear and nowhere relations.
pub fn learn_model(
    spec: &Spec,
    world: &SpecWorld,
    demonstrations: &[Demonstration],
) -> Result<Model, BuildError> {
    Ok(lamp_learn::learn(demonstrations, &learning(spec, world), &SpecShapes::new(world))?)
}

/// The learning configuration of a spec: its settings, and its shapes' turns.
fn learning(spec: &Spec, world: &SpecWorld) -> lamp_learn::LearnConfig {
    let mut config = learn_config(spec);
    config.symmetries = shape_symmetries(spec, world);
    config.symmetry_from_data = spec.learning.symmetry != Some(lamp_spec::Switch::On);
    config
}

/// Unless `symmetry off`, the turns about each object type's vertical axis (its frame's z, up as
/// the type is declared) that map its shape onto itself (lamp-geometry's `upright_symmetries`);
/// none with it.
fn shape_symmetries(
    spec: &Spec,
    world: &SpecWorld,
) -> std::collections::BTreeMap<String, Vec<nalgebra::UnitQuaternion<f64>>> {
    if spec.learning.symmetry == Some(lamp_spec::Switch::Off) {
        return std::collections::BTreeMap::new();
    }
    world
        .type_parts
        .iter()
        .map(|(name, parts)| (name.clone(), lamp_geometry::upright_symmetries(parts)))
        .filter(|(_, turns)| turns.len() > 1)
        .collect()
}

/// Every artifact of a learned model.
pub fn artifacts(
    context: &BuildContext<'_>,
    model: &Model,
    demonstrations: &[Demonstration],
    digest: Digest,
) -> Result<Artifacts, BuildError> {
    let spec = context.spec;
    let provenance = provenance(context, demonstrations, digest);
    let domain = lamp_learn::domain(model, &spec.domain)?;
    let domain_text = format!("{}{}", provenance.pddl_comment(), lamp_pddl::write_domain(&domain));
    let aliases = resolve_aliases(model, &spec.relation_aliases, &learning(spec, context.world))?;
    let header = provenance.lines();
    let problem_context = ProblemContext {
        model,
        domain: &domain,
        world: context.world,
        adapter: context.adapter,
        aliases: &aliases,
        header: &header,
    };
    let mut summary = Summary {
        demonstrations: demonstrations.len(),
        steps: demonstrations.iter().map(|demonstration| demonstration.steps.len()).sum(),
        regions: model.pairs.iter().map(|pair| pair.regions.len()).sum(),
        relations: domain.predicates.len(),
        actions: domain.actions.len(),
        pairs_without_regions: model.pairs_without_regions.iter().map(|pair| pair.stem()).collect(),
        aliases: aliases
            .iter()
            .map(|(name, resolved)| (name.clone(), resolved.relation.clone()))
            .collect(),
        digest: provenance.digest.clone(),
        grab_warnings: grasps_outside_grab_distance(spec, demonstrations),
        ..Summary::default()
    };
    let mut files = vec![ArtifactFile { path: DOMAIN_FILE.into(), contents: domain_text }];
    let mut structure_issues = Vec::new();
    let mut refused = 0;
    for problem in &spec.problems {
        match problem_pddl(&problem_context, problem)? {
            ProblemOutcome::Written { name, text, .. }
                if text.len() as u64 > context.model_file_limit =>
            {
                let reason = too_large(text.len() as u64, context.model_file_limit);
                summary.problems_skipped.push((name, reason));
            }
            ProblemOutcome::Written { name, text, warnings } => {
                files.push(ArtifactFile {
                    path: PathBuf::from(PROBLEMS_DIR).join(format!("{name}.pddl")),
                    contents: text,
                });
                summary.warnings.extend(warnings);
                summary.problems_written.push(name);
            }
            ProblemOutcome::Skipped { name, reason } => {
                summary.problems_skipped.push((name, reason))
            }
            ProblemOutcome::Refused { issues, .. } => {
                refused += 1;
                structure_issues.extend(issues);
            }
        }
    }
    if !structure_issues.is_empty() {
        return Err(BuildError::Structures { problems: refused, issues: structure_issues });
    }
    let samplers = SamplersFile::new(provenance.clone(), model.sampler_artifact());
    files.push(ArtifactFile { path: SAMPLERS_FILE.into(), contents: samplers.to_json()? });
    let plots = crate::region_plots::region_plots(model, context.world, spec.seed);
    files.push(ArtifactFile {
        path: VOCABULARY_FILE.into(),
        contents: vocabulary(&provenance, model, &plots),
    });
    files.extend(plots);
    let manifest = Manifest::new(&provenance, &SpecSources::of(spec, context.world), &files);
    files.push(ArtifactFile { path: MANIFEST_FILE.into(), contents: manifest.to_json()? });
    files.sort_by(|a, b| a.path.cmp(&b.path));
    Ok(Artifacts { files, summary })
}

/// The vocabulary report of a learned model, with its provenance, for a build whose artifacts
/// could not be written ([`artifacts`] failed on an alias or a goal): what the demonstrations
/// taught, so that the user can see why (region pictures are left out).
pub fn learned_vocabulary(
    context: &BuildContext<'_>,
    model: &Model,
    demonstrations: &[Demonstration],
    digest: Digest,
) -> String {
    vocabulary(&provenance(context, demonstrations, digest), model, &[])
}

/// Where a model comes from: the spec, its domain and seed, and the demonstrations read.
fn provenance(
    context: &BuildContext<'_>,
    demonstrations: &[Demonstration],
    digest: Digest,
) -> Provenance {
    let spec = context.spec;
    Provenance::new(context.spec_file, &spec.domain, spec.seed, demonstrations.len(), digest)
}

/// Why a problem of `size` bytes is not written when model files may be `limit` bytes: a solve
/// would refuse to read it.
fn too_large(size: u64, limit: u64) -> String {
    format!(
        "its PDDL would be {size} bytes, more than the {limit} a solve reads; split it into \
         problems of fewer objects"
    )
}

/// The vocabulary report with the provenance under its title.
fn vocabulary(provenance: &Provenance, model: &Model, plots: &[ArtifactFile]) -> String {
    let mut report = lamp_learn::vocabulary_report(model);
    if !plots.is_empty() {
        report.truncate(report.trim_end().len());
        report.push_str("\n\n## Region pictures\n\nSamples of every region in the primary's frame, top and side views.\n\n");
        for plot in plots {
            let path = plot.path.to_string_lossy().replace('\\', "/");
            let stem =
                plot.path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            report.push_str(&format!("![{stem}]({path})\n\n"));
        }
        report.truncate(report.trim_end().len());
        report.push('\n');
    }
    let lines = provenance.lines();
    let mut block = String::new();
    for (index, line) in lines.iter().enumerate() {
        match index {
            0 => block.push_str(&format!("> {line}\n>\n")),
            _ => block.push_str(&format!("> - {line}\n")),
        }
    }
    match report.split_once("\n\n") {
        Some((title, rest)) if title.starts_with("# ") => format!("{title}\n\n{block}\n{rest}"),
        _ => format!("{block}\n{report}"),
    }
}

/// The whole pipeline on files in memory: files are taken in name order.
pub fn build(
    spec: &Spec,
    spec_file: &str,
    world: &SpecWorld,
    files: &[DemoFile],
) -> Result<(Model, Artifacts), BuildError> {
    let adapter = Adapter::new(spec, &world.robots)?;
    check_initial_scenes(spec, world)?;
    let mut sorted: Vec<&DemoFile> = files.iter().collect();
    sorted.sort_by(|a, b| a.name.cmp(&b.name));
    let demonstrations =
        sorted.iter().map(|file| adapter.demonstration(file)).collect::<Result<Vec<_>, _>>()?;
    if demonstrations.is_empty() {
        return Err(BuildError::NoDemonstrations { searched: "the given files".into() });
    }
    let model = learn_model(spec, world, &demonstrations)?;
    let context = BuildContext {
        spec,
        spec_file,
        world,
        adapter: &adapter,
        model_file_limit: MODEL_FILE_LIMIT,
    };
    let artifacts = artifacts(&context, &model, &demonstrations, demonstration_digest(files))?;
    Ok((model, artifacts))
}
