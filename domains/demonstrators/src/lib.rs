//! Simulated demonstrators: scripted skills (approach, grasp, carry, place, retreat) executed
//! with lamp-world's collision-free IK and RRT-Connect, recorded as demonstration files.
//!
//! Pure: a spec's loaded world in, `Trajectory` values or MCAP bytes out; `lampc demos` writes
//! the files. Demonstration `i` draws every random choice from
//! `ChaCha8Rng::seed_from_u64(seed)` with `set_stream(i)` ([`demo_rng`]), so demonstrations are
//! generated in parallel (rayon) and are identical whatever the thread count. Tracking noise,
//! when the spec asks for it, is drawn from a stream of its own per demonstration ([`noise_rng`]).
//! `docs/demonstrations.md` describes what each demonstrator does.

mod cafe;
mod error;
mod jenga;
mod keva;
mod layout;
mod noise;
mod packing;
mod planks;
mod rate;
mod skills;
mod tower;

use std::collections::{BTreeMap, BTreeSet};

use lamp_spec::{DemoSource, Mobility, Spec, TrackingNoise, limits};
use lamp_trajectory::{Step, Trajectory, TrajectoryHeader};
use lamp_world::SpecWorld;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

pub use error::DemoError;
pub use lamp_world::STEP_NANOSECONDS;
pub use noise::noise_rng;

/// Attempts per demonstration before giving up (each with fresh random choices).
pub const MAX_ATTEMPTS: u32 = 25;

/// Most blocks in a Jenga demonstration's scene: the spare ones lie on the table, which has room
/// for a few.
pub const MAX_JENGA_BLOCKS: u32 = 4;

/// Most planks in a Keva demonstration's scene: the training structures use up to three, and
/// the loose ones lie on the table, which has room for a few.
pub const MAX_KEVA_PLANKS: u32 = 4;

/// The demonstrators lamp ships.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Demonstrator {
    /// A free-flying magnetic gripper packs a can into an open box.
    Packing,
    /// A Fetch carries a can between tables and a counter.
    Cafe,
    /// The Café script with every movable type (glasses, bowls), one object per demonstration,
    /// and a marker recorded where the object is put.
    Dinner,
    /// A Fetch arm on a fixed base places one Jenga block of a small tower, the blocks below it
    /// already placed; a marker recorded at each placed block.
    Jenga,
    /// A free-flying two-finger gripper places one Keva plank of a small structure (a pi, a log
    /// cabin layer, an upright on a flat plank), the planks it rests on already placed; a marker
    /// recorded at each placed plank.
    Keva,
}

impl Demonstrator {
    /// The demonstrator called `name` in a spec (`packing`, `cafe`, `dinner`, `jenga`, `keva`).
    pub fn from_name(name: &str) -> Result<Demonstrator, DemoError> {
        match name {
            "packing" => Ok(Demonstrator::Packing),
            "cafe" => Ok(Demonstrator::Cafe),
            "dinner" => Ok(Demonstrator::Dinner),
            "jenga" => Ok(Demonstrator::Jenga),
            "keva" => Ok(Demonstrator::Keva),
            _ => Err(DemoError::UnknownDemonstrator { name: name.to_string() }),
        }
    }

    /// The name a spec uses.
    pub fn name(self) -> &'static str {
        match self {
            Demonstrator::Packing => "packing",
            Demonstrator::Cafe => "cafe",
            Demonstrator::Dinner => "dinner",
            Demonstrator::Jenga => "jenga",
            Demonstrator::Keva => "keva",
        }
    }
}

/// What to simulate: the spec's `simulate` source, possibly overridden by the caller.
#[derive(Clone, Debug, PartialEq)]
pub struct Simulation {
    pub demonstrator: Demonstrator,
    pub count: u32,
    /// Fraction of demonstrations cut short at a random step.
    pub cut_fraction: f64,
    /// Objects of the manipulated type per demonstration (1, except for Jenga and Keva: blocks or
    /// planks in the scene, the training structures using up to three).
    pub objects: u32,
    pub seed: u64,
    /// The tracking noise added to every recorded object pose (none by default).
    pub noise: TrackingNoise,
    /// The recording rate in hertz: the timed motion sampled every 1/rate seconds. `None`: one
    /// step per state of each planned path, [`STEP_NANOSECONDS`] apart.
    pub rate: Option<f64>,
}

impl Simulation {
    /// The first simulated source of `spec`.
    pub fn from_spec(spec: &Spec) -> Result<Simulation, DemoError> {
        spec.demonstrations
            .iter()
            .find_map(|source| match source {
                DemoSource::Simulated {
                    demonstrator,
                    count,
                    cut_fraction,
                    objects,
                    seed,
                    noise,
                    rate,
                    ..
                } => Some(Demonstrator::from_name(demonstrator).map(|demonstrator| Simulation {
                    demonstrator,
                    count: *count,
                    cut_fraction: *cut_fraction,
                    objects: *objects,
                    seed: *seed,
                    noise: *noise,
                    rate: *rate,
                })),
                DemoSource::Files { .. } => None,
            })
            .unwrap_or(Err(DemoError::NoSimulator))
    }
}

