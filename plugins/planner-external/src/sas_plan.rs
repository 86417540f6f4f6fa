//! Plan files as Fast Downward and K* write them: one `(action arg ...)` per line and a closing
//! `; cost = N (unit cost)` comment.

use lamp_planner::Plan;

/// One parsed plan file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SasPlan {
    /// The steps in order, names in lower case.
    pub plan: Plan,
    /// The cost the planner stated, when it wrote the `; cost = ...` line.
    pub cost: Option<u64>,
}

/// Why a plan file is not a plan.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SasPlanError {
    /// A line that is neither a step nor a comment.
    #[error(transparent)]
    Step(#[from] lamp_planner::PlanParseError),
    /// A `; cost =` comment whose value is not a whole number.
    #[error("line {line}: the cost is not a whole number: {text}")]
    Cost {
        /// The 1-based line.
        line: usize,
        /// The line's text.
        text: String,
    },
    /// A unit-cost plan whose stated cost is not its length: the file was cut or mixed up.
    #[error("the plan states unit cost {cost} but has {steps} steps")]
    CostMismatch {
        /// The stated cost.
        cost: u64,
        /// The steps read.
        steps: usize,
    },
}

/// Parses the text of a `sas_plan` file.
///
/// # Errors
/// [`SasPlanError`] for a line that is not a step, a malformed cost, or a unit-cost plan whose
/// cost is not its length.
pub fn parse_sas_plan(text: &str) -> Result<SasPlan, SasPlanError> {
    let plan = Plan::parse(text)?;
    let mut cost = None;
    let mut unit_cost = false;
    for (index, line) in text.lines().enumerate() {
        let Some(rest) = line.trim().strip_prefix(';') else { continue };
        let Some(value) = rest.trim().strip_prefix("cost") else { continue };
        let Some(value) = value.trim().strip_prefix('=') else { continue };
        let number = value.split_whitespace().next().unwrap_or_default();
        let parsed = number
            .parse::<u64>()
            .map_err(|_| SasPlanError::Cost { line: index + 1, text: line.trim().to_string() })?;
        cost = Some(parsed);
        unit_cost = value.contains("(unit cost)");
    }
    if let Some(cost) = cost.filter(|_| unit_cost) {
        let steps = plan.len();
        if usize::try_from(cost).ok() != Some(steps) {
            return Err(SasPlanError::CostMismatch { cost, steps });
        }
    }
    Ok(SasPlan { plan, cost })
}

#[cfg(test)]
mod tests {
    use super::*;

    const FAST_DOWNWARD: &str = "(pick ball1 rooma left)\n(move rooma roomb)\n\
                                 (drop ball1 roomb left)\n; cost = 3 (unit cost)\n";

    #[test]
    fn steps_and_cost_are_read() {
        let parsed = parse_sas_plan(FAST_DOWNWARD).expect("a plan");
        let steps: Vec<String> = parsed.plan.steps.iter().map(ToString::to_string).collect();
        assert_eq!(
            steps,
            ["(pick ball1 rooma left)", "(move rooma roomb)", "(drop ball1 roomb left)"]
        );
        assert_eq!(parsed.cost, Some(3));
    }

    #[test]
    fn names_are_lowered_and_k_star_costs_are_not_lengths() {
        let parsed = parse_sas_plan("(Move A B)\n; cost = 7 (general cost)\n").expect("a plan");
        assert_eq!(parsed.plan.steps[0].to_string(), "(move a b)");
        assert_eq!(parsed.cost, Some(7), "general costs are not checked against the length");
    }

    #[test]
    fn an_empty_plan_and_a_plan_without_cost_are_plans() {
        let empty = parse_sas_plan("; cost = 0 (unit cost)\n").expect("the empty plan");
        assert!(empty.plan.is_empty());
        let bare = parse_sas_plan("(noop)\n").expect("no cost line");
        assert_eq!((bare.plan.len(), bare.cost), (1, None));
    }

    #[test]
    fn malformed_files_are_refused() {
        assert!(matches!(
            parse_sas_plan("(pick a)\nmove a b\n"),
            Err(SasPlanError::Step(error)) if error.line == 2
        ));
        assert!(matches!(
            parse_sas_plan("(pick a)\n; cost = many (unit cost)\n"),
            Err(SasPlanError::Cost { line: 2, .. })
        ));
        assert_eq!(
            parse_sas_plan(&FAST_DOWNWARD.replace("(move rooma roomb)\n", "")),
            Err(SasPlanError::CostMismatch { cost: 3, steps: 2 })
        );
        assert!(matches!(parse_sas_plan("()\n"), Err(SasPlanError::Step(_))));
    }
}
