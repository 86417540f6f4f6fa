//! Calls to the planner plugin: the plans for a problem, the plan from a state reached during
//! refinement, and relaxing a goal no plan reaches.

use std::collections::BTreeSet;

use lamp_abstraction::GroundAtom;
use lamp_pddl::{Condition, Domain, Problem, write_domain, write_problem};
use lamp_plugin_api::{GroundedAction, HostServices, Plan, PlanRequest, PlanStatus};

use crate::error::SolveError;
use crate::ground::{ground_step, pddl_atom};
use crate::plugins::Plugins;
use crate::settings::SolveSettings;

/// What the planner answered.
pub enum Planned {
    /// At least one plan, at most the number asked for.
    Plans(Vec<Plan>),
    /// No plan exists, and why.
    NoPlan(String),
    /// The planner's budget ran out before it found a plan: whether one exists is not known.
    OutOfBudget,
}

/// Plans for `problem` (at most `plan_count`) or why there is none; `Err` is a planner failure.
pub fn plans(
    plugins: &mut Plugins<'_>,
    domain: &Domain,
    problem: &Problem,
    plan_count: usize,
    settings: &SolveSettings<'_>,
) -> Result<Planned, SolveError> {
    let mut request = PlanRequest::new(write_domain(domain), write_problem(problem));
    request.plan_count = plan_count.max(1);
    request.budget = settings.planner_budget;
    request.seed = settings.seed;
    let host = Cancellation(settings.cancelled);
    let response = plugins
        .planner
        .plan(&request, &host)
        .map_err(|error| SolveError::from_plugin("planner", error))?;
    if !response.plans.is_empty() {
        return Ok(Planned::Plans(response.plans));
    }
    Ok(Planned::NoPlan(match response.status {
        PlanStatus::Unsolvable { reason } => reason,
        PlanStatus::BudgetExhausted => return Ok(Planned::OutOfBudget),
        PlanStatus::Failed { message } => {
            return Err(SolveError::PluginAnswer { kind: "planner", reason: message });
        }
        // "Solved" with nothing in hand is the planner's fault, not the goal's: relaxing the
        // goal would blame the learned model.
        PlanStatus::Solved => {
            return Err(SolveError::PluginAnswer {
                kind: "planner",
                reason: "it answered `solved` but returned no plan (the goal was not found \
                         unreachable; check the planner's configuration)"
                    .to_string(),
            });
        }
    }))
}

/// How the goal is reached from a state met during refinement.
#[derive(Clone, Debug)]
pub enum Rest {
    /// The planner's plan from there, grounded.
    Plan(Vec<GroundedAction>),
    /// No plan reaches the goal from there.
    Unreachable,
    /// The planner's budget ran out before it found one: whether one exists is not known.
    OutOfBudget,
}

/// One plan from `state` to `problem`'s goal, grounded, or why there is none.
pub fn plan_from(
    plugins: &mut Plugins<'_>,
    domain: &Domain,
    problem: &Problem,
    state: &BTreeSet<GroundAtom>,
    settings: &SolveSettings<'_>,
) -> Result<Rest, SolveError> {
    let mut from = problem.clone();
    from.init = state
        .iter()
        .map(|atom| {
            let objects: Vec<&str> = atom.arguments.iter().map(String::as_str).collect();
            lamp_pddl::Atom::ground(atom.predicate.clone(), &objects)
        })
        .collect();
    let found = match plans(plugins, domain, &from, 1, settings)? {
        Planned::Plans(found) => found,
        Planned::NoPlan(_) => return Ok(Rest::Unreachable),
        Planned::OutOfBudget => return Ok(Rest::OutOfBudget),
    };
    let Some(plan) = found.into_iter().next() else { return Ok(Rest::Unreachable) };
    plan.steps
        .iter()
        .map(|step| ground_step(domain, problem, step))
        .collect::<Result<Vec<_>, _>>()
        .map(Rest::Plan)
}

