//! The sampler-artifact reader: `lamp_build::SamplersFile::from_json` on arbitrary text, and
//! through it lamp-learn's artifact validation and lamp-gmm's validation of serialised mixtures.
//!
//! "Validated" must mean usable: a file that reads is written and read back equal, every region
//! (up to a bound) is sampled and tested for membership as the refiner does, and a small scene of
//! the artifact's own types is abstracted as the solver does.

use std::collections::BTreeSet;

use lamp_abstraction::{Participant, Pose, RegionClassifier, Role, SamplerArtifact, Snapshot};
use lamp_build::SamplersFile;
use nalgebra::{Isometry3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Regions sampled per input: enough for every bundled domain's artifact, few enough that an
/// input listing thousands of regions does not slow the fuzzer to a crawl.
const MAX_REGIONS: usize = 64;

/// Draws per sampled region.
const SAMPLES_PER_REGION: usize = 4;

/// Types placed in the abstracted scene (each twice), for the same reason as [`MAX_REGIONS`].
const MAX_TYPES: usize = 6;

/// The seed of the draws; any fixed value does.
const SEED: u64 = 14;

/// Reads the sampler file in `data` and uses what it accepts.
///
/// # Panics
/// When the reader panics, or an accepted file does not round-trip, draws a non-finite pose,
/// gives a NaN membership margin, or cannot abstract a scene of its own types.
pub fn samplers(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(file) = SamplersFile::from_json(&text) else { return };
    let json = file
        .to_json()
        .unwrap_or_else(|error| panic!("an accepted sampler file cannot be written: {error}"));
    let back = SamplersFile::from_json(&json)
        .unwrap_or_else(|error| panic!("a written sampler file does not read: {error}\n{json}"));
    assert_eq!(back, file, "a sampler file changes when written and read back");
    sample_every_region(&file.artifact);
    abstract_a_scene(&file.artifact);
}

fn sample_every_region(artifact: &SamplerArtifact) {
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    for region in artifact.pairs.iter().flat_map(|pair| &pair.regions).take(MAX_REGIONS) {
        for _ in 0..SAMPLES_PER_REGION {
            let pose = artifact
                .sample_region(&region.relation, &mut rng)
                .unwrap_or_else(|| panic!("region `{}` is not found by name", region.relation));
            assert!(is_finite(&pose), "region `{}` draws {pose:?}", region.relation);
            let margin = region.model.margin(&pose);
            assert!(!margin.is_nan(), "region `{}` has a NaN margin at {pose:?}", region.relation);
        }
        let margin = region.model.margin(&Pose::identity());
        assert!(!margin.is_nan(), "region `{}` has a NaN margin at the identity", region.relation);
    }
}

/// Two bodies of each of the artifact's types (the first a gripper holding the second), at
/// fixed poses a few centimetres apart.
fn abstract_a_scene(artifact: &SamplerArtifact) {
    let types: BTreeSet<&str> = artifact
        .pairs
        .iter()
        .flat_map(|pair| [pair.primary.as_str(), pair.secondary.as_str()])
        .collect();
    let participants: Vec<Participant> = types
        .into_iter()
        .take(MAX_TYPES)
        .flat_map(|type_name| {
            ["a", "b"].map(|suffix| Participant {
                name: format!("{type_name}_{suffix}"),
                type_name: type_name.to_string(),
                role: Role::Object { movable: true },
            })
        })
        .enumerate()
        .map(|(index, mut participant)| {
            if index == 0 {
                participant.role = Role::RobotPart { gripper: true };
            }
            participant
        })
        .collect();
    let poses: Vec<Pose> = (0..participants.len())
        .map(|index| {
            let step = index as f64;
            Isometry3::new(
                Vector3::new(0.04 * step, -0.03 * step, 0.02 * step),
                Vector3::new(0.0, 0.0, 0.7 * step),
            )
        })
        .collect();
    let held = if participants.len() > 1 { vec![(0, 1)] } else { Vec::new() };
    let snapshot = Snapshot { poses, held };
    if let Err(error) = artifact.abstract_state(&participants, &snapshot) {
        panic!("a scene of the artifact's own types does not abstract: {error}");
    }
}

fn is_finite(pose: &Pose) -> bool {
    pose.translation.vector.iter().all(|value| value.is_finite())
        && pose.rotation.coords.iter().all(|value| value.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;
    use lamp_abstraction::RegionModel;
    use lamp_abstraction::SAMPLER_ARTIFACT_VERSION;
    use lamp_abstraction::{ArtifactPair, ArtifactRegion};
    use lamp_build::Provenance;

    /// A region model: one standard normal component over the 9 features, at the identity
    /// rotation and a can's height, inside a 20 cm box.
    fn model() -> RegionModel {
        let identity: Vec<String> =
            (0..81).map(|index| if index % 10 == 0 { "1.0" } else { "0.0" }.to_string()).collect();
        let text = format!(
            r#"{{"g": 0, "threshold": -20.0, "extent": [[-0.1, 0.1], [-0.1, 0.1], [0.0, 0.2]],
              "mixture": {{"dimension": 9, "weights": [1.0],
                "means": [[0.0, 0.0, 0.1, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]],
                "covariances": [[{}]]}}}}"#,
            identity.join(", ")
        );
        serde_json::from_str(&text).expect("the test model deserialises")
    }

    #[test]
    fn a_valid_file_is_read_sampled_and_abstracted() {
        let region = ArtifactRegion {
            relation: "surface_can_1".into(),
            g: 0,
            clear: true,
            nowhere: true,
            model: model(),
        };
        let pair = ArtifactPair {
            primary: "surface".into(),
            secondary: "can".into(),
            regions: vec![region],
        };
        let artifact =
            SamplerArtifact { version: SAMPLER_ARTIFACT_VERSION, seed: 3, pairs: vec![pair] };
        let digest = lamp_build::demonstration_digest(&[]);
        let file = SamplersFile::new(Provenance::new("t.lamp", "t", 3, 0, digest), artifact);
        let json = file.to_json().expect("the test file writes");
        assert_eq!(SamplersFile::from_json(&json).expect("the test file reads"), file);
        samplers(json.as_bytes());
    }

    #[test]
    fn malformed_files_are_refused_quietly() {
        samplers(b"{}");
        samplers(b"{\"format\": \"lamp-samplers\", \"version\": 1}");
        samplers(b"[1, 2");
        assert!(SamplersFile::from_json("{}").is_err());
    }
}
