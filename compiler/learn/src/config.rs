//! Learning settings: discretisation, criticality threshold and mixture settings per ordered type pair, and the seed.
//!
//! A user pins some settings ([`PinnedSettings`]); the learner chooses every other one from the demonstrations
//! ([`crate::selection`]), or, for the few it does not choose, takes it from the one table of defaults,
//! [`PairSettings::DEFAULT`].

use std::collections::{BTreeMap, BTreeSet};

use crate::error::LearnError;
use lamp_abstraction::FreeTurn;

pub(crate) use lamp_abstraction::TypePair;

/// The settings one type pair is learned with, every one resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct PairSettings {
    /// Position bins along x, y and z of the primary's frame.
    pub position_bins: [usize; 3],
    /// Half-ranges (m): positions outside `[-R, R]` on any axis fall in no cell.
    pub half_range: [f64; 3],
    /// Bins per rotation-vector component over `[-π, π]`.
    pub rotation_bins: usize,
    /// A turn of the secondary the demonstrations leave free, found by the selection (never pinned): rotation
    /// cells are then taken from its reference, with one bin along its axis.
    pub free_turn: Option<FreeTurn>,
    /// Criticality threshold θ ∈ (0, 1]: the share of demonstrations that must visit a cell.
    pub threshold: f64,
    /// The largest number of mixture components BIC may choose.
    pub max_components: usize,
    /// The share of a region's own samples that its likelihood threshold must accept.
    pub cover: f64,
    /// Whether `clear_<primary>_<secondary>_<k>(x)` relations ("no secondary in region k of x") are invented.
    pub clear: Switch,
    /// Whether `nowhere_<primary>_<secondary>_<k>(y)` relations ("y is in region k of no primary") are invented.
    pub nowhere: Switch,
}

/// Whether one side's clear relations are invented: always, never, or where the geometry says they are sound.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Switch {
    /// For every region.
    On,
    /// For no region.
    Off,
    /// For the regions whose capacity test says one object at a time (see [`crate::capacity`]).
    Auto,
}

impl PairSettings {
    /// The one table of defaults. The component cap, the cover and the two switches are used whenever a spec
    /// leaves them out; the grid and the threshold only where the selection has nothing to choose from (see
    /// `docs/learning.md`).
    pub const DEFAULT: PairSettings = PairSettings {
        position_bins: [35, 35, 35],
        half_range: [0.3, 0.3, 0.3],
        rotation_bins: 61,
        free_turn: None,
        threshold: 0.5,
        max_components: 6,
        cover: 0.99,
        clear: Switch::Auto,
        nowhere: Switch::Auto,
    };
}

impl Default for PairSettings {
    fn default() -> Self {
        PairSettings::DEFAULT
    }
}

/// The settings a user pinned for a type pair; `None` is left to the learner.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PinnedSettings {
    /// Position bins along x, y and z.
    pub position_bins: Option<[usize; 3]>,
    /// Half-ranges (m).
    pub half_range: Option<[f64; 3]>,
    /// Bins per rotation-vector component.
    pub rotation_bins: Option<usize>,
    /// Criticality threshold θ.
    pub threshold: Option<f64>,
    /// The largest number of mixture components BIC may choose.
    pub max_components: Option<usize>,
    /// The share of a region's own samples that its likelihood threshold must accept.
    pub cover: Option<f64>,
    /// Whether clear relations are invented.
    pub clear: Option<Switch>,
    /// Whether nowhere relations are invented.
    pub nowhere: Option<Switch>,
}

impl PinnedSettings {
    /// These settings, with every one left out taken from `base`.
    pub fn over(&self, base: &PinnedSettings) -> PinnedSettings {
        PinnedSettings {
            position_bins: self.position_bins.or(base.position_bins),
            half_range: self.half_range.or(base.half_range),
            rotation_bins: self.rotation_bins.or(base.rotation_bins),
            threshold: self.threshold.or(base.threshold),
            max_components: self.max_components.or(base.max_components),
            cover: self.cover.or(base.cover),
            clear: self.clear.or(base.clear),
            nowhere: self.nowhere.or(base.nowhere),
        }
    }

