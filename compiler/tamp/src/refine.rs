//! Refining one symbolic plan: actions in order, each from its refiner stream, with chronological
//! backtracking — when step i has no candidate left, step i − 1 takes its next one.
//!
//! A candidate is kept when the step's effects hold in the state it reaches and the rest of the
//! plan still runs from that state to the goal (execution monitoring). The state need not be the
//! one the plan predicted: a learned action says what it changes, not everything that changes
//! with it (lifting a can off a table happens while the arm tucks; the tuck action does not say
//! so), and such a side effect is harmless unless a later step or the goal needs what it undid.
//! When it does, the planner is asked for a new rest of the plan from the reached state
//! (replanning), and the candidate is kept if there is one; backtracking into that step puts the
//! old rest back.
//!
//! Replanning can loop: a rest whose own step has the same unstated side effect leads back to a
//! state the refinement has already been in. A candidate is refused when the abstract state it
//! reaches is one of the states before the steps refined so far on the current path (a cycle).
//! Reaching a state that was replanned from on another path, after backtracking, is no loop: the
//! continuous state differs, and the rest planned from there before is used again (the planner is
//! deterministic, so asking it again would only cost time).

use std::collections::{BTreeMap, BTreeSet};

use lamp_abstraction::{GroundAtom, SamplerArtifact};
use lamp_geometry::Pose;
use lamp_participants::ParticipantMap;
use lamp_pddl::{Domain, Problem};
use lamp_plugin_api::{Candidate, CandidateStream, GroundedAction, RefineRequest};
use lamp_world::{Recorder, Scene};

use crate::error::SolveError;
use crate::execute::{MotionCounts, Rejection, execute};
use crate::failures::{Cause, DeepestState, FailureLog};
use crate::ground::{Broken, call_text, first_broken, progress, unmet_effects};
use crate::host::SceneHost;
use crate::planning::{Rest, plan_from};
use crate::plugins::Plugins;
use crate::postpone::{self, Order, Postponed};
use crate::settings::SolveSettings;
use crate::state::{abstraction, world_state};
use crate::summary::{ObjectPose, ReplanPoint};
use crate::targets::first_miss_where_reached;

/// What the refinement loop shares.
pub struct Context<'a> {
    /// The domain, and the problem as planned (its goal possibly relaxed), for replanning.
    pub domain: &'a Domain,
    pub problem: &'a Problem,
    pub artifact: &'a SamplerArtifact,
    pub participants: &'a ParticipantMap,
    pub targets: &'a [lamp_spec::AtGoal],
    pub settings: &'a SolveSettings<'a>,
}

/// Wasted candidates a plan may spend per step, once that is more than `max_refused`.
///
/// Giving a plan up starts its refinement again from the first step, so a budget that does not
/// grow with the plan throws away more refined steps the longer the plan is: a 175-step plan
/// given up after 100 wasted candidates has redone its first 100 steps for nothing, while a
/// 19-step one has lost little. Five per step is the rate of the least budget (100) on the
/// 19-step Packing plans it was set for.
pub const WASTED_PER_STEP: usize = 5;

/// The wasted candidates a plan of `steps` steps may spend: `least`, or [`WASTED_PER_STEP`] per
/// step when that is more.
pub fn wasted_budget(least: usize, steps: usize) -> usize {
    least.max(WASTED_PER_STEP * steps)
}

/// One level of the backtracking stack: the state before a step and the step's stream.
struct Level {
    scene: Scene,
    /// The abstract state of `scene`.
    state: BTreeSet<GroundAtom>,
    /// The abstract state the plan's segment predicts before this step: the state its steps
    /// reach in the domain from where the segment starts (the initial state, or the state reached
    /// at the last replan before this step).
    predicted: BTreeSet<GroundAtom>,
    recorded: usize,
    stream: Box<dyn CandidateStream>,
    /// Candidates its stream has offered.
    offered: usize,
    /// Set while a candidate of this level has replaced the steps after it by a replan.
    replaced: Option<Replaced>,
}

/// The steps after a level as they were when it was opened, and the replan that replaced them.
struct Replaced {
    rest: Vec<GroundedAction>,
    point: ReplanPoint,
}