/// One generated demonstration.
#[derive(Clone, Debug, PartialEq)]
pub struct Demonstration {
    pub index: u32,
    /// Steps kept when the demonstration was cut short, `None` for a full one.
    pub cut_at: Option<usize>,
    /// Steps up to and including the release: a cut demonstration never goes beyond them.
    pub retreat_at: usize,
    pub trajectory: Trajectory,
}

impl Demonstration {
    /// The MCAP file's bytes.
    pub fn to_bytes(&self) -> Result<Vec<u8>, DemoError> {
        Ok(self.trajectory.to_bytes()?)
    }
}

/// The file name of demonstration `index` of `domain`: `<domain>_<index:04>.mcap`.
pub fn file_name(domain: &str, index: u32) -> String {
    format!("{domain}_{index:04}.mcap")
}

/// The generator of demonstration `index`: seeded with `seed`, on stream `index`.
pub fn demo_rng(seed: u64, index: u32) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(u64::from(index));
    rng
}

/// A full recording before any cut, from one demonstrator attempt.
pub(crate) struct Recording {
    pub(crate) header: TrajectoryHeader,
    pub(crate) steps: Vec<Step>,
    /// Steps up to and including the release.
    pub(crate) retreat_at: usize,
    /// The scene as the script left it: its robots time the motion and carry what they hold
    /// when the recording is resampled at a fixed rate.
    pub(crate) scene: lamp_world::Scene,
}

/// A demonstrator checked against its spec, ready to generate.
enum Prepared<'a> {
    Packing(packing::Packing<'a>),
    // Boxed: the Café demonstrator keeps its furniture and configurations, Packing very little.
    Cafe(Box<cafe::Cafe<'a>>),
    Jenga(Box<jenga::Jenga<'a>>),
    Keva(Box<keva::Keva<'a>>),
}

impl Prepared<'_> {
    fn attempt(&self, seed: u64, rng: &mut ChaCha8Rng) -> Result<Recording, String> {
        match self {
            Prepared::Packing(packing) => packing.attempt(seed, rng),
            Prepared::Cafe(cafe) => cafe.attempt(seed, rng),
            Prepared::Jenga(jenga) => jenga.attempt(seed, rng),
            Prepared::Keva(keva) => keva.attempt(seed, rng),
        }
    }
}

fn prepare<'a>(world: &'a SpecWorld, simulation: &Simulation) -> Result<Prepared<'a>, DemoError> {
    let objects_ok = match simulation.demonstrator {
        Demonstrator::Jenga => (1..=MAX_JENGA_BLOCKS).contains(&simulation.objects),
        Demonstrator::Keva => (1..=MAX_KEVA_PLANKS).contains(&simulation.objects),
        _ => simulation.objects == 1,
    };
    if !objects_ok {
        return Err(DemoError::Unsupported {
            demonstrator: simulation.demonstrator.name().to_string(),
            reason: format!(
                "`objects {}`: this demonstrator moves exactly one object (Jenga: 1 to {MAX_JENGA_BLOCKS} blocks in the scene, Keva: 1 to {MAX_KEVA_PLANKS} planks)",
                simulation.objects
            ),
        });
    }
    if !(0.0..=1.0).contains(&simulation.cut_fraction) {
        return Err(DemoError::Unsupported {
            demonstrator: simulation.demonstrator.name().to_string(),
            reason: format!("cut fraction {} is not within 0..1", simulation.cut_fraction),
        });
    }
    // The spec checker refuses these already; a caller that builds a `Simulation` by hand gets
    // the same bounds as a typed error.
    let position = limits::NOISE_POSITION.check(simulation.noise.position);
    let rotation = limits::NOISE_ROTATION.check(simulation.noise.rotation);
    let dropped = limits::DROPPED_POSES.check(simulation.noise.dropped);
    if let Err(error) = position.and(rotation).and(dropped) {
        return Err(DemoError::Unsupported {
            demonstrator: simulation.demonstrator.name().to_string(),
            reason: format!("tracking noise: {error}"),
        });
    }
    if let Some(rate) = simulation.rate
        && let Err(error) = limits::RECORDING_RATE.check(rate)
    {
        return Err(DemoError::Unsupported {
            demonstrator: simulation.demonstrator.name().to_string(),
            reason: format!("recording rate: {error}"),
        });
    }
    Ok(match simulation.demonstrator {
        Demonstrator::Packing => Prepared::Packing(packing::Packing::new(world)?),
        Demonstrator::Cafe | Demonstrator::Dinner => {
            Prepared::Cafe(Box::new(cafe::Cafe::new(world)?))
        }
        Demonstrator::Jenga => {
            Prepared::Jenga(Box::new(jenga::Jenga::new(world, simulation.objects)?))
        }
        Demonstrator::Keva => Prepared::Keva(Box::new(keva::Keva::new(world, simulation.objects)?)),
    })
}