    /// Whether the learner has something to choose: the grid or the threshold.
    pub fn leaves_a_choice(&self) -> bool {
        self.position_bins.is_none()
            || self.half_range.is_none()
            || self.rotation_bins.is_none()
            || self.threshold.is_none()
    }

    /// Every setting resolved: the pinned ones as pinned, the others from `chosen`.
    pub fn resolve(&self, chosen: &PairSettings) -> PairSettings {
        PairSettings {
            position_bins: self.position_bins.unwrap_or(chosen.position_bins),
            half_range: self.half_range.unwrap_or(chosen.half_range),
            rotation_bins: self.rotation_bins.unwrap_or(chosen.rotation_bins),
            free_turn: chosen.free_turn,
            threshold: self.threshold.unwrap_or(chosen.threshold),
            max_components: self.max_components.unwrap_or(chosen.max_components),
            cover: self.cover.unwrap_or(chosen.cover),
            clear: self.clear.unwrap_or(chosen.clear),
            nowhere: self.nowhere.unwrap_or(chosen.nowhere),
        }
    }
}

impl From<PairSettings> for PinnedSettings {
    fn from(settings: PairSettings) -> Self {
        PinnedSettings {
            position_bins: Some(settings.position_bins),
            half_range: Some(settings.half_range),
            rotation_bins: Some(settings.rotation_bins),
            threshold: Some(settings.threshold),
            max_components: Some(settings.max_components),
            cover: Some(settings.cover),
            clear: Some(settings.clear),
            nowhere: Some(settings.nowhere),
        }
    }
}

/// Everything the learner can be told.
#[derive(Debug, Clone, PartialEq)]
pub struct LearnConfig {
    /// Settings pinned for every pair (a pair's own entry wins).
    pub default: PinnedSettings,
    /// Settings pinned per ordered type pair.
    pub pairs: BTreeMap<TypePair, PinnedSettings>,
    /// Ordered type pairs that never get relations.
    pub ignored: BTreeSet<TypePair>,
    /// A cell is critical only if at least this many demonstrations visit it, whatever θ says.
    pub min_support: usize,
    /// A critical voxel keeps each rotation cell used by at least this share of its visiting demonstrations.
    pub rotation_share: f64,
    /// Poses drawn uniformly from a region to fit its mixture.
    pub samples_per_region: usize,
    /// How far (m) an object may settle from where it was let go: chosen regions keep every demonstrated pose
    /// at least this far inside their cells, so that the relations an object had when released still hold
    /// once it has come to rest. The world's settle rule decides it (lamp-build passes its largest drop).
    pub release_tolerance: f64,
    /// The one seed of all randomness in learning.
    pub seed: u64,
    /// Per object type, the turns of its frame that map its shape onto itself (the identity
    /// first); a pair of types with any besides the identity compares relative poses up to them
    /// (lamp-abstraction's `PairSymmetry`). Empty: every relative pose as recorded.
    pub symmetries: BTreeMap<String, Vec<nalgebra::UnitQuaternion<f64>>>,
    /// Whether each pair with a symmetry is compared up to it only where the demonstrations show
    /// that it pays (`symmetry auto`, [`crate::symmetry_choice`]), rather than always (`on`).
    pub symmetry_from_data: bool,
}

impl Default for LearnConfig {
    fn default() -> Self {
        LearnConfig {
            default: PinnedSettings::default(),
            pairs: BTreeMap::new(),
            ignored: BTreeSet::new(),
            min_support: 3,
            rotation_share: 0.1,
            samples_per_region: 400,
            release_tolerance: 0.005,
            seed: 0,
            symmetries: BTreeMap::new(),
            symmetry_from_data: false,
        }
    }
}

/// Fewer samples than this cannot support a full-covariance mixture in the 9-D feature space.
pub const MIN_SAMPLES_PER_REGION: usize = 50;

impl LearnConfig {
    /// The settings pinned for an ordered pair: its own entry (else the reversed pair's) over the default.
    pub fn pinned(&self, pair: &TypePair) -> PinnedSettings {
        let reversed = TypePair::new(pair.secondary.clone(), pair.primary.clone());
        match self.pairs.get(pair).or_else(|| self.pairs.get(&reversed)) {
            Some(own) => own.over(&self.default),
            None => self.default.clone(),
        }
    }

