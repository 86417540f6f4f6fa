//! How hard a solve tries and what its motions may use: the settings every part of the loop reads.

use lamp_plugin_api::{MotionBudget, PlanBudget};
use lamp_world::MotionConfig;

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
    /// Wasted candidates per plan before it is given up: refused, backtracked over, or needing a
    /// replan (the steps of the plan being refined do not count). This is the least; a plan of
    /// more than `max_refused / WASTED_PER_STEP` steps gets
    /// [`WASTED_PER_STEP`](crate::refine::WASTED_PER_STEP) per step.
    pub max_refused: usize,
    /// Motion settings.
    pub motion: MotionSettings,
    /// Whether to drop goal atoms when no plan reaches the whole goal.
    pub relax_goal: bool,
    /// Whether the user asked to stop; the planner, the refiner, the motion planner and the
    /// final replay all poll it.
    pub cancelled: &'a dyn Fn() -> bool,
}

/// What the motion of one candidate may use.
pub struct MotionSettings {
    /// Resolutions of recording and checking.
    pub config: MotionConfig,
    /// The motion planner's budget per call.
    pub budget: MotionBudget,
    /// Grab distance range per robot name (link origin to object origin), if the spec gives one.
    pub grab_ranges: Vec<(String, (f64, f64))>,
}

/// The grab distance range of every robot whose spec gives one, for [`MotionSettings`].
pub fn grab_ranges(spec: &lamp_spec::Spec) -> Vec<(String, (f64, f64))> {
    spec.robots
        .iter()
        .filter_map(|robot| robot.grab_distance.map(|range| (robot.name.clone(), range)))
        .collect()
}