/// The counts of one refinement.
#[derive(Clone, Debug, Default)]
pub struct RefineCounts {
    pub candidates: usize,
    pub backtracks: usize,
    pub replans: usize,
    /// Carries moved later in their plan because their release found nothing to hold the object
    /// up ([`postpone`]).
    pub postponements: usize,
    /// The deepest step reached (1-based), and the length of the plan it was reached in.
    pub deepest: usize,
    pub deepest_of: usize,
    pub motion: MotionCounts,
    /// Why a candidate of the deepest step that failed was refused (the latest such).
    pub deepest_failure: String,
    deepest_failed: usize,
    /// Every refusal, by plan and step, for the failure report.
    pub failures: FailureLog,
    /// The scene the deepest step reached started from, with the step's action.
    pub deepest_state: Option<Box<DeepestState>>,
}

/// How one plan's refinement ended.
pub enum Refined {
    /// Every step refined: the steps (changed by replanning where a side effect broke the rest)
    /// and the final scene; the recorder holds the whole trajectory.
    Done {
        steps: Vec<GroundedAction>,
        scene: Scene,
        /// Per step, the index of the recorded state its motion begins with.
        starts: Vec<usize>,
        /// The replans on the way, in step order.
        replans: Vec<ReplanPoint>,
    },
    /// The streams ran dry or the refusal budget ran out.
    Failed,
}

/// A plan to refine: its grounded `actions` from the scene `initial`, the `goal` they must
/// reach, and the `seed` of its candidate streams.
#[derive(Debug, Clone, Copy)]
pub struct PlanToRefine<'a> {
    pub initial: &'a Scene,
    pub actions: &'a [GroundedAction],
    pub goal: &'a BTreeSet<GroundAtom>,
    pub seed: u64,
}