    /// The symmetry a pair's relative poses are compared up to, if its types have any.
    pub fn pair_symmetry(&self, pair: &TypePair) -> Option<lamp_abstraction::PairSymmetry> {
        let turns = |type_name: &str| self.symmetries.get(type_name).cloned().unwrap_or_default();
        lamp_abstraction::PairSymmetry::new(turns(&pair.primary), turns(&pair.secondary))
    }

    /// Whether a pair (in either order) is ignored.
    pub fn is_ignored(&self, pair: &TypePair) -> bool {
        let reversed = TypePair::new(pair.secondary.clone(), pair.primary.clone());
        self.ignored.contains(pair) || self.ignored.contains(&reversed)
    }

    /// Checks every setting.
    pub fn validate(&self) -> Result<(), LearnError> {
        let global = |reason: &str| LearnError::BadSetting {
            pair: "all pairs".into(),
            reason: reason.into(),
        };
        if !(self.rotation_share > 0.0 && self.rotation_share <= 1.0) {
            return Err(global("the rotation share must be in (0, 1]"));
        }
        if self.min_support == 0 {
            return Err(global("the minimum support must be at least 1 demonstration"));
        }
        if self.samples_per_region < MIN_SAMPLES_PER_REGION {
            return Err(global(&format!(
                "at least {MIN_SAMPLES_PER_REGION} samples per region are needed"
            )));
        }
        validate_pair("the default", &self.default)?;
        for (pair, settings) in &self.pairs {
            validate_pair(&pair.to_string(), settings)?;
        }
        Ok(())
    }
}

fn validate_pair(name: &str, settings: &PinnedSettings) -> Result<(), LearnError> {
    let fail = |reason: &str| {
        Err(LearnError::BadSetting { pair: name.to_string(), reason: reason.to_string() })
    };
    if settings.position_bins.is_some_and(|bins| bins.contains(&0))
        || settings.rotation_bins == Some(0)
    {
        return fail("every bin count must be at least 1");
    }
    if settings.half_range.is_some_and(|range| !range.iter().all(|r| r.is_finite() && *r > 0.0)) {
        return fail("half-ranges must be positive");
    }
    if settings.threshold.is_some_and(|threshold| !(threshold > 0.0 && threshold <= 1.0)) {
        return fail("the threshold θ must be in (0, 1]");
    }
    if settings.max_components == Some(0) {
        return fail("at least one mixture component is needed");
    }
    if settings.cover.is_some_and(|cover| !(cover > 0.0 && cover <= 1.0)) {
        return fail("the cover fraction must be in (0, 1]");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_are_rejected() {
        let mut config = LearnConfig::default();
        assert_eq!(config.validate(), Ok(()));
        config.default.threshold = Some(0.0);
        assert!(config.validate().is_err());
        config.default.threshold = Some(1.0);
        assert_eq!(config.validate(), Ok(()));
        config.default.half_range = Some([0.1, -1.0, 0.1]);
        assert!(config.validate().is_err());
    }

    #[test]
    fn settings_fall_back_to_the_reversed_pair_then_the_default() {
        let mut config = LearnConfig::default();
        config.default.rotation_bins = Some(21);
        let special = PinnedSettings { threshold: Some(0.3), ..PinnedSettings::default() };
        config.pairs.insert(TypePair::new("surface", "can"), special);
        let surface_can = config.pinned(&TypePair::new("can", "surface"));
        assert_eq!((surface_can.threshold, surface_can.rotation_bins), (Some(0.3), Some(21)));
        let gripper_can = config.pinned(&TypePair::new("gripper", "can"));
        assert_eq!((gripper_can.threshold, gripper_can.rotation_bins), (None, Some(21)));
        assert!(gripper_can.leaves_a_choice());
        let all = PinnedSettings::from(PairSettings::DEFAULT);
        assert!(!all.leaves_a_choice());
        assert_eq!(
            all.resolve(&PairSettings { threshold: 0.9, ..PairSettings::DEFAULT }),
            PairSettings::DEFAULT
        );
    }
}
