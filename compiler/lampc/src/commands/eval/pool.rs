//! The demonstration pool of an evaluation: every file of the spec's demonstration source, topped
//! up with simulated demonstrations when the largest count needs more, read once into memory
//! with what the subset draw needs to know of each (cut or full, objects shown).

use std::collections::BTreeSet;
use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use lamp_build::{Adapter, DemoFile};
use lamp_demonstrators::{Simulation, file_name};
use lamp_eval::PoolDemo;
use lamp_learn::Demonstration;
use lamp_spec::{DemoSource, Mobility, Spec};
use lamp_trajectory::TrajectoryHeader;
use lamp_world::SpecWorld;

use super::error::EvaluationError;
use crate::commands::Failure;

/// The provenance key of a simulated demonstration's cut (`none` for a full one).
const CUT_KEY: &str = "cut_at";

/// Every demonstration of the pool, in file-name order.
pub(super) struct Pool {
    /// The files as read (names relative to the spec's folder).
    pub(super) files: Vec<DemoFile>,
    /// The learner's demonstrations of the files.
    pub(super) demonstrations: Vec<Demonstration>,
    /// What the draw and the generalization factor need of each file.
    pub(super) entries: Vec<PoolDemo>,
    /// Files this evaluation generated.
    pub(super) generated: usize,
}

/// Whether a demonstration file was cut short: its header's `cut_at` provenance names a step.
/// A file without that provenance (recorded elsewhere) counts as a full demonstration.
pub(super) fn is_cut(header: &TrajectoryHeader) -> bool {
    header.provenance.get(CUT_KEY).is_some_and(|value| value != "none")
}

/// The names of the spec's movable object types: what the evaluation counts as objects.
pub(super) fn movable_types(spec: &Spec) -> BTreeSet<&str> {
    spec.object_types
        .iter()
        .filter(|ty| ty.mobility == Mobility::Movable && !ty.world)
        .map(|ty| ty.name.as_str())
        .collect()
}

/// The pool: the spec's demonstration files; when a simulated source has fewer than `wanted`,
/// the missing `<domain>_NNNN.mcap` of indices below `wanted` are generated first, as
/// `lampc demos --count wanted` would make them, into the source's folder.
pub(super) fn gather(
    spec: &Spec,
    spec_dir: &Path,
    build_dir: &Path,
    world: &SpecWorld,
    adapter: &Adapter,
    wanted: Option<usize>,
    show: &dyn Fn(&str),
) -> Result<Pool, Failure> {
    let find = || crate::commands::build::find_demonstrations(spec, spec_dir, build_dir, None);
    let simulated = spec.demonstrations.iter().any(|s| matches!(s, DemoSource::Simulated { .. }));
    let mut generated = 0;
    let found = find();
    let short =
        found.as_ref().map_or(true, |paths| wanted.is_some_and(|wanted| paths.len() < wanted));
    let paths = match wanted {
        // No files yet, or fewer than the largest count: a simulated source is topped up.
        Some(wanted) if short && simulated => {
            let folder = build_dir.join(lamp_build::SIMULATED_DEMOS_DIR);
            generated = generate_missing(spec, world, &folder, wanted, show)?;
            find()?
        }
        _ => found?,
    };
    let movable = movable_types(spec);
    let mut pool = Pool {
        files: Vec::with_capacity(paths.len()),
        demonstrations: Vec::with_capacity(paths.len()),
        entries: Vec::with_capacity(paths.len()),
        generated,
    };
    let mut bags = crate::commands::build::BagMappings::new(spec, spec_dir, None);
    for path in &paths {
        let name = lamp_build::demo_name(path, spec_dir);
        let limit = crate::files::DEMONSTRATION_FILE_LIMIT;
        let bytes =
            crate::files::read_limited(path, limit, "demonstration file").map_err(|error| {
                Failure::Message(format!("cannot read {}: {error}", path.display()))
            })?;
        let file = bags.read(world, path, DemoFile { name, bytes })?;
        let reader =
            lamp_trajectory::TrajectoryReader::from_bytes(&file.bytes, file.name.as_str())?;
        let header = reader.header();
        let objects =
            header.bodies.iter().filter(|body| movable.contains(body.type_name.as_str())).count();
        pool.entries.push(PoolDemo { name: file.name.clone(), cut: is_cut(header), objects });
        pool.demonstrations.push(adapter.demonstration(&file)?);
        pool.files.push(file);
    }
    bags.check().map_err(|(_, error)| error)?;
    Ok(pool)
}

/// Generates the simulated demonstrations of indices below `wanted` that `folder` lacks, on
/// every core (a demonstration depends only on the seed and its index), and writes each through
/// a temporary file renamed into place. Returns how many it wrote.
fn generate_missing(
    spec: &Spec,
    world: &SpecWorld,
    folder: &Path,
    wanted: usize,
    show: &dyn Fn(&str),
) -> Result<usize, Failure> {
    let mut simulation = Simulation::from_spec(spec)?;
    simulation.count =
        u32::try_from(wanted).map_err(|_| EvaluationError::TooManyDemonstrations { wanted })?;
    let missing: Vec<u32> = (0..simulation.count)
        .filter(|&index| !folder.join(file_name(&spec.domain, index)).is_file())
        .collect();
    show(&format!(
        "generating {} {} demonstration(s) into {}",
        missing.len(),
        simulation.demonstrator.name(),
        folder.display()
    ));
    // Held while files are added: a `lampc demos` into the same folder must not replace it
    // meanwhile.
    let _lock = crate::output::OutputFolder::new(folder).and_then(|demos| demos.lock("eval"))?;
    std::fs::create_dir_all(folder)
        .map_err(|error| EvaluationError::io("create", folder, error))?;
    let next = AtomicUsize::new(0);
    let failure: Mutex<Option<Failure>> = Mutex::new(None);
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    std::thread::scope(|scope| {
        for _ in 0..threads {
            scope.spawn(|| {
                loop {
                    let slot = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&index) = missing.get(slot) else { return };
                    // The same bytes `lampc demos` writes, standard channels included.
                    let written = lamp_demonstrators::generate(world, &simulation, index)
                        .map_err(Failure::from)
                        .and_then(|demonstration| {
                            let trajectory = &demonstration.trajectory;
                            crate::viewable::mcap_bytes(world, trajectory, None)
                                .map_err(Failure::Report)
                        })
                        .and_then(|bytes| {
                            let name = file_name(&spec.domain, index);
                            Ok(write_file(folder, &name, &bytes)?)
                        });
                    if let Err(error) = written {
                        let mut failure = failure.lock().unwrap_or_else(|p| p.into_inner());
                        failure.get_or_insert(error);
                        next.store(missing.len(), Ordering::Relaxed);
                        return;
                    }
                }
            });
        }
    });
    match failure.into_inner().unwrap_or_else(|p| p.into_inner()) {
        Some(error) => Err(error),
        None => Ok(missing.len()),
    }
}

/// Writes through a temporary file renamed into place, so a file is never seen half written.
fn write_file(folder: &Path, name: &str, contents: &[u8]) -> Result<(), EvaluationError> {
    let path = folder.join(name);
    let temporary = folder.join(format!(".{name}.tmp"));
    std::fs::write(&temporary, contents)
        .map_err(|error| EvaluationError::io("write", &temporary, error))?;
    std::fs::rename(&temporary, &path).map_err(|error| {
        let _ = std::fs::remove_file(&temporary);
        EvaluationError::Io {
            action: "move into place",
            path: temporary.clone(),
            error,
            consequence: format!(" (as {})", path.display()),
        }
    })
}
