//! Why a problem could not be solved.

use lamp_pddl::{PddlError, PddlErrors};
use lamp_plugin_api::PluginError;
use miette::{Diagnostic, NamedSource};
use thiserror::Error;

use crate::failures::{DeepestState, FailureReport, NAMED_CAUSES};

/// A solve failure, with a stable code.
#[derive(Debug, Error, Diagnostic)]
pub enum SolveError {
    /// The domain or problem text does not parse: every error is related, with its span in the
    /// text, which is attached (named `domain` or `problem` until the caller names its file with
    /// [`SolveError::in_files`]).
    #[error("the {what} does not parse: {} PDDL error(s) in {}", .errors.len(), .text.name())]
    #[diagnostic(
        code(lamp::solve::pddl),
        help("Rebuild with `lampc build`, or fix the edited file where the errors point.")
    )]
    Pddl {
        /// `domain` or `problem`.
        what: &'static str,
        #[source_code]
        text: NamedSource<String>,
        #[related]
        errors: Vec<PddlError>,
    },
    /// The problem's scene abstracts to another state than the problem file's `:init`.
    #[error(
        "problem `{problem}` is stale: its scene abstracts to another initial state than its PDDL file ({difference})"
    )]
    #[diagnostic(
        code(lamp::solve::stale_problem),
        help("rebuild with `lampc build` after changing the spec or the demonstrations")
    )]
    StaleProblem { problem: String, difference: String },
    /// The planner returned a plan that names an unknown action, the wrong arity, or an argument
    /// that is no object of the problem or of the wrong type.
    #[error("the planner returned a bad step {step}: {reason}")]
    #[diagnostic(code(lamp::solve::bad_plan))]
    BadPlan { step: String, reason: String },
    /// A plugin call failed: the plugin's own error, kept whole for callers that tell its
    /// variants apart.
    #[error("the {kind} plugin failed: {error}")]
    #[diagnostic(code(lamp::solve::plugin))]
    Plugin { kind: &'static str, error: PluginError },
    /// A plugin answered with something the solver cannot use: a planner's `Failed` status, a
    /// refiner's target for another robot, a path the world rejects.
    #[error("the {kind} plugin failed: {reason}")]
    #[diagnostic(code(lamp::solve::plugin))]
    PluginAnswer { kind: &'static str, reason: String },
    /// No plan exists even with every goal relation but one dropped, or the planner gave up.
    #[error("no plan: {reason}")]
    #[diagnostic(
        code(lamp::solve::no_plan),
        help(
            "check the goal against the vocabulary report; more demonstrations may teach the missing action"
        )
    )]
    NoPlan { reason: String },
    /// The planner's budget ran out before it found a plan: the goal may be reachable, so it is
    /// not relaxed. `relaxed` lists the atoms dropped before, when a plan was proved not to
    /// exist for the whole goal.
    #[error(
        "no plan: the planner's budget ran out before it found one{}",
        if relaxed.is_empty() { String::new() } else { format!(" (after dropping {relaxed})") }
    )]
    #[diagnostic(
        code(lamp::solve::planner_budget),
        help(
            "A plan may exist: give the planner more time (`planner gbfs-ff {{ timeout 60 s }}` in the spec, or leave its `timeout` out for no limit) or try another planner (`--planner external`)."
        )
    )]
    PlannerBudget { relaxed: String },
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
    #[diagnostic(code(lamp::solve::refinement_failed), help("{}", .0.advice()))]
    RefinementFailed(Progress),
    /// The final trajectory leaves an object outside the tolerance of its `at` goal or structure
    /// pose: the learned region of the object on its marker let a placement through that the goal
    /// does not accept.
    #[error("the solution misses a target: {0}")]
    #[diagnostic(
        code(lamp::solve::target_missed),
        help(
            "Loosen an `at` goal's tolerance to what the demonstrations place (`lampc build` warns when the learned region is wider), or record more precise demonstrations (a structure is built within 5 mm and 3°)."
        )
    )]
    TargetMissed(String),
    /// An object does not stay put under gravity (the physics check), in the final scene or
    /// (`step`) in the scene right after a trajectory step lets go of something.
    #[error(
        "`{object}` does not stay where the solution leaves it{}: under gravity it moves {:.1} mm and turns {:.1}° in {seconds} s (at most {:.0} mm and {:.0}°)",
        step.map_or_else(String::new, |step| format!(" after what is let go of at step {step}")),
        shift * 1000.0,
        turn.to_degrees(),
        lamp_physics::MAX_SHIFT * 1000.0,
        lamp_physics::MAX_TURN.to_degrees()
    )]
    #[diagnostic(
        code(lamp::solve::unstable),
        help(
            "the object is placed where it cannot rest, or on another object that moves: look at the final scene (`lampc render`); if the demonstrations place objects like this, they are not at rest either"
        )
    )]
    Unstable { object: String, shift: f64, turn: f64, seconds: f64, step: Option<usize> },
    /// The final trajectory failed its replay check: a bug, never a user error.
    #[error("the solution failed validation at step {step}: {reason}")]
    #[diagnostic(code(lamp::solve::invalid_solution))]
    InvalidSolution { step: usize, reason: String },
    /// Cancelled by the host (an interrupt, a time limit), with how far the refinement got.
    #[error("cancelled ({0})")]
    #[diagnostic(code(lamp::solve::cancelled), help("{}", .0.advice_when_stopped()))]
    Cancelled(Progress),
    /// A broken invariant inside the solver.
    #[error("internal error: {0}")]
    #[diagnostic(code(lamp::solve::internal))]
    Internal(String),
}

