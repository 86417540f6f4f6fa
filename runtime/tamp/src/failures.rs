//! Why candidates were refused, counted by cause per plan step: what a failed solve reports.
//!
//! Every refusal the search meets is tallied under the step it happened at: the TAMP loop's own
//! verdicts (effects that do not hold, a release with nothing under the object, a path that
//! could not be found) and what the refiner's draws ran into, which the solver sees through the
//! host services it lends the refiner (an IK target out of reach, a configuration that collides,
//! naming the bodies). A failed solve hands the whole log back ([`FailureLog`]), and
//! [`FailureLog::deciding`] picks the causes that ended the plans: those at each plan's deepest
//! step, summed over plans. Tallying costs a counter and, for a collision, two names: cheap next
//! to the check that found it, and nothing at all for a candidate that is accepted.

use std::collections::BTreeMap;

use lamp_world::{Contact, Scene};
use serde::Serialize;

/// Why a candidate, or one of the refiner's attempts at one, was refused.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(tag = "cause", rename_all = "snake_case")]
pub enum Cause {
    /// The step's refiner stream ended without offering a single candidate; what its attempts
    /// ran into is tallied beside it.
    NoCandidate,
    /// IK: the target lies beyond what the robot's arm can stretch to (the tally's `nearest` is
    /// the least shortfall, metres).
    OutOfReach { robot: String, link: String },
    /// IK: no configuration came within tolerance of the target, though it is within the arm's
    /// stretch (`nearest`: the least position error, metres).
    NoIkSolution { robot: String, link: String },
    /// A configuration collides: `moving` (a robot link, or the object it holds when `held`)
    /// touches `other` (a body, or a link), which a robot may carry when `other_movable`.
    Collision { moving: String, held: bool, other: String, other_movable: bool },
    /// A configuration leaves the robot's joint limits.
    OutOfLimits { robot: String },
    /// The motion planner found no path for the joint group within its budget.
    NoPath { robot: String, group: String },
    /// The object was outside the gripper's grab range when the gripper arrived.
    OutOfGrabRange { object: String },
    /// The step's effects do not hold in the state reached: these atoms are false, those still
    /// true.
    EffectsUnmet { missing: Vec<String>, unwanted: Vec<String> },
    /// An object of an `at` goal or a structure is outside its target's tolerance.
    TargetMissed { object: String },
    /// A release where nothing holds the object up.
    NotAtRest { object: String },
    /// The state reached breaks a later step or the goal, and no other plan reaches the goal
    /// from there (or the state is one the plan was already in).
    RestBroken { reason: String },
    /// Anything else, as its message says.
    Other { reason: String },
}

impl Cause {
    /// The cause of a configuration of `robot` that `scene` refuses.
    pub fn of_contact(robot: &str, contact: Contact, scene: &Scene) -> Cause {
        let movable =
            |body: &str| scene.body_index(body).is_some_and(|index| scene.bodies()[index].movable);
        let collision = |moving: String, held: bool, other: String, body: bool| Cause::Collision {
            other_movable: body && movable(&other),
            moving,
            held,
            other,
        };
        match contact {
            Contact::OutOfLimits => Cause::OutOfLimits { robot: robot.to_string() },
            Contact::LinkBody { link, body } => collision(link, false, body, true),
            Contact::SelfCollision { a, b } => collision(a, false, b, false),
            Contact::HeldBody { held, body } => collision(held, true, body, true),
            Contact::HeldLink { held, link } => collision(held, true, link, false),
        }
    }
}