/// Generates demonstration `index` of `simulation` in `world`.
pub fn generate(
    world: &SpecWorld,
    simulation: &Simulation,
    index: u32,
) -> Result<Demonstration, DemoError> {
    let prepared = prepare(world, simulation)?;
    generate_prepared(&prepared, &untracked_types(world.spec()), simulation, index)
}

/// Generates every demonstration of `simulation` on rayon's pool, calling `done` after each
/// (in completion order, for progress); the result is in index order.
pub fn generate_all(
    world: &SpecWorld,
    simulation: &Simulation,
    done: impl Fn(&Demonstration) + Sync,
) -> Result<Vec<Demonstration>, DemoError> {
    let prepared = prepare(world, simulation)?;
    let untracked = untracked_types(world.spec());
    (0..simulation.count)
        .into_par_iter()
        .map(|index| {
            let demonstration = generate_prepared(&prepared, &untracked, simulation, index)?;
            done(&demonstration);
            Ok(demonstration)
        })
        .collect()
}

/// The types no tracking system measures: markers, poses with no body that the demonstrator
/// records where it put something.
fn untracked_types(spec: &Spec) -> BTreeSet<String> {
    spec.object_types
        .iter()
        .filter(|ty| ty.mobility == Mobility::Marker)
        .map(|ty| ty.name.clone())
        .collect()
}

fn generate_prepared(
    prepared: &Prepared<'_>,
    untracked: &BTreeSet<String>,
    simulation: &Simulation,
    index: u32,
) -> Result<Demonstration, DemoError> {
    let mut rng = demo_rng(simulation.seed, index);
    // Drawn first, so that whether and where a demonstration is cut does not depend on how many
    // attempts its layout took.
    let cut = rng.random::<f64>() < simulation.cut_fraction;
    let cut_position: f64 = rng.random();
    let mut last = String::new();
    for _ in 0..MAX_ATTEMPTS {
        match prepared.attempt(simulation.seed, &mut rng) {
            Ok(recording) => {
                let recording = match simulation.rate {
                    None => recording,
                    Some(rate) => match at_rate(recording, rate) {
                        Ok(recording) => recording,
                        Err(reason) => {
                            last = reason;
                            continue;
                        }
                    },
                };
                let mut demonstration =
                    finish(recording, simulation, index, cut.then_some(cut_position));
                let trajectory = &mut demonstration.trajectory;
                let mut noise = noise_rng(simulation.seed, index);
                let mut drops = noise::drop_rng(simulation.seed, index);
                noise::perturb(
                    &mut trajectory.steps,
                    &trajectory.header,
                    untracked,
                    simulation.noise,
                    &mut noise,
                    &mut drops,
                );
                return Ok(demonstration);
            }
            Err(reason) => last = reason,
        }
    }
    Err(DemoError::AttemptsExhausted { index, attempts: MAX_ATTEMPTS, last })
}

/// The recording resampled at `rate` hertz (`rate.rs`).
fn at_rate(recording: Recording, rate: f64) -> Result<Recording, String> {
    let Recording { header, steps, retreat_at, scene } = recording;
    let (steps, retreat_at) = rate::resample(&steps, &scene, rate, retreat_at.saturating_sub(1))
        .map_err(|error| format!("timing the recording: {error}"))?;
    Ok(Recording { header, steps, retreat_at, scene })
}

/// Applies the cut (keeping `1 + ⌊u·retreat_at⌋` steps, so never the retreat) and the provenance.
fn finish(
    recording: Recording,
    simulation: &Simulation,
    index: u32,
    cut: Option<f64>,
) -> Demonstration {
    let Recording { mut header, mut steps, retreat_at, .. } = recording;
    let cut_at = cut.map(|u| {
        // Truncation is the point: a uniform step index among the first `retreat_at`.
        let kept = 1 + (u * retreat_at as f64).floor() as usize;
        kept.min(retreat_at)
    });
    if let Some(kept) = cut_at {
        steps.truncate(kept);
    }
    let mut provenance = BTreeMap::new();
    provenance.insert("demonstrator".to_string(), simulation.demonstrator.name().to_string());
    provenance.insert("demo_index".to_string(), index.to_string());
    provenance.insert("seed".to_string(), simulation.seed.to_string());
    provenance
        .insert("cut_at".to_string(), cut_at.map_or_else(|| "none".to_string(), |k| k.to_string()));
    provenance.insert("retreat_at".to_string(), retreat_at.to_string());
    // Only with noise, so that a noise-free file is byte for byte what it was before the option.
    let noise = simulation.noise;
    if noise.position != 0.0 || noise.rotation != 0.0 {
        provenance.insert(
            "tracking_noise".to_string(),
            format!("{} m {} rad", noise.position, noise.rotation),
        );
    }
    if noise.dropped != 0.0 {
        provenance.insert("dropped_poses".to_string(), noise.dropped.to_string());
    }
    // Only at a fixed rate, so that a file recorded as before is byte for byte what it was.
    if let Some(rate) = simulation.rate {
        provenance.insert("recording_rate".to_string(), format!("{rate} Hz"));
    }
    header.provenance = provenance;
    Demonstration { index, cut_at, retreat_at, trajectory: Trajectory { header, steps } }
}