/// Refines `plan` so that it reaches its goal, recording into `recorder`.
/// The plan is given up after `max_refused` wasted candidates, or [`WASTED_PER_STEP`] per step
/// of a longer plan: refused ones, accepted ones backtracked over, and those whose side effect
/// needed a replan.
pub fn refine_plan(
    context: &Context<'_>,
    plugins: &mut Plugins<'_>,
    plan: &PlanToRefine<'_>,
    recorder: &mut Recorder,
    counts: &mut RefineCounts,
) -> Result<Refined, SolveError> {
    let PlanToRefine { initial, actions, goal, seed } = *plan;
    let start_len = recorder.len();
    counts.failures.start_plan(actions.len());
    let mut search = Search {
        actions: actions.to_vec(),
        levels: Vec::new(),
        refused: 0,
        seed,
        tried: BTreeSet::new(),
        unsupported: BTreeMap::new(),
    };
    let mut rests = Rests::default();
    let mut scene = initial.clone();
    let mut state = abstraction(context.artifact, context.participants, &scene)?;
    let mut predicted = state.clone();
    loop {
        if search.levels.len() == search.actions.len() {
            let starts = search.levels.iter().map(|level| level.recorded).collect();
            let replans = search
                .levels
                .iter_mut()
                .filter_map(|level| level.replaced.take().map(|replaced| replaced.point))
                .collect();
            return Ok(Refined::Done { steps: search.actions, scene, starts, replans });
        }
        if (context.settings.cancelled)() {
            return Err(SolveError::cancelled());
        }
        if search.postpone_unrefined(&scene, &state, goal) {
            counts.postponements += 1;
            continue;
        }
        let before = std::mem::take(&mut state);
        let before_predicted = std::mem::take(&mut predicted);
        search.open_level(
            context,
            plugins,
            &scene,
            (before, before_predicted),
            recorder.len(),
            counts,
        )?;
        loop {
            let Some((at, candidate)) = search.next_candidate(context, counts)? else {
                recorder.truncate(start_len);
                return Ok(Refined::Failed);
            };
            let recorded = search.levels[at].recorded;
            let mut trial = search.levels[at].scene.clone();
            recorder.truncate(recorded);
            let attempt = execute(
                &mut trial,
                &candidate,
                recorder,
                plugins.motion,
                context.settings,
                mix(seed, at as u64, counts.candidates as u64 + 7),
                &mut counts.motion,
            );
            search.refused += 1;
            let verdict = match attempt {
                Ok(()) => {
                    let path: Vec<&BTreeSet<GroundAtom>> =
                        search.levels.iter().map(|level| &level.state).collect();
                    let mut judge = Judge { context, plugins, goal, rests: &mut rests, path };
                    judge.judge(&trial, &search.actions, at, counts)?
                }
                Err(Rejection::Candidate { cause, why }) => Verdict::Refused(cause, why),
                Err(Rejection::Unsupported { object, reason }) => {
                    Verdict::Unsupported { object, reason }
                }
                Err(Rejection::Fatal(error)) => return Err(error),
            };
            let (cause, why) = match verdict {
                Verdict::Accepted(reached) => {
                    search.refused -= 1;
                    predicted = progress(&search.levels[at].predicted, &search.actions[at]);
                    scene = trial;
                    state = reached;
                    break;
                }
                Verdict::Replanned(reached, rest) => {
                    let expected = progress(&search.levels[at].predicted, &search.actions[at]);
                    let point = replan_point(context, at, &expected, &reached, &trial)?;
                    let old = search.actions.split_off(at + 1);
                    search.actions.extend(rest);
                    search.levels[at].replaced = Some(Replaced { rest: old, point });
                    predicted = reached.clone();
                    scene = trial;
                    state = reached;
                    break;
                }
                Verdict::Refused(cause, why) => (cause, why),
                Verdict::Unsupported { object, reason } => {
                    let action = search.actions[at].clone();
                    let level = &search.levels[at].scene;
                    if let Some(body) = level.body_index(&object) {
                        search.unsupported.insert(object.clone(), level.body_pose(body));
                    }
                    let cause = Cause::NotAtRest { object: object.clone() };
                    if let Some(carry_start) = search.postpone(at, &object, goal) {
                        note_refusal(counts, at, &action, cause, &reason);
                        counts.postponements += 1;
                        recorder.truncate(carry_start.recorded);
                        (scene, state, predicted) =
                            (carry_start.scene, carry_start.state, carry_start.predicted);
                        break;
                    }
                    (cause, reason)
                }
            };
            note_refusal(counts, at, &search.actions[at], cause, &why);
            recorder.truncate(recorded);
        }
    }
}

/// Whether `object`, let go of at `released` in `scene`, would find something to hold it up
/// (it may still be refused for another reason, which refining it will tell).
fn supported(scene: &Scene, object: &str, released: &Pose) -> bool {
    let Some(body) = scene.body_index(object) else { return true };
    let mut probe = scene.clone();
    probe.set_body_pose(body, *released);
    probe.resting_pose(body).err().is_none_or(|refusal| refusal.lacks_support().is_none())
}

/// Tallies the refusal of a candidate of step `at` (0-based), `action`, for `cause`, and keeps
/// `why` as the deepest refusal when the step is at least as deep as the last.
fn note_refusal(
    counts: &mut RefineCounts,
    at: usize,
    action: &GroundedAction,
    cause: Cause,
    why: &str,
) {
    counts.failures.note(at, &call_text(&action.name, &action.arguments), cause, None);
    if at + 1 >= counts.deepest_failed {
        counts.deepest_failed = at + 1;
        counts.deepest_failure = format!("step {} ({}): {why}", at + 1, action.name);
    }
}

/// The backtracking stack of one plan's refinement and the candidates it has wasted.
struct Search {
    /// The plan's steps, their rest replaced where a replan was accepted.
    actions: Vec<GroundedAction>,
    /// One level per step refined so far, the last one being refined.
    levels: Vec<Level>,
    /// Wasted candidates (see [`wasted_budget`]).
    refused: usize,
    seed: u64,
    /// The orders refined from each step on, where a carry was postponed ([`postpone`]).
    tried: BTreeSet<(usize, Order)>,
    /// The objects whose release found nothing to hold them up, with the pose they were let go
    /// of at the last time.
    unsupported: BTreeMap<String, Pose>,
}

