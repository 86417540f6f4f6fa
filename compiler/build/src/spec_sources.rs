//! What a build was made from in the spec, as digests the manifest records, so that a solve can
//! refuse a build made from another version of the spec instead of answering a goal the spec no
//! longer has.
//!
//! Two kinds of source:
//! - the model's: the seed, the robots, the object types, the demonstration sources and the
//!   learning settings, everything the domain and the samplers were learned from, and the robot
//!   models and object shapes as loaded from the files the spec names (URDF, meshes), so that an
//!   edited URDF or mesh makes the build stale too;
//! - each problem's: the problem itself (scene, goal, plugin settings), the relation aliases and
//!   the structures, everything its PDDL was written from besides the model.
//!
//! Each digest is FNV-1a over the checked spec's debug rendering of those parts: plain data with no
//! hash maps, so the same spec always gives the same text, while comments, layout and the order of
//! other problems do not count. The loaded models are taken from the world, whose loader read the
//! files: their kinematics and collision shapes, which is what the model depends on.

use std::collections::BTreeMap;

use lamp_spec::Spec;
use lamp_world::SpecWorld;
use serde::{Deserialize, Serialize};

use crate::digest::file_digest;

/// The digests of a spec's sources, as the manifest records them.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SpecSources {
    /// What the domain and samplers were learned from.
    pub model: String,
    /// Per problem, by name, what its PDDL was written from besides the model.
    pub problems: BTreeMap<String, String>,
}

impl SpecSources {
    /// The sources of `spec`, with its robots and object shapes as `world` loaded them.
    pub fn of(spec: &Spec, world: &SpecWorld) -> Self {
        let model = (
            (spec.seed, &spec.robots, &spec.object_types, &spec.demonstrations, &spec.learning),
            (&world.robots, &world.type_parts),
        );
        let shared = (&spec.relation_aliases, &spec.structures);
        let problems = spec
            .problems
            .iter()
            .map(|problem| (problem.name.clone(), digest_of(&(problem, shared))))
            .collect();
        SpecSources { model: digest_of(&model), problems }
    }
}

fn digest_of(value: &impl std::fmt::Debug) -> String {
    file_digest(format!("{value:?}").as_bytes()).to_string()
}
