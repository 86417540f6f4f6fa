//! lamp-tamp: task and motion planning over a learned model (paper App. F).
//!
//! [`solve`] plans with the planner plugin (k plans), refines each plan's actions in order with the
//! refiner plugin's candidate streams and chronological backtracking ([`refine`]), moves the robot
//! with the motion-planner plugin for every configuration change ([`execute`]), and checks after
//! every step that the step's effects hold in the learned abstraction of the reached state and
//! that the rest of the plan still runs from there to the goal. When no plan refines, the next of the k plans is tried, then all of them again with
//! fresh samples; when the planner proves the goal unreachable, the goal is relaxed (the relation
//! used least in action preconditions dropped first) and the summary says so. The finished
//! trajectory is replayed from the initial scene ([`validate`]), and its final scene simulated
//! under gravity ([`at_rest`]), before it is returned.
//!
//! Pure: values in, values out. Plugins arrive as trait objects; files, terminals and libraries
//! are `lampc`'s.

pub mod at_rest;
pub mod error;
pub mod execute;
pub mod failures;
pub mod ground;
pub mod host;
pub mod plugins;
pub mod poses;
pub mod postpone;
pub mod refine;
pub mod settings;
pub mod state;
pub mod summary;
pub mod targets;
pub mod validate;

mod planning;
mod solve;

pub use error::{Progress, SolveError};
pub use plugins::Plugins;
pub use refine::{Context, WASTED_PER_STEP};
pub use settings::{MotionSettings, SolveSettings, grab_ranges};
pub use solve::{Solution, SolveInput, solve};
pub use summary::{ApproachEnd, ApproachSpan, ObjectPose, ReplanPoint, Sink, Summary};
