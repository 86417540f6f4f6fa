//! Learning settings: defaults, per type-pair overrides and ignored pairs.

use std::collections::{BTreeMap, BTreeSet};

/// An ordered pair of type names: (primary, secondary).
pub type TypePair = (String, String);

/// Discretisation and model settings for one type pair.
#[derive(Clone, Debug, PartialEq)]
pub struct PairSettings {
    /// Voxel counts along x, y, z of the relative position.
    pub position_bins: [u32; 3],
    /// Half-ranges (metres) of the relative position along x, y, z.
    pub position_range: [f64; 3],
    /// Bins per rotation component.
    pub rotation_bins: u32,
    /// Criticality threshold θ ∈ (0, 1]: fraction of demonstrations that must visit a cell.
    pub threshold: f64,
    /// Upper bound on Gaussian components per region (BIC chooses up to this).
    pub max_components: u32,
    /// Fraction of a region's own samples the membership threshold must accept.
    pub likelihood_cover: f64,
    /// Whether `clear_<t1>_<t2>_<k>(x)` relations ("no t2 in region k of x") are invented. `auto`
    /// (the default) leaves them out of the regions where two t2 fit at once (a box holding cans),
    /// where "region k is empty" would wrongly become a precondition of putting one more in.
    pub clear: Switch,
    /// Whether `nowhere_<t1>_<t2>_<k>(y)` relations ("y is in region k of no t1") are invented.
    /// `auto` (the default) leaves them out of the regions where y fits in two t1 at once.
    pub nowhere: Switch,
}

/// A relation family's switch: `on`, `off`, or `auto` (decided per region by the shapes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Switch {
    /// For every region of the pair.
    On,
    /// For no region of the pair.
    Off,
    /// For the regions where the learner's capacity test says one at a time.
    Auto,
}

impl PairSettings {
    /// Defaults, taken from the reference implementation's common values.
    pub const DEFAULT: PairSettings = PairSettings {
        position_bins: [35, 35, 35],
        position_range: [0.3, 0.3, 0.3],
        rotation_bins: 61,
        threshold: 0.5,
        max_components: 6,
        likelihood_cover: 0.99,
        clear: Switch::Auto,
        nowhere: Switch::Auto,
    };
}

/// The `learn { … }` block with its defaults resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct Learning {
    /// Settings for every pair without an override.
    pub defaults: PairSettings,
    /// Full settings per overridden pair (the override merged over `defaults`).
    pub pairs: BTreeMap<TypePair, PairSettings>,
    /// Pairs excluded from learning, in both orders.
    pub ignored_pairs: BTreeSet<TypePair>,
}

impl Learning {
    /// The settings for an ordered pair; an override written in either order applies.
    pub fn settings(&self, primary: &str, secondary: &str) -> &PairSettings {
        let forward = (primary.to_string(), secondary.to_string());
        let backward = (secondary.to_string(), primary.to_string());
        self.pairs.get(&forward).or_else(|| self.pairs.get(&backward)).unwrap_or(&self.defaults)
    }

    /// Whether the pair (in either order) is excluded from learning.
    pub fn is_ignored(&self, first: &str, second: &str) -> bool {
        self.ignored_pairs.contains(&(first.to_string(), second.to_string()))
    }
}
