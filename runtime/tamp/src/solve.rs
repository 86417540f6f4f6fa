//! The top of the loop: plan, refine, try the next plan, relax the goal, validate.

use std::collections::BTreeSet;
use std::time::Instant;

use lamp_build::Adapter;
use lamp_learn::{GroundAtom, SamplerArtifact};
use lamp_pddl::{Condition, Domain, Problem, parse_domain, parse_problem, write_problem};
use lamp_plugin_api::{
    GroundedAction, HostServices, Plan, PlanBudget, PlanRequest, PlanStatus, PluginError,
};
use lamp_trajectory::{Trajectory, TrajectoryHeader};
use lamp_world::{Recorder, Scene};

use crate::error::SolveError;
use crate::execute::MotionSettings;
use crate::ground::{ground_step, pddl_atom, step_text};
use crate::plugins::Plugins;
use crate::refine::{RefineCounts, Refined, difference, mix, refine_plan};
use crate::state::abstraction;
use crate::summary::Summary;
use crate::validate::replay;

/// How hard a solve tries.
pub struct SolveSettings<'a> {
    /// The one seed of the run.
    pub seed: u64,
    /// Plans asked of the planner per call (the planner may return fewer).
    pub plan_count: usize,
    /// The planner's budget per call.
    pub planner_budget: PlanBudget,
    /// Rounds over the plans, each with fresh samples.
    pub rounds: usize,
    /// Refiner candidates per plan before it is given up.
    pub max_candidates: usize,
    /// Motion settings.
    pub motion: MotionSettings<'a>,
    /// Whether to drop goal atoms when no plan reaches the whole goal.
    pub relax_goal: bool,
}

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
    pub adapter: &'a Adapter,
    /// The header of the trajectory to write.
    pub header: TrajectoryHeader,
}

/// What the refinement loop shares.
pub struct Context<'a> {
    pub artifact: &'a SamplerArtifact,
    pub adapter: &'a Adapter,
    pub settings: &'a SolveSettings<'a>,
    pub cancelled: &'a dyn Fn() -> bool,
}

/// A solved problem.
pub struct Solution {
    /// The validated trajectory.
    pub trajectory: Trajectory,
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
        .map_err(|errors| SolveError::Pddl { what: "domain".into(), reason: errors.to_string() })?;
    let mut problem = parse_problem(input.problem, &domain).map_err(|errors| SolveError::Pddl {
        what: "problem".into(),
        reason: errors.to_string(),
    })?;
    let initial_state = abstraction(input.artifact, input.adapter, input.scene)?;
    let init: BTreeSet<GroundAtom> = problem.init.iter().map(pddl_atom).collect();
    if init != initial_state {
        return Err(SolveError::StaleProblem {
            problem: problem.name.clone(),
            difference: difference(&initial_state, &init),
        });
    }
    let context = Context {
        artifact: input.artifact,
        adapter: input.adapter,
        settings,
        cancelled: settings.motion.cancelled,
    };
    let mut summary = Summary { problem: problem.name.clone(), ..Summary::default() };
    let mut counts = RefineCounts::default();
    let mut attempts = 0;
    loop {
        progress("planning");
        let started = Instant::now();
        let plans = plan(plugins, &domain, &problem, settings)?;
        summary.seconds_planning += started.elapsed().as_secs_f64();
        let plans = match plans {
            Ok(plans) => plans,
            Err(reason) => {
                let Some(dropped) = relax(&domain, &mut problem).filter(|_| settings.relax_goal)
                else {
                    return Err(SolveError::NoPlan { reason });
                };
                summary.relaxed_goal.push(dropped);
                continue;
            }
        };
        let started = Instant::now();
        for round in 0..settings.rounds {
            for (index, plan) in plans.iter().enumerate() {
                attempts += 1;
                summary.plans_tried += 1;
                progress(&format!(
                    "refining plan {} of {} (round {})",
                    index + 1,
                    plans.len(),
                    round + 1
                ));
                let actions = plan
                    .steps
                    .iter()
                    .map(|step| ground_step(&domain, step))
                    .collect::<Result<Vec<GroundedAction>, _>>()?;
                let goal: BTreeSet<GroundAtom> = problem
                    .goal
                    .iter()
                    .filter(|l| l.positive)
                    .map(|l| pddl_atom(&l.atom))
                    .collect();
                let mut recorder = Recorder::default();
                recorder.record(input.scene);
                let seed = mix(settings.seed, attempts, 0);
                let outcome = refine_plan(
                    &context,
                    plugins,
                    input.scene,
                    &actions,
                    &goal,
                    seed,
                    &mut recorder,
                    &mut counts,
                )?;
                if let Refined::Done(_) = outcome {
                    summary.seconds_refining += started.elapsed().as_secs_f64();
                    progress("validating");
                    let started = Instant::now();
                    replay(
                        input.scene,
                        &recorder.steps,
                        &settings.motion.config,
                        input.artifact,
                        input.adapter,
                        &goal,
                    )?;
                    summary.seconds_validating = started.elapsed().as_secs_f64();
                    summary.success = true;
                    summary.plan = plan.steps.iter().map(step_text).collect();
                    fill(&mut summary, &counts, recorder.len());
                    let trajectory =
                        Trajectory { header: input.header.clone(), steps: recorder.steps };
                    return Ok(Solution { trajectory, summary });
                }
            }
        }
        fill(&mut summary, &counts, 0);
        let length = plans.iter().map(|plan| plan.steps.len()).max().unwrap_or(0);
        return Err(SolveError::RefinementFailed {
            plans: summary.plans_tried,
            candidates: counts.candidates,
            deepest: counts.deepest,
            length,
            last_failure: counts.last_failure,
        });
    }
}