impl SolveError {
    /// The one conversion of a plugin call's error: a cancellation stops the solve as every other
    /// cancellation does; anything else is the failure of the plugin of that kind.
    pub(crate) fn from_plugin(kind: &'static str, error: PluginError) -> Self {
        match error {
            PluginError::Cancelled => SolveError::cancelled(),
            error => SolveError::Plugin { kind, error },
        }
    }

    /// A PDDL text that does not parse, with its errors.
    pub(crate) fn pddl(what: &'static str, text: &str, errors: PddlErrors) -> Self {
        SolveError::Pddl {
            what,
            text: NamedSource::new(what, text.to_string()),
            errors: errors.errors,
        }
    }

    /// Names the files the domain and problem texts were read from, so that a PDDL error's
    /// report points into the file (`path:line:column`); other errors are returned as they are.
    #[must_use]
    pub fn in_files(self, domain: &str, problem: &str) -> Self {
        match self {
            SolveError::Pddl { what, text, errors } => {
                let name = if what == "domain" { domain } else { problem };
                SolveError::Pddl {
                    what,
                    text: NamedSource::new(name, text.inner().clone()),
                    errors,
                }
            }
            other => other,
        }
    }

    pub(crate) fn internal(reason: impl Into<String>) -> Self {
        SolveError::Internal(reason.into())
    }

    /// A cancellation seen inside a call, before the solve fills in its progress.
    pub(crate) fn cancelled() -> Self {
        SolveError::Cancelled(Progress::default())
    }
}

/// How far the refinement got before it failed or was cancelled.
#[derive(Clone, Debug, Default, serde::Serialize)]
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
    /// Every refusal by cause, and the causes that ended the plans.
    pub report: FailureReport,
    /// Where the search got furthest (the scene before step `deepest`), for a picture.
    #[serde(skip)]
    pub deepest_state: Option<Box<DeepestState>>,
}

impl Progress {
    /// What to do about it: from where the plans ended and why ([`FailureReport::advice`]), or,
    /// when no cause stands out, more samples, a larger motion budget or more plans.
    pub fn advice(&self) -> String {
        self.report.advice().map(|advice| advice.text).unwrap_or_else(|| {
            "raise the refiner's `samples` or the motion budget, or try `--planner topk`"
                .to_string()
        })
    }
}

