//! The run summary written next to the trajectory: what was solved, how, and how long each phase
//! took.

use serde::Serialize;

/// What one solve did.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Summary {
    /// The problem's name.
    pub problem: String,
    /// Whether a validated trajectory was produced.
    pub success: bool,
    /// Goal atoms dropped because no plan reaches them (empty when the goal was kept whole).
    pub relaxed_goal: Vec<String>,
    /// The refined plan, one `(action args…)` per step.
    pub plan: Vec<String>,
    /// Symbolic plans tried (each refinement round counts every plan it tries).
    pub plans_tried: usize,
    /// Refiner candidates tried.
    pub candidates: usize,
    /// Times the refinement went back to an earlier step.
    pub backtracks: usize,
    /// Times a step's side effect broke the rest of the plan and the planner was asked again
    /// from the reached state.
    pub replans: usize,
    /// Motion-planner calls, and how many found no path.
    pub motion_calls: usize,
    pub motion_failures: usize,
    /// Recorded trajectory steps.
    pub trajectory_steps: usize,
    /// Seconds spent planning, refining (sampling, IK, motion) and validating.
    pub seconds_planning: f64,
    pub seconds_refining: f64,
    pub seconds_validating: f64,
}
