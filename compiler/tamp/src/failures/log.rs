//! The refusals of a solve, plan by plan and step by step, and where the plans ended.

use std::collections::BTreeMap;

use lamp_world::Scene;
use serde::Serialize;

use super::NAMED_CAUSES;
use super::cause::{Cause, CauseCount, Tally};

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

    /// Step `at` (0-based) of the current plan was reached; the plan is now `length` steps long.
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
    pub(crate) fn arguments(&self) -> Vec<&str> {
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

/// The scene before the deepest step any refinement reached: where the search got furthest.
#[derive(Clone, Debug)]
pub struct DeepestState {
    pub scene: Scene,
    /// The step's grounded action (its place and its plan's length are the refinement's
    /// `deepest` and `deepest_of`).
    pub action: String,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::failures::cause::held_can_touches as collision;

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
}