impl Progress {
    /// What to do about a search stopped before it ended: what was refused where most plans
    /// ended, when that says something ([`FailureReport::advice`]), or that a search left to run
    /// says what stopped it.
    pub fn advice_when_stopped(&self) -> String {
        self.report.advice().map(|advice| advice.text).unwrap_or_else(|| {
            "The search was stopped before it ended: without a time limit it runs its whole \
             budget, and a search that fails says what stopped it."
                .to_string()
        })
    }
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
        let deciding = &self.report.deciding;
        if !deciding.is_empty() {
            let named: Vec<String> =
                deciding.iter().take(NAMED_CAUSES).map(ToString::to_string).collect();
            write!(f, "; {}", named.join("; "))?;
        } else if !self.failure.is_empty() {
            write!(f, "; the deepest refusal: {}", self.failure)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use miette::{GraphicalReportHandler, GraphicalTheme};

    const DOMAIN: &str = "\
(define (domain pick)
  (:requirements :strips :typing)
  (:types can gripper - object)
  (:predicates (holding ?g - gripper ?c - can) (free ?g - gripper) (on-table ?c - can))
  (:action pick
    :parameters (?g - gripper ?c - can)
    :precondition (and (free ?g) (on-table ?c))
    :effect (and (holding ?g ?c) (not (free ?g)) (not (on-table ?c)))))
";

    fn render(error: &SolveError) -> String {
        let mut out = String::new();
        GraphicalReportHandler::new_themed(GraphicalTheme::unicode_nocolor())
            .with_width(100)
            .render_report(&mut out, error)
            .expect("rendering into a String cannot fail");
        out
    }

    #[test]
    fn a_domain_that_does_not_parse_points_into_its_file() {
        let broken = DOMAIN.replace("(free ?g) (on-table", "(free ?g)) (on-table");
        let errors = lamp_pddl::parse_domain(&broken).expect_err("the domain is broken");
        let error = SolveError::pddl("domain", &broken, errors)
            .in_files("build/model/domain.pddl", "build/model/problems/p1.pddl");
        let rendered = render(&error);
        assert!(rendered.contains("[build/model/domain.pddl:7:"), "{rendered}");
        insta::assert_snapshot!(rendered);
    }

    #[test]
    fn a_stopped_search_says_what_stopped_its_plans_when_it_knows() {
        let help = |error: &SolveError| error.help().map(|help| help.to_string());
        let unknown = SolveError::Cancelled(Progress::default());
        assert!(help(&unknown).is_some_and(|text| text.contains("without a time limit")));
        let mut log = crate::failures::FailureLog::default();
        log.start_plan(9);
        log.reached(4, 9);
        let reach =
            crate::failures::Cause::OutOfReach { robot: "yumi".into(), link: "hand".into() };
        log.note(4, "(a5 yumi_gripper goal_p1 p1)", reach, Some(0.2));
        let stopped =
            SolveError::Cancelled(Progress { report: log.report(), ..Progress::default() });
        let text = help(&stopped).expect("a help");
        assert!(text.contains("`yumi` cannot reach where the step puts `hand`"), "{text}");
    }

    #[test]
    fn a_problem_error_names_the_problem_file() {
        let domain = lamp_pddl::parse_domain(DOMAIN).expect("the domain parses");
        let problem = "(define (problem p1) (:domain pick)\n  (:objects g1 - gripper c1 - can)\n  (:init (free g1) (on-tabel c1))\n  (:goal (holding g1 c1)))\n";
        let errors = lamp_pddl::parse_problem(problem, &domain).expect_err("unknown predicate");
        let error = SolveError::pddl("problem", problem, errors)
            .in_files("build/model/domain.pddl", "build/model/problems/p1.pddl");
        let rendered = render(&error);
        assert!(
            rendered.contains(
                "the problem does not parse: 1 PDDL error(s) in build/model/problems/p1.pddl"
            ),
            "{rendered}"
        );
        assert!(rendered.contains("[build/model/problems/p1.pddl:3:"), "{rendered}");
        assert!(rendered.contains("lamp::pddl::unknown_predicate"), "{rendered}");
    }
}
