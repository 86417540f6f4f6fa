//! lamp-abstraction: the learned abstraction as the run time reads it.
//!
//! What the learner leaves behind and a refiner or the solver needs: participants and their
//! [`snapshot`]s, the invented vocabulary ([`relations`] over [`TypePair`]s), the [`features`] of a
//! relative pose, each region's membership test and generator ([`region_model`]), the
//! [`abstraction`] of a snapshot into ground atoms, and the versioned [`artifact`] that carries
//! them. Learning itself (lamp-learn) builds on this crate; nothing here learns.

pub mod abstraction;
pub mod artifact;
pub mod error;
pub mod features;
pub mod free_turn;
pub mod instances;
pub mod region_model;
pub mod relations;
pub mod snapshot;
pub mod symmetry;
mod type_pair;

pub use abstraction::{GroundAtom, RegionClassifier};
pub use artifact::{ArtifactPair, ArtifactRegion, SAMPLER_ARTIFACT_VERSION, SamplerArtifact};
pub use error::AbstractionError;
pub use free_turn::FreeTurn;
pub use region_model::RegionModel;
pub use snapshot::{Participant, Pose, Role, Snapshot};
pub use symmetry::PairSymmetry;
pub use type_pair::TypePair;