impl std::fmt::Display for Cause {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Cause::NoCandidate => f.write_str("the refiner offered no candidate"),
            Cause::OutOfReach { robot, link } => {
                write!(f, "the target of `{robot}`'s `{link}` is out of reach")
            }
            Cause::NoIkSolution { robot, link } => {
                write!(f, "IK found no configuration of `{robot}` placing `{link}`")
            }
            Cause::Collision { moving, held: true, other, .. } => {
                write!(f, "held `{moving}` touches `{other}`")
            }
            Cause::Collision { moving, held: false, other, .. } => {
                write!(f, "link `{moving}` touches `{other}`")
            }
            Cause::OutOfLimits { robot } => write!(f, "`{robot}` leaves its joint limits"),
            Cause::NoPath { robot, group } => {
                write!(f, "no {group} path for `{robot}` within the motion budget")
            }
            Cause::OutOfGrabRange { object } => {
                write!(f, "`{object}` is outside the grab range")
            }
            Cause::EffectsUnmet { missing, unwanted } => {
                f.write_str("its effects do not hold in the state reached")?;
                let mut parts = Vec::new();
                if !missing.is_empty() {
                    parts.push(format!("{} false", missing.join(" ")));
                }
                if !unwanted.is_empty() {
                    parts.push(format!("{} still true", unwanted.join(" ")));
                }
                if !parts.is_empty() {
                    write!(f, " ({})", parts.join("; "))?;
                }
                Ok(())
            }
            Cause::TargetMissed { object } => write!(f, "`{object}` misses its target"),
            Cause::NotAtRest { object } => {
                write!(f, "`{object}` is let go of where nothing holds it up")
            }
            Cause::RestBroken { reason } | Cause::Other { reason } => f.write_str(reason),
        }
    }
}

/// How often one cause was met, with the nearest miss where the cause measures one.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CauseCount {
    #[serde(flatten)]
    pub cause: Cause,
    pub count: usize,
    /// For [`Cause::OutOfReach`] the least shortfall, for [`Cause::NoIkSolution`] the least
    /// position error, in metres.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nearest: Option<f64>,
}

/// Causes met, by cause.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tally {
    counts: BTreeMap<Cause, (usize, Option<f64>)>,
}

impl Tally {
    /// Counts `cause` once; `measure` (metres) keeps the least seen.
    pub fn note(&mut self, cause: Cause, measure: Option<f64>) {
        let entry = self.counts.entry(cause).or_insert((0, None));
        entry.0 += 1;
        if let Some(measure) = measure.filter(|value| value.is_finite()) {
            entry.1 = Some(entry.1.map_or(measure, |least: f64| least.min(measure)));
        }
    }

    /// Adds every count of `other`.
    pub fn merge(&mut self, other: Tally) {
        for (cause, (count, nearest)) in other.counts {
            let entry = self.counts.entry(cause).or_insert((0, None));
            entry.0 += count;
            entry.1 = match (entry.1, nearest) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
        }
    }

    pub fn is_empty(&self) -> bool {
        self.counts.is_empty()
    }

    /// The counts, most frequent first (ties in the causes' order).
    pub fn counts(&self) -> Vec<CauseCount> {
        let mut counts: Vec<CauseCount> = self
            .counts
            .iter()
            .map(|(cause, &(count, nearest))| CauseCount { cause: cause.clone(), count, nearest })
            .collect();
        counts.sort_by(|a, b| b.count.cmp(&a.count).then_with(|| a.cause.cmp(&b.cause)));
        counts
    }
}

/// The refusals of one plan step.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StepFailures {
    /// The step's place in the plan, 1-based.
    pub step: usize,
    /// The grounded action, `(name args…)`.
    pub action: String,
    /// Candidates the refiner offered for it.
    pub candidates: usize,
    /// What was refused, most frequent first.
    pub causes: Vec<CauseCount>,
}

/// The refusals met while refining one plan.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlanFailures {
    /// Which plan this was, in the order they were tried (1-based; a plan tried again in a later
    /// round counts again).
    pub attempt: usize,
    /// The plan's length when it was given up (replans and postponements change it).
    pub length: usize,
    /// The deepest step its refinement reached (1-based).
    pub deepest: usize,
    /// Every step that refused anything, in plan order.
    pub steps: Vec<StepFailures>,
}

/// One plan being refined: its steps' tallies, by step and action.
#[derive(Clone, Debug, Default)]
struct PlanLog {
    length: usize,
    deepest: usize,
    steps: BTreeMap<(usize, String), (usize, Tally)>,
}

/// Every refusal of a solve, plan by plan.
#[derive(Clone, Debug, Default)]
pub struct FailureLog {
    plans: Vec<PlanLog>,
}

impl FailureLog {
    /// Starts the log of the next plan, `length` steps long.
    pub fn start_plan(&mut self, length: usize) {
        self.plans.push(PlanLog { length, ..PlanLog::default() });
    }

    fn current(&mut self) -> &mut PlanLog {
        if self.plans.is_empty() {
            self.plans.push(PlanLog::default());
        }
        let last = self.plans.len() - 1;
        &mut self.plans[last]
    }

