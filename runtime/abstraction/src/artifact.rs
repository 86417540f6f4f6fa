//! The sampler artifact: the regions' models with just enough vocabulary to abstract states and
//! sample regions at run time, as a versioned serde value (the caller chooses the encoding and the
//! file). The learner writes it (`lamp_learn::Model::sampler_artifact`).

use std::collections::BTreeSet;

use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::abstraction::{self, GroundAtom};
use crate::error::AbstractionError;
use crate::region_model::RegionModel;
use crate::relations::PairVocabulary;
use crate::snapshot::{Participant, Pose, Snapshot};
use crate::type_pair::TypePair;

/// The artifact format version; bumped on any change to the serialised shape or its meaning.
pub const SAMPLER_ARTIFACT_VERSION: u32 = 6;

/// Everything the run time needs from learning besides the PDDL text.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SamplerArtifact {
    /// Always [`SAMPLER_ARTIFACT_VERSION`] when written by the learner.
    pub version: u32,
    /// The seed learning used.
    pub seed: u64,
    /// Pairs with regions, in relation order.
    pub pairs: Vec<ArtifactPair>,
}

/// One type pair of the artifact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArtifactPair {
    /// The type whose frame relative poses are in.
    pub primary: String,
    /// The other type.
    pub secondary: String,
    /// Its regions; region k is at index k − 1.
    pub regions: Vec<ArtifactRegion>,
}

/// One region of the artifact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArtifactRegion {
    /// Its relation name `<primary>_<secondary>_<k>`.
    pub relation: String,
    /// Its held flag.
    pub g: u8,
    /// Whether it has `clear_<primary>_<secondary>_<k>`.
    pub clear: bool,
    /// Whether it has `nowhere_<primary>_<secondary>_<k>`.
    pub nowhere: bool,
    /// Its membership test and generator.
    pub model: RegionModel,
}

impl SamplerArtifact {
    /// Checks a deserialised artifact: its version and every mixture.
    pub fn validate(&self) -> Result<(), AbstractionError> {
        if self.version != SAMPLER_ARTIFACT_VERSION {
            return Err(AbstractionError::ArtifactVersion {
                found: self.version,
                supported: SAMPLER_ARTIFACT_VERSION,
            });
        }
        for region in self.pairs.iter().flat_map(|pair| &pair.regions) {
            region.model.validate().map_err(|reason| AbstractionError::Mixture {
                relation: region.relation.clone(),
                reason,
            })?;
        }
        Ok(())
    }

    /// The region behind a relation name.
    pub fn region(&self, relation: &str) -> Option<&ArtifactRegion> {
        self.pairs.iter().flat_map(|pair| &pair.regions).find(|region| region.relation == relation)
    }

    /// Draws a relative pose (secondary in primary's frame) from a region.
    pub fn sample_region(&self, relation: &str, rng: &mut ChaCha8Rng) -> Option<Pose> {
        self.region(relation).map(|region| region.model.sample(rng))
    }

    /// The abstract state of a snapshot under this artifact's vocabulary (the same as the model's).
    pub fn abstract_state(
        &self,
        participants: &[Participant],
        snapshot: &Snapshot,
    ) -> Result<BTreeSet<GroundAtom>, AbstractionError> {
        let (vocabulary, classifiers) = self.classifiers();
        abstraction::abstract_atoms(&vocabulary, &classifiers, participants, snapshot)
    }

    /// Whether every atom of `adds` is in the snapshot's abstract state and none of `deletes`
    /// is: what [`Self::abstract_state`] answers, without naming every atom of the scene (a
    /// refiner asks it of every candidate, and most of the state is about other objects).
    pub fn effects_hold(
        &self,
        participants: &[Participant],
        snapshot: &Snapshot,
        adds: &BTreeSet<GroundAtom>,
        deletes: &BTreeSet<GroundAtom>,
    ) -> Result<bool, AbstractionError> {
        let (vocabulary, classifiers) = self.classifiers();
        abstraction::effects_hold(&vocabulary, &classifiers, participants, snapshot, adds, deletes)
    }

    /// The vocabulary and the region classifiers of every pair, in pair order.
    fn classifiers(&self) -> (Vec<PairVocabulary>, Vec<Vec<&RegionModel>>) {
        let vocabulary: Vec<PairVocabulary> = self
            .pairs
            .iter()
            .map(|pair| PairVocabulary {
                pair: TypePair::new(pair.primary.clone(), pair.secondary.clone()),
                region_flags: pair.regions.iter().map(|region| region.g).collect(),
                clear: pair.regions.iter().map(|region| region.clear).collect(),
                nowhere: pair.regions.iter().map(|region| region.nowhere).collect(),
            })
            .collect();
        let classifiers: Vec<Vec<&RegionModel>> = self
            .pairs
            .iter()
            .map(|pair| pair.regions.iter().map(|region| &region.model).collect())
            .collect();
        (vocabulary, classifiers)
    }
}
