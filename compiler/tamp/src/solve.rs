//! The top of the loop: plan, refine, try the next plan, relax the goal, validate.
//!
//! A trajectory to a relaxed goal is a partial result (`Summary::success` false); relaxing until
//! nothing is left to achieve is a failure ([`SolveError::GoalRelaxedAway`]).

use std::collections::BTreeSet;
use std::time::Instant;

use lamp_abstraction::{GroundAtom, SamplerArtifact};
use lamp_participants::ParticipantMap;
use lamp_pddl::{Domain, Problem, parse_domain, parse_problem};
use lamp_plugin_api::GroundedAction;
use lamp_robot::Robot;
use lamp_trajectory::{Trajectory, TrajectoryHeader};
use lamp_world::{ApproachKind, Recorder, Scene, WorldError, time_steps};

use crate::error::{Progress, SolveError};
use crate::ground::{call_text, ground_step, pddl_atom};
use crate::planning::{Planned, explain_no_plan, goal_holds_initially, plans, relax};
use crate::plugins::Plugins;
use crate::refine::{Context, PlanToRefine, RefineCounts, Refined, difference, mix, refine_plan};
use crate::settings::SolveSettings;
use crate::state::abstraction;
use crate::summary::{ApproachEnd, ApproachSpan, Summary};
use crate::validate::{Expected, replay};

/// What a solve reads.
pub struct SolveInput<'a> {
    /// The problem's initial scene.
    pub scene: &'a Scene,
    /// The learned domain and the problem, as PDDL text.
    pub domain: &'a str,
    pub problem: &'a str,
    /// The learned regions.
    pub artifact: &'a SamplerArtifact,
    /// How scenes map to participants.
    pub participants: &'a ParticipantMap,
    /// Where the problem wants objects, with tolerances: its AtGoal targets and its structure's
    /// poses (`SpecWorld::placement_targets`). Their markers are in `scene`, their goal atoms in
    /// `problem`; the tolerances are checked in the world frame.
    pub targets: &'a [lamp_spec::AtGoal],
    /// The header of the trajectory to write.
    pub header: TrajectoryHeader,
}

/// A solved problem.
pub struct Solution {
    /// The validated trajectory.
    pub trajectory: Trajectory,
    /// Per step of `summary.plan`, the index of the trajectory step its motion begins with
    /// (steps before the first one's are the initial state).
    pub step_starts: Vec<usize>,
    /// What happened.
    pub summary: Summary,
}

/// Solves one problem; `progress` is told what phase the solve is in.
pub fn solve(
    input: &SolveInput<'_>,
    plugins: &mut Plugins<'_>,
    settings: &SolveSettings<'_>,
    progress: &dyn Fn(&str),
) -> Result<Solution, SolveError> {
    let domain = parse_domain(input.domain)
        .map_err(|errors| SolveError::pddl("domain", input.domain, errors))?;
    let mut problem = parse_problem(input.problem, &domain)
        .map_err(|errors| SolveError::pddl("problem", input.problem, errors))?;
    let initial_state = abstraction(input.artifact, input.participants, input.scene)?;
    let init: BTreeSet<GroundAtom> = problem.init.iter().map(pddl_atom).collect();
    if init != initial_state {
        return Err(SolveError::StaleProblem {
            problem: problem.name.clone(),
            difference: difference(&initial_state, &init),
        });
    }
    let mut summary = Summary { problem: problem.name.clone(), ..Summary::default() };
    let mut counts = RefineCounts::default();
    let inputs = LoopInputs { input, settings, progress, domain: &domain };
    let outcome = solve_with(&inputs, plugins, &mut problem, &mut summary, &mut counts);
    outcome.map_err(|error| match error {
        SolveError::Cancelled(_) => SolveError::Cancelled(progress_of(&summary, &counts)),
        other => other,
    })
}

/// What the loop of [`solve`] reads and never changes.
#[derive(Clone, Copy)]
struct LoopInputs<'a> {
    input: &'a SolveInput<'a>,
    settings: &'a SolveSettings<'a>,
    progress: &'a dyn Fn(&str),
    domain: &'a Domain,
}

