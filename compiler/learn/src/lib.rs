//! lamp-learn: demonstrations in memory become a learned planning model.
//!
//! The pipeline, one module per stage: [`pairs`] (which type pairs, relative poses, held flag) →
//! [`selection`] (the settings a spec leaves out, chosen from the demonstrations' keyframes) → [`discretise`] (voxels and rotation cells) → [`occupancy`] (criticality) → [`regions`] (connected components) →
//! [`capacity`] (which regions get clear and nowhere relations) → [`region_model`] (a membership test and generator per
//! region) → [`relations`] (the vocabulary) → [`abstraction`] (states to facts)
//! → [`actions`] (induced operators) → [`emit`] (PDDL) and [`report`] (Markdown).
//! [`learn`] runs it all and returns a [`Model`]; [`abstract_state`] abstracts new snapshots with a model.
//! The method and every sort key are documented in `docs/learning.md`. What the run time reads of a
//! model (participants, vocabulary, region models, abstraction, the sampler artifact) lives in
//! lamp-abstraction, and its users name it there: this crate does not re-export it.

pub mod abstraction;
pub mod actions;
pub mod artifact;
pub mod capacity;
pub mod config;
pub mod demo;
pub mod discretise;
pub mod emit;
pub mod error;
mod existential;
use lamp_abstraction::features;
mod learner;
mod lifted;
pub mod model;
pub mod occupancy;
pub mod pairs;
mod placements;
pub mod region_model;
pub mod regions;
mod rigid;
use lamp_abstraction::relations;
pub mod report;
pub mod resting;
pub mod selection;
pub mod symmetry_choice;
pub mod synthetic;

pub use abstraction::CellClassifier;
pub use actions::{Action, LiftedAtom, Parameter, TransitionRef};
pub use capacity::{NoShapes, RegionSides, ShapeOracle, Side, SideReason};
pub use config::{LearnConfig, PairSettings, PinnedSettings, Switch};
pub use demo::Demonstration;
pub use emit::{domain, domain_text, ground_atoms};
pub use error::LearnError;
pub use learner::{PairRegions, RegionSummary};
pub use model::{LearnedPair, Model, Region, abstract_state, learn};
pub use report::vocabulary_report;
pub use resting::UndescribedRest;
#[cfg(test)]
mod chosen_settings;
#[cfg(test)]
mod end_to_end;