fn fill(summary: &mut Summary, counts: &RefineCounts, steps: usize) {
    summary.candidates = counts.candidates;
    summary.backtracks = counts.backtracks;
    summary.motion_calls = counts.motion.calls;
    summary.motion_failures = counts.motion.failures;
    summary.trajectory_steps = steps;
}

/// Plans, or why there is no plan (`Err` inside `Ok`), or a planner failure.
fn plan(
    plugins: &mut Plugins<'_>,
    domain: &Domain,
    problem: &Problem,
    settings: &SolveSettings<'_>,
) -> Result<Result<Vec<Plan>, String>, SolveError> {
    let mut request = PlanRequest::new(lamp_pddl::write_domain(domain), write_problem(problem));
    request.plan_count = settings.plan_count.max(1);
    request.budget = settings.planner_budget;
    request.seed = settings.seed;
    let host = Cancellation(settings.motion.cancelled);
    let response = plugins.planner.plan(&request, &host).map_err(|error| match error {
        PluginError::Cancelled => SolveError::Cancelled,
        other => SolveError::Plugin { kind: "planner", reason: other.to_string() },
    })?;
    if !response.plans.is_empty() {
        return Ok(Ok(response.plans));
    }
    Ok(Err(match response.status {
        PlanStatus::Unsolvable { reason } => reason,
        PlanStatus::BudgetExhausted => "the planner's budget ran out".to_string(),
        PlanStatus::Failed { message } => {
            return Err(SolveError::Plugin { kind: "planner", reason: message });
        }
        PlanStatus::Solved => "the planner returned no plan".to_string(),
    }))
}

/// Drops the goal atom whose predicate appears least often in action preconditions (ties: the
/// last in goal order); returns it, or `None` when at most one atom is left.
fn relax(domain: &Domain, problem: &mut Problem) -> Option<String> {
    if problem.goal.len() <= 1 {
        return None;
    }
    let uses = |predicate: &str| {
        domain
            .actions
            .iter()
            .flat_map(|action| &action.precondition)
            .filter(|condition| {
                matches!(condition, Condition::Atom { atom, .. } if atom.predicate == predicate)
            })
            .count()
    };
    let (index, _) = problem
        .goal
        .iter()
        .enumerate()
        .map(|(index, literal)| (index, uses(&literal.atom.predicate)))
        .min_by_key(|&(index, count)| (count, std::cmp::Reverse(index)))?;
    let dropped = problem.goal.remove(index);
    Some(pddl_atom(&dropped.atom).to_string())
}

/// Host services for the planner: cancellation only.
struct Cancellation<'a>(&'a dyn Fn() -> bool);

impl HostServices for Cancellation<'_> {
    fn is_cancelled(&self) -> bool {
        (self.0)()
    }
}
