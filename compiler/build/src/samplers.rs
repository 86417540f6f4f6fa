//! The sampler file (`samplers.json`): lamp-abstraction's `SamplerArtifact` in a small versioned envelope
//! that adds the build's provenance, so that the run time can tell what a sampler was learned from.
//!
//! The envelope is ours and lamp-abstraction's artifact stays as it is: the artifact has its own version,
//! the envelope has `format` and `version` for the file around it.

use lamp_abstraction::SamplerArtifact;
use serde::{Deserialize, Serialize};

use crate::error::BuildError;
use crate::provenance::Provenance;

/// The `format` field of every sampler file.
pub const SAMPLERS_FORMAT: &str = "lamp-samplers";
/// The envelope version; bumped when the envelope's shape or meaning changes.
pub const SAMPLERS_VERSION: u32 = 1;

/// The content of `samplers.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SamplersFile {
    /// Always [`SAMPLERS_FORMAT`].
    pub format: String,
    /// Always [`SAMPLERS_VERSION`] when written by this crate.
    pub version: u32,
    /// What the samplers were learned from.
    pub provenance: Provenance,
    /// The regions' models and the vocabulary needed to abstract states.
    pub artifact: SamplerArtifact,
}

impl SamplersFile {
    /// A sampler file for an artifact.
    pub fn new(provenance: Provenance, artifact: SamplerArtifact) -> Self {
        SamplersFile {
            format: SAMPLERS_FORMAT.to_string(),
            version: SAMPLERS_VERSION,
            provenance,
            artifact,
        }
    }

    /// Pretty JSON with exact float round trips, ending in a newline.
    pub fn to_json(&self) -> Result<String, BuildError> {
        let mut text = serde_json::to_string_pretty(self).map_err(|error| BuildError::Emit {
            what: "samplers.json".into(),
            reason: error.to_string(),
        })?;
        text.push('\n');
        Ok(text)
    }

    /// Reads a sampler file and checks its format, version and artifact.
    pub fn from_json(text: &str) -> Result<Self, BuildError> {
        let fail = |reason: String| BuildError::Samplers { reason };
        let file: SamplersFile =
            serde_json::from_str(text).map_err(|error| fail(error.to_string()))?;
        if file.format != SAMPLERS_FORMAT {
            return Err(fail(format!("its format is `{}`, not `{SAMPLERS_FORMAT}`", file.format)));
        }
        if file.version != SAMPLERS_VERSION {
            return Err(fail(format!(
                "it has envelope version {}, this build reads version {SAMPLERS_VERSION}",
                file.version
            )));
        }
        file.artifact.validate().map_err(|error| fail(error.to_string()))?;
        Ok(file)
    }
}
