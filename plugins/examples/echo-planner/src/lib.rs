//! An example planner plugin, small enough to read in one sitting: it answers a planning request
//! with one `achieve` step per atom of the problem's goal, in the order written. It does not
//! search and does not read the domain; it shows how a plugin is written with lamp-plugin-sdk
//! (statuses, budget, progress, cancellation) and serves as the fixture of the host's loading
//! tests. Build it as a shared library with `cargo build -p echo-planner`.

mod sexpr;

use lamp_plugin_api::{
    HostServices, Plan, PlanRequest, PlanResponse, PlanStatus, PlanStep, Planner, PluginConfig,
    PluginError,
};
use lamp_plugin_sdk::{PluginFactory, export_plugin};

use crate::sexpr::{Expression, parse};

/// The name of the step each goal atom becomes.
pub const ACHIEVE: &str = "achieve";

/// The example planner. It reads no options: its configuration is empty or `{}`.
#[derive(Clone, Copy, Debug, Default)]
pub struct EchoPlanner;

impl PluginFactory for EchoPlanner {
    fn create(config: &[u8]) -> Result<Self, PluginError> {
        // Reading the one configuration format, even with nothing to read, refuses any option.
        PluginConfig::parse(config)?.finish()?;
        Ok(EchoPlanner)
    }
}

impl Planner for EchoPlanner {
    fn plan(
        &mut self,
        request: &PlanRequest,
        host: &dyn HostServices,
    ) -> Result<PlanResponse, PluginError> {
        host.report_progress(0.0, "reading the goal");
        if host.is_cancelled() {
            return Err(PluginError::Cancelled);
        }
        let atoms = match goal_atoms(&request.problem) {
            Ok(atoms) => atoms,
            Err(message) => {
                return Ok(PlanResponse {
                    status: PlanStatus::Failed { message },
                    plans: Vec::new(),
                });
            }
        };
        // One "expansion" per step, so that the budget means something even here.
        let steps = u64::try_from(atoms.len()).unwrap_or(u64::MAX);
        if request.budget.max_expansions.is_some_and(|limit| steps > limit) {
            return Ok(PlanResponse { status: PlanStatus::BudgetExhausted, plans: Vec::new() });
        }
        let plan = Plan {
            steps: atoms
                .into_iter()
                .map(|atom| PlanStep { action: ACHIEVE.to_string(), arguments: atom })
                .collect(),
        };
        host.report_progress(1.0, "done");
        // There is only one such plan, so a top-k request is solved by it too.
        Ok(PlanResponse { status: PlanStatus::Solved, plans: vec![plan] })
    }
}

/// The atoms of the problem's `(:goal ...)`, each as its predicate followed by its arguments.
///
/// # Errors
/// A message when the text is not an s-expression, has no goal, or the goal is not a
/// conjunction of positive atoms.
pub fn goal_atoms(problem: &str) -> Result<Vec<Vec<String>>, String> {
    let expression = parse(problem)?;
    let goal = find_goal(&expression).ok_or("the problem has no (:goal ...) section")?;
    let mut atoms = Vec::new();
    collect_atoms(goal, &mut atoms)?;
    Ok(atoms)
}

fn find_goal(expression: &Expression) -> Option<&Expression> {
    let Expression::List(items) = expression else { return None };
    if let [Expression::Symbol(head), goal] = items.as_slice()
        && head.eq_ignore_ascii_case(":goal")
    {
        return Some(goal);
    }
    items.iter().find_map(find_goal)
}

fn collect_atoms(formula: &Expression, atoms: &mut Vec<Vec<String>>) -> Result<(), String> {
    let Expression::List(items) = formula else {
        return Err(format!("the goal has a bare symbol {formula} where an atom was expected"));
    };
    match items.first() {
        Some(Expression::Symbol(head)) if head.eq_ignore_ascii_case("and") => {
            items[1..].iter().try_for_each(|item| collect_atoms(item, atoms))
        }
        Some(Expression::Symbol(head))
            if ["not", "or", "imply", "forall", "exists"]
                .iter()
                .any(|keyword| head.eq_ignore_ascii_case(keyword)) =>
        {
            Err(format!("echo-planner only echoes positive atoms, not {formula}"))
        }
        Some(Expression::Symbol(_)) => {
            let mut atom = Vec::with_capacity(items.len());
            for item in items {
                match item {
                    Expression::Symbol(symbol) => atom.push(symbol.clone()),
                    Expression::List(_) => return Err(format!("{formula} is not an atom")),
                }
            }
            atoms.push(atom);
            Ok(())
        }
        _ => Err(format!("{formula} is not an atom")),
    }
}

export_plugin! {
    planner: EchoPlanner,
    name: "echo-planner",
    version: env!("CARGO_PKG_VERSION"),
    description: "Example planner: one `achieve` step per goal atom.",
}

#[cfg(test)]
mod tests {
    use lamp_plugin_api::{MinimalHost, PlanBudget};

    use super::*;

    const PROBLEM: &str = "; a comment (with parentheses)
        (define (problem stack) (:domain blocks)
          (:objects a b c)
          (:init (clear a) (on a b))
          (:goal (and (on b c) (and (on a b)) (clear a))))";

    fn strings(atom: &[&str]) -> Vec<String> {
        atom.iter().map(ToString::to_string).collect()
    }

    #[test]
    fn goal_atoms_are_read_in_order_through_nested_conjunctions() {
        let atoms = goal_atoms(PROBLEM).unwrap();
        assert_eq!(
            atoms,
            vec![strings(&["on", "b", "c"]), strings(&["on", "a", "b"]), strings(&["clear", "a"])]
        );
        assert_eq!(
            goal_atoms("(define (problem p) (:goal (done)))").unwrap(),
            vec![strings(&["done"])]
        );
    }

    #[test]
    fn unsupported_or_missing_goals_are_reported() {
        assert_eq!(
            goal_atoms("(define (problem p))").unwrap_err(),
            "the problem has no (:goal ...) section"
        );
        assert!(
            goal_atoms("(define (problem p) (:goal (not (on a b))))")
                .unwrap_err()
                .contains("(not (on a b))")
        );
        assert!(goal_atoms("(define (problem p) (:goal (and (on a b)").is_err());
    }

    #[test]
    fn the_planner_answers_with_statuses() {
        let mut planner = EchoPlanner::create(&[]).unwrap();
        let mut request = PlanRequest::new("(define (domain blocks))", PROBLEM);
        let response = planner.plan(&request, &MinimalHost).unwrap();
        assert_eq!(response.status, PlanStatus::Solved);
        assert_eq!(
            response.plans[0].steps[1],
            PlanStep { action: ACHIEVE.into(), arguments: strings(&["on", "a", "b"]) }
        );
        request.budget = PlanBudget { max_expansions: Some(2), time_limit: None };
        assert_eq!(
            planner.plan(&request, &MinimalHost).unwrap().status,
            PlanStatus::BudgetExhausted
        );
        request.problem = "(define (problem p)".into();
        assert!(matches!(
            planner.plan(&request, &MinimalHost).unwrap().status,
            PlanStatus::Failed { .. }
        ));
        assert!(EchoPlanner::create(b"x").is_err());
    }
}