    /// Step `at` (0-based) of the current plan, `action`, was reached; the plan is now `length`
    /// steps long.
    pub fn reached(&mut self, at: usize, length: usize) {
        let plan = self.current();
        plan.deepest = plan.deepest.max(at + 1);
        plan.length = length;
    }

    /// The refiner offered a candidate for step `at` (0-based), `action`.
    pub fn offered(&mut self, at: usize, action: &str) {
        self.current().steps.entry((at, action.to_string())).or_default().0 += 1;
    }

    /// A refusal at step `at` (0-based), `action`.
    pub fn note(&mut self, at: usize, action: &str, cause: Cause, measure: Option<f64>) {
        let entry = self.current().steps.entry((at, action.to_string())).or_default();
        entry.1.note(cause, measure);
    }

    /// Refusals met by the refiner's attempts at step `at` (0-based), `action`.
    pub fn merge(&mut self, at: usize, action: &str, seen: Tally) {
        if seen.is_empty() {
            return;
        }
        self.current().steps.entry((at, action.to_string())).or_default().1.merge(seen);
    }

    /// The whole log, plan by plan, steps in order, only steps that refused something.
    pub fn plans(&self) -> Vec<PlanFailures> {
        self.plans
            .iter()
            .enumerate()
            .map(|(index, plan)| PlanFailures {
                attempt: index + 1,
                length: plan.length,
                deepest: plan.deepest,
                steps: plan
                    .steps
                    .iter()
                    .filter(|(_, (_, tally))| !tally.is_empty())
                    .map(|((at, action), (candidates, tally))| StepFailures {
                        step: at + 1,
                        action: action.clone(),
                        candidates: *candidates,
                        causes: tally.counts(),
                    })
                    .collect(),
            })
            .collect()
    }

    /// Where the plans ended and why: each plan's deepest step, grouped by its action over the
    /// plans that ended there, with every cause met there summed; the action most plans ended
    /// at first.
    pub fn deciding(&self) -> Vec<DecidingStep> {
        let mut ended: BTreeMap<&str, (BTreeMap<usize, usize>, Tally)> = BTreeMap::new();
        for plan in &self.plans {
            let Some(at) = plan.deepest.checked_sub(1) else { continue };
            for ((step, action), (_, tally)) in plan.steps.range((at, String::new())..) {
                if *step != at {
                    break;
                }
                let entry = ended.entry(action).or_default();
                *entry.0.entry(at + 1).or_default() += 1;
                entry.1.merge(tally.clone());
            }
        }
        let mut deciding: Vec<DecidingStep> = ended
            .into_iter()
            .map(|(action, (steps, tally))| DecidingStep {
                action: action.to_string(),
                plans: steps.values().sum(),
                steps: steps.into_keys().collect(),
                causes: tally.counts(),
            })
            .collect();
        deciding.sort_by(|a, b| b.plans.cmp(&a.plans).then_with(|| a.action.cmp(&b.action)));
        deciding
    }
}

/// A step where plans ended, and what was refused there.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DecidingStep {
    /// The grounded action, `(name args…)`.
    pub action: String,
    /// The step numbers it held in those plans (1-based).
    pub steps: Vec<usize>,
    /// How many plans ended there.
    pub plans: usize,
    /// What was refused there, over those plans, most frequent first.
    pub causes: Vec<CauseCount>,
}

impl DecidingStep {
    /// The objects the step's action names (its arguments).
    fn arguments(&self) -> Vec<&str> {
        let call = self.action.trim_start_matches('(').trim_end_matches(')');
        call.split_whitespace().skip(1).collect()
    }
}

impl std::fmt::Display for DecidingStep {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let steps: Vec<String> = self.steps.iter().map(ToString::to_string).collect();
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        write!(
            f,
            "step{} {} {}, where {} plan{} ended:",
            plural(self.steps.len()),
            steps.join(", "),
            self.action,
            self.plans,
            plural(self.plans)
        )?;
        // A stream that offered nothing is said first: the other causes say why.
        let mut causes: Vec<&CauseCount> = self.causes.iter().collect();
        causes.sort_by_key(|count| count.cause != Cause::NoCandidate);
        let named: Vec<String> = causes.iter().take(NAMED_CAUSES).map(|c| c.to_string()).collect();
        write!(f, " {}", named.join("; "))?;
        if causes.len() > NAMED_CAUSES {
            write!(f, "; {} more", causes.len() - NAMED_CAUSES)?;
        }
        Ok(())
    }
}