impl Search {
    /// Opens the refiner's stream for the next step, from `scene`, the state it starts in, whose
    /// abstract state is the first of `states` and the one the plan predicts there the second.
    fn open_level(
        &mut self,
        context: &Context<'_>,
        plugins: &mut Plugins<'_>,
        scene: &Scene,
        states: (BTreeSet<GroundAtom>, BTreeSet<GroundAtom>),
        recorded: usize,
        counts: &mut RefineCounts,
    ) -> Result<(), SolveError> {
        let index = self.levels.len();
        let stream_seed = mix(self.seed, index as u64, counts.candidates as u64);
        let request = RefineRequest {
            action: self.actions[index].clone(),
            world: world_state(context.participants, scene)?,
            seed: stream_seed,
        };
        let host = SceneHost::new(scene, stream_seed, context.settings.cancelled);
        let stream = plugins
            .refiner
            .refine(&request, &host)
            .map_err(|error| SolveError::from_plugin("refiner", error))?;
        let action = &self.actions[index];
        let action_text = call_text(&action.name, &action.arguments);
        counts.failures.reached(index, self.actions.len());
        counts.failures.merge(index, &action_text, host.take_seen());
        let (state, predicted) = states;
        self.levels.push(Level {
            scene: scene.clone(),
            state,
            predicted,
            recorded,
            stream,
            offered: 0,
            replaced: None,
        });
        if index + 1 > counts.deepest {
            counts.deepest = index + 1;
            counts.deepest_of = self.actions.len();
            // Cloned only when the search gets deeper than ever: at most once per step.
            counts.deepest_state =
                Some(Box::new(DeepestState { scene: scene.clone(), action: action_text.clone() }));
        }
        Ok(())
    }

    /// Postpones the carry of `object`, whose release at step `at` (the last level) found nothing
    /// to hold it up ([`postpone`]): the steps from where the carry began are reordered and the
    /// levels from there dropped, so that the search goes on from the state of the carry's first
    /// level, which is returned. `None` when no reordering runs to the goal. The levels dropped
    /// count as wasted, as backtracking over them would.
    fn postpone(&mut self, at: usize, object: &str, goal: &BTreeSet<GroundAtom>) -> Option<Level> {
        let carry = postpone::carry(&self.actions, at, object)?;
        let state = &self.levels[*carry.start()].state;
        let postponed = postpone::postpone(&self.actions, carry, state, goal, &self.tried)?;
        let from = postponed.from;
        self.reorder(postponed, at - from);
        self.levels.drain(from..).next()
    }

    /// Postpones, before any of it is refined, the carry that begins at the next step when its
    /// object's release found nothing to hold it up before and would find nothing in `scene`
    /// either, at the pose it was let go of at then: refining the carry again could only end in
    /// the same refusal. `state` is the abstract state of `scene`. Counts as a wasted candidate.
    fn postpone_unrefined(
        &mut self,
        scene: &Scene,
        state: &BTreeSet<GroundAtom>,
        goal: &BTreeSet<GroundAtom>,
    ) -> bool {
        let at = self.levels.len();
        let waiting = self.unsupported.iter().find_map(|(object, released)| {
            let carry = postpone::carry(&self.actions, at, object)?;
            (*carry.start() == at && !supported(scene, object, released)).then_some(carry)
        });
        let Some(carry) = waiting else { return false };
        match postpone::postpone(&self.actions, carry, state, goal, &self.tried) {
            Some(postponed) => {
                self.reorder(postponed, 1);
                true
            }
            None => false,
        }
    }

    /// Takes the reordered plan, remembering the order it replaces and its own as tried from
    /// where they part, and counts `wasted` candidates.
    fn reorder(&mut self, postponed: Postponed, wasted: usize) {
        let from = postponed.from;
        self.tried.insert((from, postpone::order(&self.actions[from..])));
        self.tried.insert((from, postpone::order(&postponed.actions[from..])));
        self.refused += wasted;
        self.actions = postponed.actions;
    }

