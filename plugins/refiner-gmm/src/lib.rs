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
use lamp_plugin_api::config::{self, PluginConfig};
use lamp_plugin_api::{CandidateStream, HostServices, PluginError, RefineRequest, Refiner};
use lamp_plugin_sdk::PluginFactory;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::stream::{Effects, GmmStream};
use crate::world_view::WorldView;

/// How hard the refiner tries per action.
#[derive(Clone, Copy, Debug, PartialEq)]
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
            ways: None,
            sampled: 0,
        }))
    }
}

/// The configuration key of the sampler artifact, the one option without a default.
pub const ARTIFACT_OPTION: &str = "artifact";
/// The configuration key of [`RefinerOptions::samples`].
pub const SAMPLES_OPTION: &str = "samples";
/// The configuration key of [`RefinerOptions::draws`].
pub const DRAWS_OPTION: &str = "draws";
/// The configuration key of [`RefinerOptions::displacement`].
pub const DISPLACEMENT_OPTION: &str = "displacement";

impl PluginFactory for GmmRefiner {
    /// The configuration is `{"artifact": <sampler artifact>, "samples": n, "draws": n,
    /// "displacement": metres}`, all but the artifact optional.
    fn create(config: &[u8]) -> Result<Self, PluginError> {
        let mut config = PluginConfig::parse(config)?;
        let artifact: SamplerArtifact =
            config.document(ARTIFACT_OPTION)?.ok_or_else(|| config::missing(ARTIFACT_OPTION))?;
        let mut options = RefinerOptions::default();
        if let Some(samples) = config.count(SAMPLES_OPTION)? {
            options.samples = samples;
        }
        if let Some(draws) = config.count(DRAWS_OPTION)? {
            options.draws = draws;
        }
        if let Some(displacement) = config.number(DISPLACEMENT_OPTION)? {
            options.displacement = displacement;
        }
        config.finish()?;
        GmmRefiner::new(artifact, options)
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

    #[test]
    fn the_configuration_is_one_object_with_the_artifact_required() {
        let artifact = r#"{"version": VERSION, "seed": 3, "pairs": []}"#
            .replace("VERSION", &lamp_abstraction::SAMPLER_ARTIFACT_VERSION.to_string());
        let created = |text: &str| GmmRefiner::create(text.as_bytes());
        let refiner =
            created(&format!(r#"{{"artifact": {artifact}, "samples": 2, "displacement": 0.5}}"#))
                .unwrap();
        assert_eq!(
            refiner.options,
            RefinerOptions { samples: 2, displacement: 0.5, ..RefinerOptions::default() }
        );
        assert_eq!(refiner.artifact.seed, 3);
        let message = |text: &str| match created(text) {
            Err(PluginError::InvalidRequest { message }) => message,
            other => panic!("{text}: expected a refusal, got {other:?}"),
        };
        assert_eq!(message("{}"), "option `artifact` is required");
        assert!(
            message(&format!(r#"{{"artifact": {artifact}, "sample": 2}}"#))
                .starts_with("unknown option `sample`")
        );
        assert!(
            message(&format!(r#"{{"artifact": {artifact}, "draws": "many"}}"#))
                .contains("must be a whole number")
        );
        assert!(message(r#"{"artifact": {"version": 1}}"#).starts_with("option `artifact`"));
        assert!(
            message(&format!(r#"{{"artifact": {artifact}, "samples": 0}}"#))
                .contains("must be at least 1")
        );
    }
}
