//! Versioned JSON documents for the structured values that cross a library boundary once per
//! call: the grounded action, the world state, a candidate and a plan response.
//!
//! Each document is an envelope `{"format": "<name>", "format_version": N, "body": {...}}`.
//! The body's shape is that of the value type in this crate, which is the plugin contract and not
//! an internal type of the compiler or runtime. A reader refuses another format name and a
//! `format_version` other than [`WIRE_FORMAT_VERSION`]; new optional fields may be added to a body
//! without a version change, because readers ignore fields they do not know.

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::error::PluginError;
use crate::planner::PlanResponse;
use crate::refiner::{Candidate, GroundedAction, WorldState};

/// The version of every document's body layout.
pub const WIRE_FORMAT_VERSION: u32 = 1;

/// A value that crosses as a versioned document.
pub trait WireDocument: Serialize + DeserializeOwned {
    /// The document's format name.
    const FORMAT: &'static str;
}

impl WireDocument for GroundedAction {
    const FORMAT: &'static str = "lamp.grounded_action";
}

impl WireDocument for WorldState {
    const FORMAT: &'static str = "lamp.world_state";
}

impl WireDocument for Candidate {
    const FORMAT: &'static str = "lamp.candidate";
}

impl WireDocument for PlanResponse {
    const FORMAT: &'static str = "lamp.plan_response";
}

/// Why a document could not be written or read.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum WireError {
    /// The bytes are not a JSON document of the expected shape (non-finite numbers included:
    /// JSON has no NaN or infinity).
    #[error("malformed {format} document: {message}")]
    Malformed {
        /// The expected format.
        format: &'static str,
        /// The JSON error.
        message: String,
    },
    /// The document is of another format.
    #[error("expected a {expected} document, found {found}")]
    WrongFormat {
        /// The expected format.
        expected: &'static str,
        /// The format found.
        found: String,
    },
    /// The document has a body version this reader does not know.
    #[error("{format} version {found} is not supported (this side reads version {supported})")]
    UnsupportedVersion {
        /// The format.
        format: &'static str,
        /// The version found.
        found: u32,
        /// The version this side reads.
        supported: u32,
    },
}

impl From<WireError> for PluginError {
    fn from(error: WireError) -> Self {
        PluginError::invalid_request(error.to_string())
    }
}

#[derive(Serialize)]
struct EnvelopeOut<'a, T> {
    format: &'static str,
    format_version: u32,
    body: &'a T,
}

#[derive(Deserialize)]
struct EnvelopeHeader {
    format: String,
    format_version: u32,
}

#[derive(Deserialize)]
struct EnvelopeIn<T> {
    body: T,
}

/// Writes `value` as a versioned document.
///
/// # Errors
/// [`WireError::Malformed`] when a number is not finite.
pub fn encode<T: WireDocument>(value: &T) -> Result<Vec<u8>, WireError> {
    let envelope =
        EnvelopeOut { format: T::FORMAT, format_version: WIRE_FORMAT_VERSION, body: value };
    let bytes = serde_json::to_vec(&envelope).map_err(|error| malformed::<T>(&error))?;
    // serde_json writes non-finite floats as `null`, which no reader accepts; refuse them here so
    // the writer, not the reader, reports the problem.
    decode::<T>(&bytes)?;
    Ok(bytes)
}

/// Reads a versioned document of type `T`.
///
/// # Errors
/// [`WireError`] when the bytes are malformed, of another format or of another version.
pub fn decode<T: WireDocument>(bytes: &[u8]) -> Result<T, WireError> {
    let header: EnvelopeHeader =
        serde_json::from_slice(bytes).map_err(|error| malformed::<T>(&error))?;
    if header.format != T::FORMAT {
        return Err(WireError::WrongFormat { expected: T::FORMAT, found: header.format });
    }
    if header.format_version != WIRE_FORMAT_VERSION {
        return Err(WireError::UnsupportedVersion {
            format: T::FORMAT,
            found: header.format_version,
            supported: WIRE_FORMAT_VERSION,
        });
    }
    let envelope: EnvelopeIn<T> =
        serde_json::from_slice(bytes).map_err(|error| malformed::<T>(&error))?;
    Ok(envelope.body)
}

