//! The safe contract between the lamp runtime and its plugins.
//!
//! Three plugin kinds, one trait each: [`Planner`] (PDDL domain and problem in, plans out),
//! [`Refiner`] (a grounded action and the world state in, a backtrackable [`CandidateStream`] of
//! target configurations out) and [`MotionPlanner`] (start and goal configurations in, a path out).
//! Every call receives the host's [`HostServices`]: progress, cancellation and the geometric
//! oracles (validity, inverse and forward kinematics, distance, interpolation, sampling);
//! randomness comes from the `seed` of each request, which a plugin feeds to its own `ChaCha8Rng`.
//!
//! The runtime sees `Box<dyn Planner>` (and so on) whether a plugin is linked statically or loaded
//! from a shared library by lamp-plugin-host. The structured inputs that cross a library boundary
//! as documents are defined in [`wire`], separate from any type inside the compiler or runtime.
//!
//! This crate depends on no other lamp crate, so the compiler's and runtime's internals can change
//! without breaking plugins.

#![deny(missing_docs)]

pub mod config;
mod error;
mod host;
mod motion;
mod planner;
mod refiner;
pub mod wire;

pub use config::{ConfigError, PluginConfig};
pub use error::{HostError, PluginError};
pub use host::{HostServices, IDENTITY_POSE, MinimalHost, Pose};
pub use motion::{MotionBudget, MotionOutcome, MotionPlanner, MotionRequest, NoPathReason};
pub use planner::{Plan, PlanBudget, PlanRequest, PlanResponse, PlanStatus, PlanStep, Planner};
pub use refiner::{
    Candidate, CandidateStream, GraspChange, GroundAtom, GroundedAction, HeldObject, ObjectPose,
    ObjectState, RefineRequest, Refiner, RobotPart, RobotState, RobotTarget, WorldState,
};