impl std::fmt::Display for CauseCount {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ×{}", self.cause, self.count)?;
        if let Some(nearest) = self.nearest {
            let what = match self.cause {
                Cause::OutOfReach { .. } => "short by at least",
                _ => "at best",
            };
            write!(f, " ({what} {:.0} mm)", nearest * 1000.0)?;
        }
        Ok(())
    }
}

/// What a failed refinement met: where its plans ended and why, and every plan's refusals.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FailureReport {
    /// [`FailureLog::deciding`].
    pub deciding: Vec<DecidingStep>,
    /// [`FailureLog::plans`].
    pub plans: Vec<PlanFailures>,
}

impl FailureLog {
    /// The report of the log.
    pub fn report(&self) -> FailureReport {
        FailureReport { deciding: self.deciding(), plans: self.plans() }
    }
}

impl FailureReport {
    /// What to do about the step most plans ended at, from what was refused there: the share
    /// of each kind of cause among its refusals decides (a place full of movable objects is no
    /// sampling problem, an unreachable target no motion-budget problem). `None` when no kind
    /// stands out, or nothing was refused.
    pub fn advice(&self) -> Option<Advice> {
        let ended = self.deciding.first()?;
        // An IK call that did not converge near its target says nothing of what is in the way
        // or out of reach (draws the solver finds awkward are common in every step), so the
        // shares are of the attempts that say something.
        let causes: Vec<&CauseCount> = ended
            .causes
            .iter()
            .filter(|count| !matches!(count.cause, Cause::NoCandidate | Cause::NoIkSolution { .. }))
            .collect();
        let total: usize = causes.iter().map(|count| count.count).sum();
        if total == 0 {
            return None;
        }
        let share = |kind: &dyn Fn(&Cause) -> bool| {
            let counted: usize =
                causes.iter().filter(|count| kind(&count.cause)).map(|count| count.count).sum();
            counted as f64 / total as f64
        };
        // The most frequent cause of a kind, when that kind makes up at least `least` of them.
        let leading = |kind: &dyn Fn(&Cause) -> bool, least: f64| {
            let first = causes.iter().find(|count| kind(&count.cause))?;
            (share(kind) >= least).then_some(&first.cause)
        };
        let steps: Vec<String> = ended.steps.iter().map(ToString::to_string).collect();
        let plural = if ended.steps.len() == 1 { "" } else { "s" };
        let at = format!("At step{plural} {} {}", steps.join(", "), ended.action);

        let arguments = ended.arguments();
        let in_the_way = |cause: &Cause| match cause {
            Cause::Collision { other, other_movable: true, .. } => {
                !arguments.contains(&other.as_str())
            }
            _ => false,
        };
        if leading(&in_the_way, MOVABLE_BLOCKERS).is_some() {
            let blockers: Vec<String> =
                hit(ended, true).iter().map(|name| format!("`{name}`")).collect();
            let blocked = share(&in_the_way);
            // A carried object meeting them is a place that is taken; the robot's own links
            // meeting them, objects crowding what it reaches for.
            let carried = |cause: &Cause| {
                in_the_way(cause) && matches!(cause, Cause::Collision { held: true, .. })
            };
            let what = if share(&carried) * 2.0 >= blocked {
                "If the place is full, ask for fewer objects in it or give it more room; if \
                 something should be moved out of the way first, the demonstrations must show \
                 such a move."
            } else {
                "They crowd what the robot reaches for: set them farther apart in the scene, or \
                 demonstrate moving such objects out of the way, so that the model learns it."
            };
            return Some(Advice::new(
                Stop::InTheWay,
                format!(
                    "{at}, {} {} in the way of {:.0} % of the attempts refused there: drawing more \
                     samples will not make room. {what}",
                    and_list(&blockers),
                    if blockers.len() == 1 { "is" } else { "are" },
                    (blocked * 100.0).round()
                ),
            ));
        }
        let reach = |cause: &Cause| matches!(cause, Cause::OutOfReach { .. });
        if let Some(Cause::OutOfReach { robot, link }) = leading(&reach, DOMINANT) {
            let nearest = causes
                .iter()
                .filter(|count| matches!(count.cause, Cause::OutOfReach { .. }))
                .filter_map(|count| count.nearest)
                .reduce(f64::min);
            let short = nearest
                .map(|value| format!(" (short by at least {:.0} mm)", value * 1000.0))
                .unwrap_or_default();
            return Some(Advice::new(
                Stop::OutOfReach,
                format!(
                    "{at}, `{robot}` cannot reach where the step puts `{link}`{short}: drawing more \
                 samples or a larger motion budget will not help; start the robot nearer, or \
                 place the objects within its reach."
                ),
            ));
        }
        if let Some(Cause::NoPath { robot, group }) =
            leading(&|cause| matches!(cause, Cause::NoPath { .. }), DOMINANT)
        {
            return Some(Advice::new(
                Stop::NoPath,
                format!(
                    "{at}, the motion planner found no {group} path for `{robot}` within its budget: \
                 give it more (`iterations` or `timeout` of the spec's `motion` plugin), or look \
                 at the scene for what crowds the way."
                ),
            ));
        }
        if let Some(Cause::NotAtRest { object }) =
            leading(&|cause| matches!(cause, Cause::NotAtRest { .. }), DOMINANT)
        {
            return Some(Advice::new(
                Stop::NotAtRest,
                format!(
                    "{at}, `{object}` would be let go of where nothing holds it up, and no order of \
                 the plans tried puts its supports first: check that the goal gives it something \
                 to rest on, and that the demonstrations show such a support (`vocabulary.md`)."
                ),
            ));
        }
        if let Some(Cause::TargetMissed { object }) =
            leading(&|cause| matches!(cause, Cause::TargetMissed { .. }), DOMINANT)
        {
            return Some(Advice::new(
                Stop::TargetMissed,
                format!(
                    "{at}, `{object}` lands outside its target's tolerance: loosen the goal's \
                 tolerance to what the demonstrations place (`lampc build` warns when the learned \
                 region is wider), or record more precise demonstrations."
                ),
            ));
        }
        if leading(&|cause| matches!(cause, Cause::EffectsUnmet { .. }), DOMINANT).is_some() {
            return Some(Advice::new(
                Stop::EffectsUnmet,
                format!(
                    "{at}, the step's effects do not hold where its candidates end: the learned \
                 region the refiner draws from and the relation the step should make disagree. \
                 Look at both in `vocabulary.md` and the region pictures; more demonstrations \
                 usually make them agree."
                ),
            ));
        }
        if leading(&|cause| matches!(cause, Cause::RestBroken { .. }), DOMINANT).is_some() {
            return Some(Advice::new(
                Stop::RestBroken,
                format!(
                    "{at}, every candidate undoes something a later step or the goal needs, and no \
                 plan reaches the goal from where it ends: a side effect the learned actions do \
                 not state. More demonstrations of the task may teach it."
                ),
            ));
        }
        let fixed = |cause: &Cause| matches!(cause, Cause::Collision { other_movable: false, .. });
        if let Some(Cause::Collision { moving, other, .. }) = leading(&fixed, DOMINANT) {
            return Some(Advice::new(
                Stop::FixedBodies,
                format!(
                    "{at}, `{moving}` touches `{other}` in most attempts: the place the learned region \
                 offers is mostly taken by bodies that do not move. The region may be wider than \
                 the place (see `regions/` in the build), or the place too small."
                ),
            ));
        }
        None
    }
}