/// The loop of [`solve`], which fills `summary` and `counts` as it goes.
fn solve_with(
    inputs: &LoopInputs<'_>,
    plugins: &mut Plugins<'_>,
    problem: &mut Problem,
    summary: &mut Summary,
    counts: &mut RefineCounts,
) -> Result<Solution, SolveError> {
    let LoopInputs { input, settings, progress, domain } = *inputs;
    let mut attempts = 0;
    loop {
        progress("planning");
        let started = Instant::now();
        let found = plans(plugins, domain, problem, settings.plan_count, settings)?;
        summary.seconds_planning += started.elapsed().as_secs_f64();
        let found = match found {
            Planned::Plans(found) => found,
            // Relaxing would drop a goal atom a plan may well reach: the planner only stopped.
            Planned::OutOfBudget => {
                let relaxed = summary.relaxed_goal.join(", ");
                return Err(SolveError::PlannerBudget { relaxed });
            }
            Planned::NoPlan(reason) => {
                let relaxed = if settings.relax_goal { relax(domain, problem) } else { None };
                let Some(dropped) = relaxed else {
                    let mut reason = match summary.relaxed_goal.is_empty() {
                        true => reason,
                        false => {
                            format!("{reason} (after dropping {})", summary.relaxed_goal.join(", "))
                        }
                    };
                    if let Some(why) = explain_no_plan(plugins, domain, problem, settings)? {
                        reason = format!("{reason}; {why}");
                    }
                    return Err(SolveError::NoPlan { reason });
                };
                summary.relaxed_goal.push(dropped);
                if goal_holds_initially(problem) {
                    // Nothing the problem asks for would be achieved: a failure, not a result.
                    let dropped = summary.relaxed_goal.join(", ");
                    return Err(SolveError::GoalRelaxedAway { dropped, reason });
                }
                continue;
            }
        };
        let problem = &*problem;
        let context = Context {
            domain,
            problem,
            artifact: input.artifact,
            participants: input.participants,
            targets: input.targets,
            settings,
        };
        let goal: BTreeSet<GroundAtom> =
            problem.goal.iter().filter(|l| l.positive).map(|l| pddl_atom(&l.atom)).collect();
        let started = Instant::now();
        for round in 0..settings.rounds {
            for (index, plan) in found.iter().enumerate() {
                attempts += 1;
                summary.plans_tried += 1;
                progress(&format!(
                    "refining plan {} of {} (round {})",
                    index + 1,
                    found.len(),
                    round + 1
                ));
                let actions = plan
                    .steps
                    .iter()
                    .map(|step| ground_step(domain, problem, step))
                    .collect::<Result<Vec<GroundedAction>, _>>()?;
                let mut recorder = Recorder::default();
                recorder.record(input.scene);
                let seed = mix(settings.seed, attempts, 0);
                let plan =
                    PlanToRefine { initial: input.scene, actions: &actions, goal: &goal, seed };
                let outcome = refine_plan(&context, plugins, &plan, &mut recorder, counts)?;
                if let Refined::Done { steps, starts, replans, .. } = outcome {
                    summary.seconds_refining += started.elapsed().as_secs_f64();
                    progress("validating");
                    let started = Instant::now();
                    // Timed before the replay, so that the replay checks the positions written:
                    // timing turns wrapped angles the short way round.
                    let robots: Vec<&Robot> =
                        input.scene.robots().iter().map(|robot| robot.robot().as_ref()).collect();
                    let execution =
                        time_steps(&mut recorder.steps, &robots).map_err(|error| match error {
                            WorldError::Timing { step, reason } => SolveError::InvalidSolution {
                                step,
                                reason: format!("it cannot be timed: {reason}"),
                            },
                            other => {
                                SolveError::InvalidSolution { step: 0, reason: other.to_string() }
                            }
                        })?;
                    summary.execution_seconds = execution as f64 / 1e9;
                    let replayed = replay(
                        input.scene,
                        &recorder.steps,
                        &settings.motion.config,
                        input.artifact,
                        input.participants,
                        &Expected { goal: &goal, targets: input.targets },
                        settings.cancelled,
                    )?;
                    summary.sink = replayed.sink;
                    summary.seconds_validating = started.elapsed().as_secs_f64();
                    summary.success = !summary.is_partial();
                    summary.plan =
                        steps.iter().map(|step| call_text(&step.name, &step.arguments)).collect();
                    summary.replan_points = replans;
                    summary.approaches = approach_spans(input.scene, &recorder, &starts);
                    fill(summary, counts, recorder.len());
                    let trajectory =
                        Trajectory { header: input.header.clone(), steps: recorder.steps };
                    return Ok(Solution {
                        trajectory,
                        step_starts: starts,
                        summary: summary.clone(),
                    });
                }
            }
        }
        fill(summary, counts, 0);
        return Err(SolveError::RefinementFailed(progress_of(summary, counts)));
    }
}

fn progress_of(summary: &Summary, counts: &RefineCounts) -> Progress {
    Progress {
        plans: summary.plans_tried,
        candidates: counts.candidates,
        deepest: counts.deepest,
        length: counts.deepest_of,
        failure: counts.deepest_failure.clone(),
        report: counts.failures.report(),
        deepest_state: counts.deepest_state.clone(),
    }
}

/// The recorded approaches, named and stamped; `starts` are the plan steps' first recorded steps.
fn approach_spans(scene: &Scene, recorder: &Recorder, starts: &[usize]) -> Vec<ApproachSpan> {
    let seconds = |step: usize| {
        recorder.steps.get(step).map_or(0.0, |step| step.time_nanoseconds as f64 / 1e9)
    };
    recorder
        .approaches
        .iter()
        .map(|approach| ApproachSpan {
            from_step: approach.from_step,
            plan_step: starts.iter().filter(|&&start| start <= approach.to_step).count(),
            kind: match approach.kind {
                ApproachKind::PutDown => ApproachEnd::PutDown,
                ApproachKind::Contact => ApproachEnd::Contact,
            },
            robot: scene.robots()[approach.robot].name.clone(),
            object: scene.bodies()[approach.body].name.clone(),
            from_seconds: seconds(approach.from_step),
            to_seconds: seconds(approach.to_step),
            metres: approach.metres,
        })
        .collect()
}

fn fill(summary: &mut Summary, counts: &RefineCounts, steps: usize) {
    summary.candidates = counts.candidates;
    summary.backtracks = counts.backtracks;
    summary.motion_calls = counts.motion.calls;
    summary.motion_failures = counts.motion.failures;
    summary.replans = counts.replans;
    summary.postponements = counts.postponements;
    summary.trajectory_steps = steps;
}
