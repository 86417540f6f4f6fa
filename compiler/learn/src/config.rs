//! Learning settings: discretisation, criticality threshold and mixture settings per ordered type pair, and the seed.

use std::collections::{BTreeMap, BTreeSet};

use crate::error::LearnError;

pub use lamp_abstraction::TypePair;

/// Settings of one type pair.
#[derive(Debug, Clone, PartialEq)]
pub struct PairSettings {
    /// Position bins along x, y and z of the primary's frame.
    pub position_bins: [usize; 3],
    /// Half-ranges (m): positions outside `[-R, R]` on any axis fall in no cell.
    pub half_range: [f64; 3],
    /// Bins per rotation-vector component over `[-π, π]`.
    pub rotation_bins: usize,
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

impl Default for PairSettings {
    fn default() -> Self {
        PairSettings {
            position_bins: [16, 16, 16],
            half_range: [0.2, 0.2, 0.2],
            rotation_bins: 24,
            threshold: 0.5,
            max_components: 4,
            cover: 0.99,
            clear: Switch::Auto,
            nowhere: Switch::Auto,
        }
    }
}

/// Everything the learner can be told.
#[derive(Debug, Clone, PartialEq)]
pub struct LearnConfig {
    /// Settings for pairs not listed in `pairs`.
    pub default: PairSettings,
    /// Settings per ordered type pair.
    pub pairs: BTreeMap<TypePair, PairSettings>,
    /// Ordered type pairs that never get relations.
    pub ignored: BTreeSet<TypePair>,
    /// A cell is critical only if at least this many demonstrations visit it, whatever θ says.
    pub min_support: usize,
    /// A critical voxel keeps each rotation cell used by at least this share of its visiting demonstrations.
    pub rotation_share: f64,
    /// Poses drawn uniformly from a region to fit its mixture.
    pub samples_per_region: usize,
    /// The one seed of all randomness in learning.
    pub seed: u64,
}

impl Default for LearnConfig {
    fn default() -> Self {
        LearnConfig {
            default: PairSettings::default(),
            pairs: BTreeMap::new(),
            ignored: BTreeSet::new(),
            min_support: 3,
            rotation_share: 0.1,
            samples_per_region: 400,
            seed: 0,
        }
    }
}

/// Fewer samples than this cannot support a full-covariance mixture in the 9-D feature space.
pub const MIN_SAMPLES_PER_REGION: usize = 50;

impl LearnConfig {
    /// The settings of an ordered pair: its own entry, else the entry of the reversed pair, else the default.
    pub fn settings(&self, pair: &TypePair) -> &PairSettings {
        let reversed = TypePair::new(pair.secondary.clone(), pair.primary.clone());
        self.pairs.get(pair).or_else(|| self.pairs.get(&reversed)).unwrap_or(&self.default)
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

fn validate_pair(name: &str, settings: &PairSettings) -> Result<(), LearnError> {
    let fail = |reason: &str| {
        Err(LearnError::BadSetting { pair: name.to_string(), reason: reason.to_string() })
    };
    if settings.position_bins.contains(&0) || settings.rotation_bins == 0 {
        return fail("every bin count must be at least 1");
    }
    if !settings.half_range.iter().all(|r| r.is_finite() && *r > 0.0) {
        return fail("half-ranges must be positive");
    }
    if !(settings.threshold > 0.0 && settings.threshold <= 1.0) {
        return fail("the threshold θ must be in (0, 1]");
    }
    if settings.max_components == 0 {
        return fail("at least one mixture component is needed");
    }
    if !(settings.cover > 0.0 && settings.cover <= 1.0) {
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
        config.default.threshold = 0.0;
        assert!(config.validate().is_err());
        config.default.threshold = 1.0;
        assert_eq!(config.validate(), Ok(()));
        config.default.half_range[1] = -1.0;
        assert!(config.validate().is_err());
    }

    #[test]
    fn settings_fall_back_to_the_reversed_pair_then_the_default() {
        let mut config = LearnConfig::default();
        let special = PairSettings { threshold: 0.3, ..PairSettings::default() };
        config.pairs.insert(TypePair::new("surface", "can"), special);
        assert_eq!(config.settings(&TypePair::new("can", "surface")).threshold, 0.3);
        assert_eq!(config.settings(&TypePair::new("gripper", "can")).threshold, 0.5);
    }
}