    /// The next candidate of the last level, backtracking while levels run dry: the level's
    /// index with the candidate, or `None` when every level ran dry or the budget of wasted
    /// candidates is spent. Backtracking into a level whose candidate had replaced the rest of
    /// the plan puts the old rest back.
    fn next_candidate(
        &mut self,
        context: &Context<'_>,
        counts: &mut RefineCounts,
    ) -> Result<Option<(usize, Candidate)>, SolveError> {
        loop {
            let at = self.levels.len().wrapping_sub(1);
            let Some(level) = self.levels.last_mut() else { return Ok(None) };
            if self.refused >= wasted_budget(context.settings.max_refused, self.actions.len()) {
                return Ok(None);
            }
            if let Some(replaced) = level.replaced.take() {
                self.actions.truncate(at + 1);
                self.actions.extend(replaced.rest);
            }
            let host_seed = mix(self.seed, at as u64, counts.candidates as u64);
            let host = SceneHost::new(&level.scene, host_seed, context.settings.cancelled);
            let next = level
                .stream
                .next(&host)
                .map_err(|error| SolveError::from_plugin("refiner", error))?;
            let action = &self.actions[at];
            let action_text = call_text(&action.name, &action.arguments);
            counts.failures.merge(at, &action_text, host.take_seen());
            if next.is_some() {
                level.offered += 1;
                counts.failures.offered(at, &action_text);
            } else if level.offered == 0 {
                counts.failures.note(at, &action_text, Cause::NoCandidate, None);
            }
            let Some(candidate) = next else {
                // The step below gives up its accepted candidate: that one is wasted too.
                self.levels.pop();
                counts.backtracks += 1;
                self.refused += 1;
                continue;
            };
            counts.candidates += 1;
            return Ok(Some((at, candidate)));
        }
    }
}

/// The rests of plans planned from states reached during one plan's refinement, by state
/// (or why none was planned).
type Rests = BTreeMap<BTreeSet<GroundAtom>, Rest>;

/// What became of a candidate that was carried out.
enum Verdict {
    /// Its effects hold, no AtGoal object rests on its marker outside its tolerance, and the
    /// rest of the plan still runs to the goal from the state reached.
    Accepted(BTreeSet<GroundAtom>),
    /// Its effects hold but a side effect broke the rest of the plan; this new rest, planned from
    /// the state reached, replaces it.
    Replanned(BTreeSet<GroundAtom>, Vec<GroundedAction>),
    /// Refused: why, and the message that says it best.
    Refused(Cause, String),
    /// Refused because it lets go of `object` where nothing holds it up yet.
    Unsupported { object: String, reason: String },
}

impl Verdict {
    /// Refused for `cause`, which says it best.
    fn refused(cause: Cause) -> Verdict {
        let why = cause.to_string();
        Verdict::Refused(cause, why)
    }
}

/// Judges the state a candidate reached (execution monitoring), replanning the rest of the plan
/// when a side effect broke it.
struct Judge<'j, 'c, 'p> {
    context: &'j Context<'c>,
    plugins: &'j mut Plugins<'p>,
    goal: &'j BTreeSet<GroundAtom>,
    rests: &'j mut Rests,
    /// The abstract states before each step on the current path, the first step's first.
    path: Vec<&'j BTreeSet<GroundAtom>>,
}

