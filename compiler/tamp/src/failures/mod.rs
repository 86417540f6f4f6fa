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

mod advice;
mod cause;
mod log;

pub use advice::{Advice, DOMINANT, MOVABLE_BLOCKERS, Stop};
pub use cause::{Cause, CauseCount, Tally};
pub use log::{DecidingStep, DeepestState, FailureLog, FailureReport, PlanFailures, StepFailures};

/// How many causes, and how many steps where plans ended, a message names: enough to show what
/// blocked the plans, few enough to read.
pub const NAMED_CAUSES: usize = 3;
