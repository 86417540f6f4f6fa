//! Why a problem could not be solved.

use miette::Diagnostic;
use thiserror::Error;

/// A solve failure, with a stable code.
#[derive(Debug, Error, Diagnostic)]
pub enum SolveError {
    /// The domain or problem text does not parse.
    #[error("the {what} does not parse: {reason}")]
    #[diagnostic(
        code(lamp::solve::pddl),
        help("rebuild with `lampc build`, or fix the edited file")
    )]
    Pddl { what: String, reason: String },
    /// The problem's scene abstracts to another state than the problem file's `:init`.
    #[error(
        "problem `{problem}` is stale: its scene abstracts to another initial state than its PDDL file ({difference})"
    )]
    #[diagnostic(
        code(lamp::solve::stale_problem),
        help("rebuild with `lampc build` after changing the spec or the demonstrations")
    )]
    StaleProblem { problem: String, difference: String },
    /// The planner returned a plan that names an unknown action or the wrong arity.
    #[error("the planner returned a bad step {step}: {reason}")]
    #[diagnostic(code(lamp::solve::bad_plan))]
    BadPlan { step: String, reason: String },
    /// A plugin call failed.
    #[error("the {kind} plugin failed: {reason}")]
    #[diagnostic(code(lamp::solve::plugin))]
    Plugin { kind: &'static str, reason: String },
    /// No plan exists even with every goal relation but one dropped, or the planner gave up.
    #[error("no plan: {reason}")]
    #[diagnostic(
        code(lamp::solve::no_plan),
        help(
            "check the goal against the vocabulary report; more demonstrations may teach the missing action"
        )
    )]
    NoPlan { reason: String },
    /// Relaxing the goal left nothing to achieve: every atom still in it holds initially.
    #[error(
        "no plan reaches any goal atom that does not already hold: relaxing the goal dropped {dropped} ({reason})"
    )]
    #[diagnostic(
        code(lamp::solve::goal_relaxed_away),
        help(
            "The learned model has no way to this goal: check the goal against the vocabulary report, and the domain if it was edited; more demonstrations may teach the missing action."
        )
    )]
    GoalRelaxedAway {
        /// The dropped atoms, in the order they were dropped.
        dropped: String,
        /// Why the planner found no plan for the last goal it was given.
        reason: String,
    },
    /// Plans exist but none could be refined into motion within the budget.
    #[error("no plan could be refined into motion ({0})")]
    #[diagnostic(
        code(lamp::solve::refinement_failed),
        help("raise the refiner's `samples` or the motion budget, or try `--planner topk`")
    )]
    RefinementFailed(Progress),
    /// The final trajectory failed its replay check: a bug, never a user error.
    #[error("the solution failed validation at step {step}: {reason}")]
    #[diagnostic(code(lamp::solve::invalid_solution))]
    InvalidSolution { step: usize, reason: String },
    /// Cancelled by the host (an interrupt, a time limit), with how far the refinement got.
    #[error("cancelled ({0})")]
    #[diagnostic(code(lamp::solve::cancelled))]
    Cancelled(Progress),
    /// A broken invariant inside the solver.
    #[error("internal error: {0}")]
    #[diagnostic(code(lamp::solve::internal))]
    Internal(String),
}

impl SolveError {
    pub(crate) fn internal(reason: impl Into<String>) -> Self {
        SolveError::Internal(reason.into())
    }

    /// A cancellation seen inside a call, before the solve fills in its progress.
    pub(crate) fn cancelled() -> Self {
        SolveError::Cancelled(Progress::default())
    }
}

/// How far the refinement got before it failed or was cancelled.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Progress {
    /// Plans tried (every round counts every plan it tries).
    pub plans: usize,
    /// Refiner candidates tried.
    pub candidates: usize,
    /// The deepest step any refinement reached (1-based), and the length of that plan.
    pub deepest: usize,
    pub length: usize,
    /// The deepest step that refused a candidate, and why.
    pub failure: String,
}

impl std::fmt::Display for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.plans == 0 {
            return f.write_str("before any plan was refined");
        }
        write!(
            f,
            "{} plan(s) tried, {} candidates, deepest step {} of {}",
            self.plans, self.candidates, self.deepest, self.length
        )?;
        if !self.failure.is_empty() {
            write!(f, "; the deepest refusal: {}", self.failure)?;
        }
        Ok(())
    }
}
