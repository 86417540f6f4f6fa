//! The `gmm` refiner: turns a grounded action of a learned domain into robot targets by sampling
//! the Gaussian mixture of the region its effect names (paper §4, App. F).
//!
//! For each action it works out the driving effect and the link that moves
//! ([`realise`](crate::realise)), then streams candidates: first "stay where you are" (a grab or a
//! release changes the relations without moving), then region samples placed in the world,
//! solved by the host's collision-free IK. A candidate is kept only if the action's effects hold
//! in the learned abstraction of the state it leads to (its adds true, its deletes false); what
//! else changed is for the solver to judge, which knows the rest of the plan. Mixture draws that
//! fall outside the region's threshold (about one in ten) are rejected by that same test.
//!
//! Linked statically, construct [`GmmRefiner::new`]; built as a shared library, the configuration
//! bytes are a JSON object `{"artifact": <sampler artifact>, "samples": n, "draws": n,
//! "displacement": metres}` (all but the artifact optional).

mod realise;
mod stream;
mod world_view;

use std::sync::Arc;

use lamp_abstraction::SamplerArtifact;
use lamp_plugin_api::{CandidateStream, HostServices, PluginError, RefineRequest, Refiner};
use lamp_plugin_sdk::PluginFactory;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;

use crate::stream::{Effects, GmmStream};
use crate::world_view::WorldView;

/// How hard the refiner tries per action.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RefinerOptions {
    /// Most candidates one stream yields (how many alternatives backtracking may try).
    pub samples: usize,
    /// Most region draws one stream makes in total.
    pub draws: usize,
    /// Longest random move of a link leaving every region of a pair, in metres.
    pub displacement: f64,
}

impl Default for RefinerOptions {
    fn default() -> Self {
        RefinerOptions { samples: 4, draws: 2000, displacement: 0.25 }
    }
}

/// The `gmm` refiner over one learned model.
#[derive(Clone, Debug)]
pub struct GmmRefiner {
    artifact: Arc<SamplerArtifact>,
    options: RefinerOptions,
}

impl GmmRefiner {
    /// A refiner sampling `artifact`'s regions.
    ///
    /// # Errors
    /// [`PluginError::InvalidRequest`] when the artifact does not validate, or the options ask
    /// for no candidate, no draw, or a displacement that is not a positive length.
    pub fn new(artifact: SamplerArtifact, options: RefinerOptions) -> Result<Self, PluginError> {
        let RefinerOptions { samples, draws, displacement } = options;
        if samples == 0 || draws == 0 || !(displacement.is_finite() && displacement > 0.0) {
            return Err(PluginError::invalid_request(format!(
                "the gmm refiner's options: samples ({samples}) and draws ({draws}) must be at least 1, displacement ({displacement} m) a positive length"
            )));
        }
        artifact
            .validate()
            .map_err(|error| PluginError::invalid_request(format!("sampler artifact: {error}")))?;
        Ok(GmmRefiner { artifact: Arc::new(artifact), options })
    }
}

impl Refiner for GmmRefiner {
    fn refine(
        &mut self,
        request: &RefineRequest,
        _host: &dyn HostServices,
    ) -> Result<Box<dyn CandidateStream>, PluginError> {
        let view = WorldView::new(&request.world)?;
        let action = &request.action;
        let realisation = realise::realisation(
            &self.artifact,
            &view,
            &action.add_effects,
            &action.delete_effects,
        );
        Ok(Box::new(GmmStream {
            artifact: Arc::clone(&self.artifact),
            options: self.options,
            effects: Effects::of(action),
            view,
            realisation,
            rng: ChaCha8Rng::seed_from_u64(request.seed),
            stayed: false,
            yielded: 0,
            draws: 0,
            pool: std::collections::VecDeque::new(),
            centre: None,
        }))
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Configuration {
    artifact: SamplerArtifact,
    #[serde(flatten)]
    options: RefinerOptions,
}

impl PluginFactory for GmmRefiner {
    fn create(config: &[u8]) -> Result<Self, PluginError> {
        let configuration: Configuration = serde_json::from_slice(config).map_err(|error| {
            PluginError::invalid_request(format!("the gmm refiner's configuration: {error}"))
        })?;
        GmmRefiner::new(configuration.artifact, configuration.options)
    }
}

#[cfg(feature = "shared-library")]
lamp_plugin_sdk::export_plugin! {
    refiner: GmmRefiner,
    name: "lamp-gmm-refiner",
    version: env!("CARGO_PKG_VERSION"),
    description: "Samples learned regions' Gaussian mixtures into IK targets (config: JSON with the sampler artifact).",
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_that_could_never_yield_a_candidate_are_refused() {
        let artifact = SamplerArtifact {
            version: lamp_abstraction::SAMPLER_ARTIFACT_VERSION,
            seed: 0,
            pairs: Vec::new(),
        };
        let defaults = RefinerOptions::default();
        for options in [
            RefinerOptions { samples: 0, ..defaults },
            RefinerOptions { draws: 0, ..defaults },
            RefinerOptions { displacement: -1.0, ..defaults },
            RefinerOptions { displacement: f64::INFINITY, ..defaults },
        ] {
            let refused = GmmRefiner::new(artifact.clone(), options);
            assert!(
                matches!(refused, Err(PluginError::InvalidRequest { .. })),
                "{options:?} must be refused"
            );
        }
        assert!(GmmRefiner::new(artifact, defaults).is_ok());
    }
}