/// What kind of cause stopped the plans where most of them ended: what [`FailureReport::advice`]
/// is chosen by, and what `lampc eval` counts failed solves by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stop {
    /// Objects a robot may carry are in the way.
    InTheWay,
    /// IK targets out of reach, or IK finding nothing.
    OutOfReach,
    /// No motion path within the budget.
    NoPath,
    /// Releases where nothing holds the object up.
    NotAtRest,
    /// Targets missed by more than their tolerance.
    TargetMissed,
    /// The step's effects do not hold where its candidates end.
    EffectsUnmet,
    /// Candidates break the rest of the plan.
    RestBroken,
    /// Bodies that do not move take the place.
    FixedBodies,
}

impl Stop {
    /// Its name in `lampc eval`'s rows.
    pub fn name(self) -> &'static str {
        match self {
            Stop::InTheWay => "in_the_way",
            Stop::OutOfReach => "out_of_reach",
            Stop::NoPath => "no_path",
            Stop::NotAtRest => "not_at_rest",
            Stop::TargetMissed => "target_missed",
            Stop::EffectsUnmet => "effects_unmet",
            Stop::RestBroken => "rest_broken",
            Stop::FixedBodies => "fixed_bodies",
        }
    }
}

/// What stopped the plans, and what to do about it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Advice {
    pub stop: Stop,
    pub text: String,
}

