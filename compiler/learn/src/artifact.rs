//! The sampler artifact of a learned model (the artifact itself is lamp-abstraction's).

use crate::model::Model;
use lamp_abstraction::artifact::{
    ArtifactPair, ArtifactRegion, SAMPLER_ARTIFACT_VERSION, SamplerArtifact,
};

impl Model {
    /// The sampler artifact of this model: what the run time reads of it.
    pub fn sampler_artifact(&self) -> SamplerArtifact {
        SamplerArtifact {
            version: SAMPLER_ARTIFACT_VERSION,
            seed: self.seed,
            pairs: self
                .pairs
                .iter()
                .map(|learned| ArtifactPair {
                    primary: learned.pair.pair.primary.clone(),
                    secondary: learned.pair.pair.secondary.clone(),
                    regions: learned
                        .regions
                        .iter()
                        .map(|region| ArtifactRegion {
                            relation: region.relation.clone(),
                            g: region.summary.g,
                            clear: region.summary.sides.clear.on,
                            nowhere: region.summary.sides.nowhere.on,
                            model: region.model.clone(),
                        })
                        .collect(),
                })
                .collect(),
        }
    }
}
