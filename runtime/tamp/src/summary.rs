//! The run summary written next to the trajectory: what was solved, how, and how long each phase
//! took.
//!
//! A summary exists only for a validated trajectory. It is a success when the trajectory reaches
//! the whole goal, and a partial result when goal atoms had to be dropped (`relaxed_goal`).

use serde::Serialize;

/// What one solve did.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Summary {
    /// The problem's name.
    pub problem: String,
    /// Whether the validated trajectory reaches the whole goal; false for a partial result, whose
    /// trajectory reaches the goal without the atoms in `relaxed_goal`.
    pub success: bool,
    /// Goal atoms dropped because no plan reaches them, in the order they were dropped (empty when
    /// the goal was kept whole).
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

impl Summary {
    /// Whether the trajectory reaches only a relaxed goal: some goal atoms were dropped.
    pub fn is_partial(&self) -> bool {
        !self.relaxed_goal.is_empty()
    }
}
