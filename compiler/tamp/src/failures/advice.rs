//! What to do about a failed refinement, chosen by what was refused where most plans ended.

use super::cause::{Cause, CauseCount};
use super::log::{DecidingStep, FailureReport};

impl FailureReport {
    /// What to do about the step most plans ended at, from what was refused there: the share
    /// of each kind of cause among its refusals decides (a place full of movable objects is no
    /// sampling problem, an unreachable target no motion-budget problem). `None` when no kind
    /// stands out, or nothing was refused.
    pub fn advice(&self) -> Option<Advice> {
        let ended = self.deciding.first()?;
        let refusals = Refusals::at(ended)?;
        let steps: Vec<String> = ended.steps.iter().map(ToString::to_string).collect();
        let plural = if ended.steps.len() == 1 { "" } else { "s" };
        let at = format!("At step{plural} {} {}", steps.join(", "), ended.action);
        in_the_way(ended, &refusals, &at).or_else(|| dominant(&refusals, &at))
    }
}

/// The refusals at the step where most plans ended that say something: an IK call that did not
/// converge near its target says nothing of what is in the way or out of reach (draws the solver
/// finds awkward are common in every step), so the shares are of the other attempts.
struct Refusals<'a> {
    causes: Vec<&'a CauseCount>,
    total: usize,
}

impl<'a> Refusals<'a> {
    /// `None` when no refusal at the step says anything.
    fn at(ended: &'a DecidingStep) -> Option<Self> {
        let causes: Vec<&CauseCount> = ended
            .causes
            .iter()
            .filter(|count| !matches!(count.cause, Cause::NoCandidate | Cause::NoIkSolution { .. }))
            .collect();
        let total: usize = causes.iter().map(|count| count.count).sum();
        (total > 0).then_some(Refusals { causes, total })
    }

    fn share(&self, kind: &dyn Fn(&Cause) -> bool) -> f64 {
        let counted: usize =
            self.causes.iter().filter(|count| kind(&count.cause)).map(|count| count.count).sum();
        counted as f64 / self.total as f64
    }

    /// The most frequent cause of a kind, when that kind makes up at least `least` of them.
    fn leading(&self, kind: &dyn Fn(&Cause) -> bool, least: f64) -> Option<&'a Cause> {
        let first = self.causes.iter().find(|count| kind(&count.cause))?;
        (self.share(kind) >= least).then_some(&first.cause)
    }

    /// How far the nearest out-of-reach target was beyond reach, in metres.
    fn nearest_shortfall(&self) -> Option<f64> {
        self.causes
            .iter()
            .filter(|count| matches!(count.cause, Cause::OutOfReach { .. }))
            .filter_map(|count| count.nearest)
            .reduce(f64::min)
    }
}

/// Objects a robot may carry, not the step's own, refusing enough of the attempts to say that
/// the place is taken.
fn in_the_way(ended: &DecidingStep, refusals: &Refusals<'_>, at: &str) -> Option<Advice> {
    let arguments = ended.arguments();
    let in_the_way = |cause: &Cause| match cause {
        Cause::Collision { other, other_movable: true, .. } => !arguments.contains(&other.as_str()),
        _ => false,
    };
    refusals.leading(&in_the_way, MOVABLE_BLOCKERS)?;
    let blockers: Vec<String> = hit(ended, true).iter().map(|name| format!("`{name}`")).collect();
    let blocked = refusals.share(&in_the_way);
    // A carried object meeting them is a place that is taken; the robot's own links meeting
    // them, objects crowding what it reaches for.
    let carried =
        |cause: &Cause| in_the_way(cause) && matches!(cause, Cause::Collision { held: true, .. });
    let what = if refusals.share(&carried) * 2.0 >= blocked {
        "If the place is full, ask for fewer objects in it or give it more room; if \
         something should be moved out of the way first, the demonstrations must show \
         such a move."
    } else {
        "They crowd what the robot reaches for: set them farther apart in the scene, or \
         demonstrate moving such objects out of the way, so that the model learns it."
    };
    Some(Advice::new(
        Stop::InTheWay,
        format!(
            "{at}, {} {} in the way of {:.0} % of the attempts refused there: drawing more \
             samples will not make room. {what}",
            and_list(&blockers),
            if blockers.len() == 1 { "is" } else { "are" },
            (blocked * 100.0).round()
        ),
    ))
}