impl Advice {
    fn new(stop: Stop, text: String) -> Advice {
        Advice { stop, text }
    }
}

impl FailureReport {
    /// The bodies the advice points at, for a picture: those in the way where most plans ended
    /// ([`Stop::InTheWay`]: the movable ones; [`Stop::FixedBodies`]: the others), most often
    /// met first; none for any other advice.
    pub fn blockers(&self) -> Vec<String> {
        let (Some(advice), Some(ended)) = (self.advice(), self.deciding.first()) else {
            return Vec::new();
        };
        let movable = match advice.stop {
            Stop::InTheWay => true,
            Stop::FixedBodies => false,
            _ => return Vec::new(),
        };
        hit(ended, movable)
    }
}

/// The bodies met at `ended` that a robot may carry (`movable`) or not, other than the step's
/// own arguments (a gripper touching the can it is to take is a draw that missed, not a
/// blocker), most often met first.
fn hit(ended: &DecidingStep, movable: bool) -> Vec<String> {
    let arguments = ended.arguments();
    let mut bodies: Vec<String> = Vec::new();
    for count in &ended.causes {
        if let Cause::Collision { other, other_movable, .. } = &count.cause
            && *other_movable == movable
            && !arguments.contains(&other.as_str())
            && !bodies.contains(other)
        {
            bodies.push(other.clone());
        }
    }
    bodies
}

/// `a`, `a and b`, `a, b and c`.
fn and_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

/// The share of the refusals at a step from objects a robot may carry, at or above which they
/// are said to be in the way: they block only where they stand, so even a minority of the
/// refusals says the place is taken (the rest are draws that miss the place altogether).
pub const MOVABLE_BLOCKERS: f64 = 0.2;
/// The share of the refusals at a step at or above which one kind of cause decides the advice.
pub const DOMINANT: f64 = 0.5;

/// The scene before the deepest step any refinement reached: where the search got furthest.
#[derive(Clone, Debug)]
pub struct DeepestState {
    pub scene: Scene,
    /// The step (1-based), the length of its plan, and its grounded action.
    pub step: usize,
    pub length: usize,
    pub action: String,
}

/// How many causes, and how many steps where plans ended, a message names: enough to show what
/// blocked the plans, few enough to read.
pub const NAMED_CAUSES: usize = 3;

#[cfg(test)]
mod tests {
    use super::*;

    fn collision(other: &str) -> Cause {
        Cause::Collision {
            moving: "can5".into(),
            held: true,
            other: other.into(),
            other_movable: other.starts_with("can"),
        }
    }

    #[test]
    fn a_tally_counts_by_cause_and_keeps_the_nearest_miss() {
        let mut tally = Tally::default();
        let reach = Cause::OutOfReach { robot: "fetch".into(), link: "gripper".into() };
        tally.note(reach.clone(), Some(0.30));
        tally.note(collision("can2"), None);
        tally.note(reach.clone(), Some(0.12));
        tally.note(reach.clone(), Some(f64::NAN));
        let counts = tally.counts();
        assert_eq!(counts[0], CauseCount { cause: reach, count: 3, nearest: Some(0.12) });
        assert_eq!(counts[1], CauseCount { cause: collision("can2"), count: 1, nearest: None });
    }

