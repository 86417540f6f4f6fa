//! Why one attempt was refused, and how often each cause was met.

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
        entry.1 = least(entry.1, measure.filter(|value| value.is_finite()));
    }

    /// Adds every count of `other`.
    pub fn merge(&mut self, other: Tally) {
        for (cause, (count, nearest)) in other.counts {
            let entry = self.counts.entry(cause).or_insert((0, None));
            entry.0 += count;
            entry.1 = least(entry.1, nearest);
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

/// The smaller of two measures, either of which may be missing.
fn least(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
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

/// A collision of held `can5` with `other`, movable when it is a can.
#[cfg(test)]
pub(crate) fn held_can_touches(other: &str) -> Cause {
    Cause::Collision {
        moving: "can5".into(),
        held: true,
        other: other.into(),
        other_movable: other.starts_with("can"),
    }
}

#[cfg(test)]
mod tests {
    use super::held_can_touches as collision;
    use super::*;

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
}
