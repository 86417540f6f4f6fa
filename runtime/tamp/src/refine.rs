//! Refining one symbolic plan: actions in order, each from its refiner stream, with chronological
//! backtracking — when step i has no candidate left, step i − 1 takes its next one.
//!
//! A candidate is kept when the step's effects hold in the state it reaches and the rest of the
//! plan still runs from that state to the goal (execution monitoring). The state need not be the
//! one the plan predicted: a learned action says what it changes, not everything that changes
//! with it (lifting a can off a table happens while the arm tucks; the tuck action does not say
//! so), and such a side effect is harmless unless a later step or the goal needs what it undid.

use std::collections::BTreeSet;

use lamp_learn::GroundAtom;
use lamp_plugin_api::{CandidateStream, GroundedAction, PluginError, RefineRequest};
use lamp_world::{Recorder, Scene};

use crate::Context;
use crate::error::SolveError;
use crate::execute::{MotionCounts, Rejection, execute};
use crate::ground::{effects_hold, first_broken};
use crate::host::SceneHost;
use crate::plugins::Plugins;
use crate::state::{abstraction, world_state};

/// One level of the backtracking stack: the state before a step and the step's stream.
struct Level {
    scene: Scene,
    recorded: usize,
    stream: Box<dyn CandidateStream>,
}

/// The counts of one refinement.
#[derive(Clone, Debug, Default)]
pub struct RefineCounts {
    pub candidates: usize,
    pub backtracks: usize,
    pub deepest: usize,
    pub motion: MotionCounts,
    pub last_failure: String,
}

/// How one plan's refinement ended.
pub enum Refined {
    /// Every step refined; the recorder holds the whole trajectory and this is the final scene.
    Done(Scene),
    /// The streams ran dry or the candidate budget ran out.
    Failed,
}

/// Refines `actions` from `initial` so that they reach `goal`, recording into `recorder`.
#[allow(clippy::too_many_arguments)] // the loop's inputs are distinct and all needed
pub fn refine_plan(
    context: &Context<'_>,
    plugins: &mut Plugins<'_>,
    initial: &Scene,
    actions: &[GroundedAction],
    goal: &BTreeSet<GroundAtom>,
    seed: u64,
    recorder: &mut Recorder,
    counts: &mut RefineCounts,
) -> Result<Refined, SolveError> {
    let start_len = recorder.len();
    let budget_end = counts.candidates + context.settings.max_candidates;
    let mut levels: Vec<Level> = Vec::new();
    let mut scene = initial.clone();
    while levels.len() <= actions.len() {
        let index = levels.len();
        if index == actions.len() {
            return Ok(Refined::Done(scene));
        }
        if (context.cancelled)() {
            return Err(SolveError::Cancelled);
        }
        let stream_seed = mix(seed, index as u64, counts.candidates as u64);
        let request = RefineRequest {
            action: actions[index].clone(),
            world: world_state(context.adapter, &scene)?,
            seed: stream_seed,
        };
        let host = SceneHost::new(&scene, stream_seed);
        let stream = plugins.refiner.refine(&request, &host).map_err(plugin_error)?;
        levels.push(Level { scene: scene.clone(), recorded: recorder.len(), stream });
        counts.deepest = counts.deepest.max(index + 1);
        // Find a candidate for the top level, backtracking while levels run dry.
        loop {
            let at = levels.len().wrapping_sub(1);
            let Some(level) = levels.last_mut() else {
                recorder.steps.truncate(start_len);
                return Ok(Refined::Failed);
            };
            if counts.candidates >= budget_end {
                recorder.steps.truncate(start_len);
                return Ok(Refined::Failed);
            }
            let host = SceneHost::new(&level.scene, mix(seed, at as u64, counts.candidates as u64));
            let next = level.stream.next(&host).map_err(plugin_error)?;
            let Some(candidate) = next else {
                levels.pop();
                counts.backtracks += 1;
                continue;
            };
            counts.candidates += 1;
            let mut trial = level.scene.clone();
            recorder.steps.truncate(level.recorded);
            let attempt = execute(
                &mut trial,
                &candidate,
                recorder,
                plugins.motion,
                &context.settings.motion,
                mix(seed, at as u64, counts.candidates as u64 + 7),
                &mut counts.motion,
            );
            match attempt {
                Ok(()) => {
                    let reached = abstraction(context.artifact, context.adapter, &trial)?;
                    let effects = effects_hold(&reached, &actions[at]);
                    let broken = if effects {
                        first_broken(&reached, &actions[at + 1..], goal)
                    } else {
                        None
                    };
                    if effects && broken.is_none() {
                        scene = trial;
                        break;
                    }
                    let why = match broken {
                        None => "its effects do not hold in the state reached".to_string(),
                        Some(broken) => {
                            let what = match actions.get(at + 1 + broken.index) {
                                Some(later) => {
                                    format!("step {} ({})", at + 2 + broken.index, later.name)
                                }
                                None => "the goal".to_string(),
                            };
                            format!(
                                "the state reached breaks {what}, which needs {}",
                                atom_list(&broken.missing)
                            )
                        }
                    };
                    counts.last_failure = format!("step {} ({}): {why}", at + 1, actions[at].name);
                }
                Err(Rejection::Candidate(reason)) => {
                    counts.last_failure =
                        format!("step {} ({}): {reason}", at + 1, actions[at].name);
                }
                Err(Rejection::Fatal(error)) => return Err(error),
            }
            recorder.steps.truncate(level.recorded);
        }
    }
    Ok(Refined::Done(scene))
}

fn plugin_error(error: PluginError) -> SolveError {
    match error {
        PluginError::Cancelled => SolveError::Cancelled,
        other => SolveError::Plugin { kind: "refiner", reason: other.to_string() },
    }
}

/// Atoms in one state and not the other, for messages.
pub fn difference(reached: &BTreeSet<GroundAtom>, expected: &BTreeSet<GroundAtom>) -> String {
    let extra: Vec<String> = reached.difference(expected).map(ToString::to_string).collect();
    let missing: Vec<String> = expected.difference(reached).map(ToString::to_string).collect();
    format!("unexpected: {}; missing: {}", list(&extra), list(&missing))
}

fn atom_list(atoms: &[GroundAtom]) -> String {
    list(&atoms.iter().map(ToString::to_string).collect::<Vec<_>>())
}

fn list(atoms: &[String]) -> String {
    if atoms.is_empty() { "none".to_string() } else { atoms.join(" ") }
}

/// A seed for one stream or motion call, mixed from the run's seed and where it is used
/// (SplitMix64's finaliser, so nearby inputs give unrelated seeds).
pub fn mix(seed: u64, a: u64, b: u64) -> u64 {
    let mut z =
        seed ^ a.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ b.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