/// Drops the goal atom whose predicate appears least often in action preconditions (ties: the
/// last in goal order); returns it, or `None` when at most one atom is left. A negated
/// `nowhere_R` or `clear_R` precondition counts as a use of `R`: it is how the learner writes "`R`
/// with some object" (docs/learning.md).
pub fn relax(domain: &Domain, problem: &mut Problem) -> Option<String> {
    if problem.goal.len() <= 1 {
        return None;
    }
    let uses = |predicate: &str| {
        let mentions = |condition: &&Condition| match condition {
            Condition::Atom { atom, positive: true } => atom.predicate == predicate,
            Condition::Atom { atom, positive: false } => {
                let name = atom.predicate.as_str();
                name == predicate
                    || [name.strip_prefix("nowhere_"), name.strip_prefix("clear_")]
                        .contains(&Some(predicate))
            }
            Condition::Equality { .. } => false,
        };
        domain.actions.iter().flat_map(|action| &action.precondition).filter(mentions).count()
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

/// Goals of more literals than this are not taken apart when no plan reaches them: each
/// literal costs a planner call, and a proof that none exists can take as long as the first.
pub const MAX_EXPLAINED_GOAL: usize = 16;

/// Why no plan reaches `problem`'s goal, in the goal's own atoms, when the planner proved that
/// none does: the literals without any one of which a plan exists (they cannot all hold
/// together in the learned model), or else those that no plan reaches even alone. `None` when
/// the goal has one literal, more than [`MAX_EXPLAINED_GOAL`], or the planner could not tell
/// (its budget ran out).
pub fn explain_no_plan(
    plugins: &mut Plugins<'_>,
    domain: &Domain,
    problem: &Problem,
    settings: &SolveSettings<'_>,
) -> Result<Option<String>, SolveError> {
    let goal = &problem.goal;
    if goal.len() <= 1 || goal.len() > MAX_EXPLAINED_GOAL {
        return Ok(None);
    }
    let text = |literal: &lamp_pddl::Literal| {
        let atom = pddl_atom(&literal.atom).to_string();
        if literal.positive { atom } else { format!("(not {atom})") }
    };
    let mut in_conflict = Vec::new();
    for (index, literal) in goal.iter().enumerate() {
        let mut without = problem.clone();
        without.goal.remove(index);
        match plans(plugins, domain, &without, 1, settings)? {
            Planned::Plans(_) => in_conflict.push(text(literal)),
            Planned::NoPlan(_) => {}
            Planned::OutOfBudget => return Ok(None),
        }
    }
    if !in_conflict.is_empty() {
        return Ok(Some(format!(
            "the goal's {} cannot all hold together in the learned model: without any one of them \
             a plan exists",
            in_conflict.join(", ")
        )));
    }
    let mut unreachable = Vec::new();
    for literal in goal {
        let mut alone = problem.clone();
        alone.goal = vec![literal.clone()];
        match plans(plugins, domain, &alone, 1, settings)? {
            Planned::Plans(_) => {}
            Planned::NoPlan(_) => unreachable.push(text(literal)),
            Planned::OutOfBudget => return Ok(None),
        }
    }
    Ok((!unreachable.is_empty())
        .then(|| format!("no plan reaches {} even alone", unreachable.join(", "))))
}

/// Whether every goal literal of `problem` already holds in its initial state, so that a plan has
/// nothing to achieve (what is left of a goal relaxed too far).
pub fn goal_holds_initially(problem: &Problem) -> bool {
    let init: BTreeSet<GroundAtom> = problem.init.iter().map(pddl_atom).collect();
    problem.goal.iter().all(|literal| init.contains(&pddl_atom(&literal.atom)) == literal.positive)
}

/// Host services for the planner: cancellation only.
struct Cancellation<'a>(&'a dyn Fn() -> bool);

impl HostServices for Cancellation<'_> {
    fn is_cancelled(&self) -> bool {
        (self.0)()
    }
}