impl Judge<'_, '_, '_> {
    /// The verdict on `trial`, the scene step `at` of `actions` reached.
    fn judge(
        &mut self,
        trial: &Scene,
        actions: &[GroundedAction],
        at: usize,
        counts: &mut RefineCounts,
    ) -> Result<Verdict, SolveError> {
        let context = self.context;
        let reached = abstraction(context.artifact, context.participants, trial)?;
        if let Some(unmet) = unmet_effects(&reached, &actions[at]) {
            let texts = |atoms: &[GroundAtom]| atoms.iter().map(ToString::to_string).collect();
            let cause = Cause::EffectsUnmet {
                missing: texts(&unmet.missing),
                unwanted: texts(&unmet.unwanted),
            };
            return Ok(Verdict::refused(cause));
        }
        if let Some(miss) = first_miss_where_reached(context.targets, self.goal, &reached, trial) {
            let why = miss.to_string();
            return Ok(Verdict::Refused(Cause::TargetMissed { object: miss.object }, why));
        }
        let Some(broken) = first_broken(&reached, &actions[at + 1..], self.goal) else {
            return Ok(Verdict::Accepted(reached));
        };
        let broken = broken_text(&broken, actions, at);
        if self.path.contains(&&reached) {
            return Ok(Verdict::refused(Cause::RestBroken {
                reason: format!(
                    "{broken}, and the state reached is one this plan was already in (a loop)"
                ),
            }));
        }
        let rest = match self.rests.get(&reached) {
            Some(rest) => rest.clone(),
            None => {
                counts.replans += 1;
                let settings = context.settings;
                let rest =
                    plan_from(self.plugins, context.domain, context.problem, &reached, settings)?;
                self.rests.insert(reached.clone(), rest.clone());
                rest
            }
        };
        Ok(match rest {
            Rest::Plan(rest) => Verdict::Replanned(reached, rest),
            Rest::Unreachable => Verdict::refused(Cause::RestBroken {
                reason: format!("{broken}, and no plan reaches the goal from there"),
            }),
            Rest::OutOfBudget => Verdict::refused(Cause::RestBroken {
                reason: format!(
                    "{broken}, and the planner's budget ran out before it found a plan from there"
                ),
            }),
        })
    }
}

/// The replan after step `at` (0-based): the atoms `reached` has that `expected` (the state the
/// plan predicted) lacks and the reverse, with the poses in `trial` of every object they name.
fn replan_point(
    context: &Context<'_>,
    at: usize,
    expected: &BTreeSet<GroundAtom>,
    reached: &BTreeSet<GroundAtom>,
    trial: &Scene,
) -> Result<ReplanPoint, SolveError> {
    let added: Vec<&GroundAtom> = reached.difference(expected).collect();
    let deleted: Vec<&GroundAtom> = expected.difference(reached).collect();
    let named: BTreeSet<&str> = added
        .iter()
        .chain(&deleted)
        .flat_map(|atom| atom.arguments.iter().map(String::as_str))
        .collect();
    let (participants, snapshot) = lamp_participants::scene_snapshot(context.participants, trial)
        .map_err(SolveError::internal)?;
    let mut poses: Vec<ObjectPose> = participants
        .iter()
        .zip(&snapshot.poses)
        .filter(|(participant, _)| named.contains(participant.name.as_str()))
        .map(|(participant, pose)| {
            let t = pose.translation.vector;
            let q = pose.rotation.quaternion();
            ObjectPose {
                object: participant.name.clone(),
                position: [t.x, t.y, t.z],
                rotation: [q.i, q.j, q.k, q.w],
            }
        })
        .collect();
    poses.sort_by(|a, b| a.object.cmp(&b.object));
    let texts = |atoms: &[&GroundAtom]| atoms.iter().map(ToString::to_string).collect();
    Ok(ReplanPoint { after_step: at + 1, added: texts(&added), deleted: texts(&deleted), poses })
}

/// What a broken rest of the plan misses, for messages.
fn broken_text(broken: &Broken, actions: &[GroundedAction], at: usize) -> String {
    let what = match actions.get(at + 1 + broken.index) {
        Some(later) => format!("step {} ({})", at + 2 + broken.index, later.name),
        None => "the goal".to_string(),
    };
    let mut needs = Vec::new();
    if !broken.missing.is_empty() {
        needs.push(atom_list(&broken.missing));
    }
    if !broken.unwanted.is_empty() {
        needs.push(format!("the absence of {}", atom_list(&broken.unwanted)));
    }
    format!("the state reached breaks {what}, which needs {}", needs.join(" and "))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_plans_get_a_budget_in_proportion_to_their_length() {
        // A Packing plan (19 steps) keeps the least budget; a Café plan of 175 steps gets 875.
        assert_eq!(wasted_budget(100, 19), 100);
        assert_eq!(wasted_budget(100, 20), 100);
        assert_eq!(wasted_budget(100, 21), 105);
        assert_eq!(wasted_budget(100, 175), 875);
        assert_eq!(wasted_budget(10, 0), 10);
    }
}