    #[test]
    fn the_plans_end_where_their_deepest_step_ran_dry() {
        let mut log = FailureLog::default();
        // Plan 1 gets to step 3 and runs dry there among collisions; step 1 refused a path.
        log.start_plan(4);
        log.reached(0, 4);
        log.note(0, "(pick can1)", Cause::NoPath { robot: "r".into(), group: "arm".into() }, None);
        log.reached(2, 4);
        log.note(2, "(put can5 box1)", collision("can2"), None);
        log.note(2, "(put can5 box1)", collision("can2"), None);
        log.note(2, "(put can5 box1)", Cause::NoCandidate, None);
        // Plan 2 ends at the same action as its step 2; plan 3 at another action.
        log.start_plan(3);
        log.reached(1, 3);
        log.note(1, "(put can5 box1)", collision("can3"), None);
        log.note(1, "(put can5 box1)", collision("can2"), None);
        log.start_plan(3);
        log.reached(0, 3);
        let reach = Cause::OutOfReach { robot: "r".into(), link: "hand".into() };
        log.note(0, "(pick can1)", reach, Some(0.0123));
        let texts: Vec<String> = log.deciding().iter().map(ToString::to_string).collect();
        assert_eq!(
            texts,
            [
                "steps 2, 3 (put can5 box1), where 2 plans ended: the refiner offered no candidate ×1; \
                 held `can5` touches `can2` ×3; held `can5` touches `can3` ×1",
                "step 1 (pick can1), where 1 plan ended: the target of `r`'s `hand` is out of reach \
                 ×1 (short by at least 12 mm)",
            ]
        );
        let plans = log.plans();
        assert_eq!(plans.len(), 3);
        assert_eq!((plans[0].attempt, plans[0].deepest, plans[0].steps.len()), (1, 3, 2));
        assert_eq!(plans[0].steps[0].causes[0].count, 1);
    }

    fn report_of(causes: &[(Cause, usize)]) -> FailureReport {
        let mut log = FailureLog::default();
        log.start_plan(5);
        log.reached(3, 5);
        for (cause, count) in causes {
            for _ in 0..*count {
                log.note(3, "(put can5 box1)", cause.clone(), Some(0.04));
            }
        }
        log.report()
    }

    #[test]
    fn the_advice_follows_from_what_was_refused_where_the_plans_ended() {
        // Movable objects in the way, even as a minority: the place is full.
        let full = report_of(&[
            (Cause::NoCandidate, 1),
            (collision("table1"), 50),
            (collision("can1"), 30),
            (collision("can2"), 20),
        ]);
        let advice = full.advice().expect("advice");
        assert_eq!(advice.stop, Stop::InTheWay);
        let advice = advice.text;
        assert!(
            advice.starts_with(
                "At step 4 (put can5 box1), `can1` and `can2` are in the way of 50 % of the \
                 attempts refused there: drawing more samples will not make room."
            ),
            "{advice}"
        );
        // The object the step acts on, and IK calls that did not converge, say nothing of what
        // is in the way.
        let touched = Cause::Collision {
            moving: "gripper_link".into(),
            held: false,
            other: "can5".into(),
            other_movable: true,
        };
        let awkward = Cause::NoIkSolution { robot: "fetch".into(), link: "gripper_link".into() };
        let one = report_of(&[
            (touched, 60),
            (awkward, 500),
            (collision("can1"), 25),
            (collision("table1"), 15),
        ]);
        let advice = one.advice().expect("advice");
        assert_eq!(advice.stop, Stop::InTheWay);
        assert!(
            advice.text.contains(", `can1` is in the way of 25 % of the attempts"),
            "{advice:?}"
        );
        assert_eq!(one.blockers(), ["can1"]);
        // Out of reach, with the least shortfall.
        let reach = Cause::OutOfReach { robot: "fetch".into(), link: "gripper_link".into() };
        let far = report_of(&[(reach, 8), (collision("table1"), 2)]);
        let advice = far.advice().expect("advice");
        assert_eq!(advice.stop, Stop::OutOfReach);
        let advice = advice.text;
        assert!(
            advice.contains(
                "`fetch` cannot reach where the step puts `gripper_link` (short by at least 40 mm)"
            ),
            "{advice}"
        );
        // No kind stands out: no advice of its own.
        let mixed = report_of(&[
            (Cause::NoPath { robot: "fetch".into(), group: "arm".into() }, 4),
            (Cause::TargetMissed { object: "can5".into() }, 4),
            (collision("table1"), 2),
        ]);
        assert_eq!(mixed.advice(), None);
        assert_eq!(FailureReport::default().advice(), None);
    }
}