fn malformed<T: WireDocument>(error: &serde_json::Error) -> WireError {
    WireError::Malformed { format: T::FORMAT, message: error.to_string() }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_1_SQRT_2;

    use super::*;
    use crate::host::IDENTITY_POSE;
    use crate::planner::{Plan, PlanStatus, PlanStep};
    use crate::refiner::{HeldObject, ObjectState, RobotPart, RobotState};

    fn world() -> WorldState {
        WorldState {
            robots: vec![RobotState {
                name: "fetch".into(),
                configuration: vec![0.5, -1.25, 3.0],
                held: vec![HeldObject {
                    object: "can1".into(),
                    link: "gripper".into(),
                    grasp: IDENTITY_POSE,
                }],
                parts: vec![RobotPart {
                    object: "fetch_gripper".into(),
                    object_type: "gripper".into(),
                    link: "gripper".into(),
                    gripper: true,
                }],
            }],
            objects: vec![ObjectState {
                name: "can1".into(),
                object_type: "can".into(),
                pose: [1.0, 2.0, 0.75, 0.0, 0.0, FRAC_1_SQRT_2, FRAC_1_SQRT_2],
            }],
        }
    }

    #[test]
    fn documents_round_trip_exactly() {
        let world = world();
        assert_eq!(decode::<WorldState>(&encode(&world).unwrap()).unwrap(), world);
        let response = PlanResponse {
            status: PlanStatus::Unsolvable { reason: "goal (on a b) unreachable".into() },
            plans: vec![Plan {
                steps: vec![PlanStep { action: "pick".into(), arguments: vec!["a".into()] }],
            }],
        };
        assert_eq!(decode::<PlanResponse>(&encode(&response).unwrap()).unwrap(), response);
    }

    #[test]
    fn the_envelope_names_format_and_version() {
        let text = String::from_utf8(encode(&WorldState::default()).unwrap()).unwrap();
        assert_eq!(
            text,
            r#"{"format":"lamp.world_state","format_version":1,"body":{"robots":[],"objects":[]}}"#
        );
    }

    #[test]
    fn readers_refuse_other_formats_and_versions() {
        let bytes = encode(&WorldState::default()).unwrap();
        assert_eq!(
            decode::<Candidate>(&bytes),
            Err(WireError::WrongFormat {
                expected: "lamp.candidate",
                found: "lamp.world_state".into()
            })
        );
        let newer = br#"{"format":"lamp.world_state","format_version":2,"body":{}}"#;
        assert_eq!(
            decode::<WorldState>(newer),
            Err(WireError::UnsupportedVersion {
                format: "lamp.world_state",
                found: 2,
                supported: 1
            })
        );
        assert!(matches!(decode::<WorldState>(b"{not json"), Err(WireError::Malformed { .. })));
    }

    #[test]
    fn non_finite_numbers_are_refused_when_writing() {
        let mut world = world();
        world.robots[0].configuration[1] = f64::NAN;
        assert!(matches!(encode(&world), Err(WireError::Malformed { .. })));
    }

    #[test]
    fn floats_round_trip_bit_for_bit() {
        // A deterministic spread of magnitudes and mantissas (a simple LCG, no dependency).
        let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut values = vec![3.788_011_121_742_039_6, -0.0, f64::MIN_POSITIVE, f64::MAX, 1e-300];
        for _ in 0..2000 {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let value = f64::from_bits(state >> 2);
            if value.is_finite() {
                values.push(value);
            }
        }
        let mut world = world();
        world.robots[0].configuration.clone_from(&values);
        let decoded = decode::<WorldState>(&encode(&world).unwrap()).unwrap();
        let bits = |values: &[f64]| values.iter().map(|value| value.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&decoded.robots[0].configuration), bits(&values));
    }

    #[test]
    fn unknown_body_fields_are_ignored() {
        let bytes = br#"{"format":"lamp.candidate","format_version":1,"body":{"targets":[],"object_poses":[],"score":3}}"#;
        assert_eq!(decode::<Candidate>(bytes).unwrap(), Candidate::default());
    }
}
