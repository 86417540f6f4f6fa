//! What a build was made from in the spec, as digests the manifest records, so that a solve can
//! refuse a build made from another version of the spec instead of answering a goal the spec no
//! longer has.
//!
//! Two kinds of source:
//! - the model's: the seed, the robots, the object types, the demonstration sources and the
//!   learning settings, everything the domain and the samplers were learned from, and the robot
//!   models and object shapes as loaded from the files the spec names (URDF, meshes), so that an
//!   edited URDF or mesh makes the build stale too;
//! - each problem's: its initial scene, its goal, the relation aliases and the structures,
//!   everything its PDDL was written from besides the model, each part a digest of its own so
//!   that a refusal can say which of them changed.
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
    pub problems: BTreeMap<String, ProblemSources>,
}

/// The digests of what one problem's PDDL was written from besides the model: its initial state
/// from the scene, its goal from the goal with the aliases and structures the goal may name.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ProblemSources {
    pub scene: String,
    pub goal: String,
    pub aliases: String,
    pub structures: String,
}

impl ProblemSources {
    /// What differs in `current` from `self`, as the parts a user edits, in the order written.
    pub fn changed_parts(&self, current: &ProblemSources) -> Vec<&'static str> {
        [
            (self.scene != current.scene, "its scene"),
            (self.goal != current.goal, "its goal"),
            (self.aliases != current.aliases, "the relation aliases"),
            (self.structures != current.structures, "the structures"),
        ]
        .into_iter()
        .filter_map(|(changed, part)| changed.then_some(part))
        .collect()
    }
}

impl SpecSources {
    /// The sources of `spec`, with its robots and object shapes as `world` loaded them.
    pub fn of(spec: &Spec, world: &SpecWorld) -> Self {
        let model = (
            (spec.seed, &spec.robots, &spec.object_types, &spec.demonstrations, &spec.learning),
            (&world.robots, &world.type_parts),
        );
        let aliases = digest_of(&spec.relation_aliases);
        let structures = digest_of(&spec.structures);
        let problems = spec
            .problems
            .iter()
            .map(|problem| {
                let sources = ProblemSources {
                    scene: digest_of(&problem.scene),
                    goal: digest_of(&problem.goal),
                    aliases: aliases.clone(),
                    structures: structures.clone(),
                };
                (problem.name.clone(), sources)
            })
            .collect();
        SpecSources { model: digest_of(&model), problems }
    }
}

fn digest_of(value: &impl std::fmt::Debug) -> String {
    file_digest(format!("{value:?}").as_bytes()).to_string()
}