/// The kinds of cause that decide the advice when they make up [`DOMINANT`] of the refusals, in
/// the order they are asked.
const DOMINANT_KINDS: [fn(&Cause) -> bool; 7] = [
    |cause| matches!(cause, Cause::OutOfReach { .. }),
    |cause| matches!(cause, Cause::NoPath { .. }),
    |cause| matches!(cause, Cause::NotAtRest { .. }),
    |cause| matches!(cause, Cause::TargetMissed { .. }),
    |cause| matches!(cause, Cause::EffectsUnmet { .. }),
    |cause| matches!(cause, Cause::RestBroken { .. }),
    |cause| matches!(cause, Cause::Collision { other_movable: false, .. }),
];

/// The advice for the first kind of cause that makes up most of the refusals.
fn dominant(refusals: &Refusals<'_>, at: &str) -> Option<Advice> {
    let cause = DOMINANT_KINDS.iter().find_map(|kind| refusals.leading(kind, DOMINANT))?;
    let (stop, message) = match cause {
        Cause::OutOfReach { robot, link } => {
            let short = refusals
                .nearest_shortfall()
                .map(|value| format!(" (short by at least {:.0} mm)", value * 1000.0))
                .unwrap_or_default();
            (
                Stop::OutOfReach,
                format!(
                    "{at}, `{robot}` cannot reach where the step puts `{link}`{short}: drawing more \
                 samples or a larger motion budget will not help; start the robot nearer, or \
                 place the objects within its reach."
                ),
            )
        }
        Cause::NoPath { robot, group } => (
            Stop::NoPath,
            format!(
                "{at}, the motion planner found no {group} path for `{robot}` within its budget: \
                 give it more (`iterations` or `timeout` of the spec's `motion` plugin), or look \
                 at the scene for what crowds the way."
            ),
        ),
        Cause::NotAtRest { object } => (
            Stop::NotAtRest,
            format!(
                "{at}, `{object}` would be let go of where nothing holds it up, and no order of \
                 the plans tried puts its supports first: check that the goal gives it something \
                 to rest on, and that the demonstrations show such a support (`vocabulary.md`)."
            ),
        ),
        Cause::TargetMissed { object } => (
            Stop::TargetMissed,
            format!(
                "{at}, `{object}` lands outside its target's tolerance: loosen the goal's \
                 tolerance to what the demonstrations place (`lampc build` warns when the learned \
                 region is wider), or record more precise demonstrations."
            ),
        ),
        Cause::EffectsUnmet { .. } => (
            Stop::EffectsUnmet,
            format!(
                "{at}, the step's effects do not hold where its candidates end: the learned \
                 region the refiner draws from and the relation the step should make disagree. \
                 Look at both in `vocabulary.md` and the region pictures; more demonstrations \
                 usually make them agree."
            ),
        ),
        Cause::RestBroken { .. } => (
            Stop::RestBroken,
            format!(
                "{at}, every candidate undoes something a later step or the goal needs, and no \
                 plan reaches the goal from where it ends: a side effect the learned actions do \
                 not state. More demonstrations of the task may teach it."
            ),
        ),
        Cause::Collision { moving, other, .. } => (
            Stop::FixedBodies,
            format!(
                "{at}, `{moving}` touches `{other}` in most attempts: the place the learned region \
                 offers is mostly taken by bodies that do not move. The region may be wider than \
                 the place (see `regions/` in the build), or the place too small."
            ),
        ),
        // Never among the dominant kinds.
        Cause::NoCandidate
        | Cause::NoIkSolution { .. }
        | Cause::OutOfLimits { .. }
        | Cause::OutOfGrabRange { .. }
        | Cause::Other { .. } => return None,
    };
    Some(Advice::new(stop, message))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::failures::FailureLog;
    use crate::failures::cause::held_can_touches as collision;

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
