//! The three plugins a solve uses, as trait objects: the runtime never knows whether they are
//! linked in or loaded from a library.

use lamp_plugin_api::{MotionPlanner, Planner, Refiner};

/// The planner, refiner and motion planner of one solve.
pub struct Plugins<'a> {
    pub planner: &'a mut dyn Planner,
    pub refiner: &'a mut dyn Refiner,
    pub motion: &'a mut dyn MotionPlanner,
}
