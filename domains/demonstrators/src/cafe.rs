//! The Café demonstrator (not written yet): a Fetch carries a can between surfaces.

use lamp_world::SpecWorld;
use rand_chacha::ChaCha8Rng;

use crate::Recording;
use crate::error::DemoError;

/// What the Café demonstrator needs from the spec.
pub(crate) struct Cafe<'a> {
    _world: &'a SpecWorld,
}

impl<'a> Cafe<'a> {
    pub(crate) fn new(_world: &'a SpecWorld) -> Result<Cafe<'a>, DemoError> {
        Err(DemoError::Unsupported {
            demonstrator: "cafe".to_string(),
            reason: "the Café demonstrator is not implemented yet".to_string(),
        })
    }

    pub(crate) fn attempt(&self, _seed: u64, _rng: &mut ChaCha8Rng) -> Result<Recording, String> {
        Err("not implemented".to_string())
    }
}
