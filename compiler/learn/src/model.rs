//! The learned model: regions with their models, the vocabulary, actions and provenance, and the entry points
//! that learn it and use it (abstraction of new snapshots, sampling a region).

use std::collections::BTreeSet;

use rand_chacha::ChaCha8Rng;

use crate::abstraction::{self, GroundAtom};
use crate::actions::Action;
use crate::capacity::ShapeOracle;
use crate::config::{LearnConfig, TypePair};
use crate::demo::{Demonstration, Participant, Pose, Role, Snapshot};
use crate::error::LearnError;
use crate::learner::{self, PairRegions, RegionSummary};
use crate::region_model::{self, RegionModel};
use crate::relations::{self, PairVocabulary, PredicateSignature};
use crate::resting::UndescribedRest;

/// One learned region: its relation, where it came from, and its model.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// The relation name `<t1>_<t2>_<k>`.
    pub relation: String,
    /// k ≥ 1.
    pub index: usize,
    /// Cells, support and a representative pose.
    pub summary: RegionSummary,
    /// The generative model and membership test.
    pub model: RegionModel,
}

/// A type pair that has regions.
#[derive(Debug, Clone, PartialEq)]
pub struct LearnedPair {
    /// The pair, its settings, grid and demonstration count.
    pub pair: PairRegions,
    /// Its regions in relation order.
    pub regions: Vec<Region>,
}

/// Everything learned from a set of demonstrations.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// Every participant type with its role, sorted by name.
    pub types: Vec<(String, Role)>,
    /// Pairs with at least one region, sorted by (primary, secondary).
    pub pairs: Vec<LearnedPair>,
    /// Pairs that occur in some demonstration but have no region (and so no relations), sorted.
    pub pairs_without_regions: Vec<TypePair>,
    /// Induced actions, `a1` … `an`.
    pub actions: Vec<Action>,
    /// Demonstrations learned from only up to a grasp: the object let go of afterwards rested
    /// against another with no relation between them ([`crate::resting`]).
    pub undescribed_rests: Vec<UndescribedRest>,
    /// How many demonstrations it was learned from.
    pub demonstrations: usize,
    /// The seed it was learned with.
    pub seed: u64,
}

/// Learns a model from demonstrations; `shapes` answers the capacity tests of the `auto` clear and nowhere
/// settings ([`crate::capacity::NoShapes`] turns every `auto` side on).
pub fn learn(
    demonstrations: &[Demonstration],
    config: &LearnConfig,
    shapes: &dyn ShapeOracle,
) -> Result<Model, LearnError> {
    let induced = learner::induce(
        demonstrations,
        config,
        shapes,
        |pair: &PairRegions, index: usize, rng: &mut ChaCha8Rng| {
            let relation = format!("{}_{}", pair.pair.stem(), index + 1);
            region_model::fit(pair, index, config.samples_per_region, rng)
                .map_err(|reason| LearnError::Mixture { relation, reason })
        },
    )?;
    let pairs = induced
        .pairs
        .into_iter()
        .zip(induced.classifiers)
        .map(|(pair, models)| {
            let regions = pair
                .regions
                .iter()
                .cloned()
                .zip(models)
                .enumerate()
                .map(|(position, (summary, model))| Region {
                    relation: format!("{}_{}", pair.pair.stem(), position + 1),
                    index: position + 1,
                    summary,
                    model,
                })
                .collect();
            LearnedPair { pair, regions }
        })
        .collect();
    Ok(Model {
        types: induced.roles.into_iter().collect(),
        pairs,
        pairs_without_regions: induced.empty_pairs,
        actions: induced.actions,
        undescribed_rests: induced.undescribed_rests,
        demonstrations: demonstrations.len(),
        seed: config.seed,
    })
}

impl Model {
    /// The vocabulary, one entry per pair with regions.
    pub fn vocabulary(&self) -> Vec<PairVocabulary> {
        self.pairs.iter().map(|learned| learned.pair.vocabulary()).collect()
    }

    /// Every predicate, in declaration order (per pair: `_0` … `_K`, then its clear relations, then its nowhere
    /// relations).
    pub fn predicates(&self) -> Vec<PredicateSignature> {
        let vocabulary = self.vocabulary();
        relations::symbols(&vocabulary)
            .into_iter()
            .map(|symbol| relations::signature(&vocabulary, symbol))
            .collect()
    }

    /// The region behind a relation name `<t1>_<t2>_<k>` (k ≥ 1).
    pub fn region(&self, relation: &str) -> Option<&Region> {
        self.pairs.iter().flat_map(|pair| &pair.regions).find(|region| region.relation == relation)
    }

    /// Draws a relative pose (secondary in primary's frame) from a region's model.
    pub fn sample_region(&self, relation: &str, rng: &mut ChaCha8Rng) -> Option<Pose> {
        self.region(relation).map(|region| region.model.sample(rng))
    }
}

/// The abstract state of a low-level snapshot: every true atom of the model's vocabulary.
pub fn abstract_state(
    model: &Model,
    participants: &[Participant],
    snapshot: &Snapshot,
) -> Result<BTreeSet<GroundAtom>, LearnError> {
    let vocabulary = model.vocabulary();
    let classifiers: Vec<Vec<&RegionModel>> = model
        .pairs
        .iter()
        .map(|pair| pair.regions.iter().map(|region| &region.model).collect())
        .collect();
    Ok(abstraction::abstract_atoms(&vocabulary, &classifiers, participants, snapshot)?)
}
