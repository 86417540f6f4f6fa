//! Learning settings as the spec writes them: block-level settings, per type-pair overrides and
//! ignored pairs.
//!
//! lamp-spec knows no defaults: a setting the spec leaves out is `None`, and the learner then
//! chooses it from the demonstrations or takes lamp-learn's one table of defaults (see
//! `docs/learning.md`).

use std::collections::{BTreeMap, BTreeSet};

/// An ordered pair of type names: (primary, secondary).
pub type TypePair = (String, String);

/// Discretisation and model settings for one type pair, each `None` where the spec leaves it out
/// (the learner then chooses it from the demonstrations or takes lamp-learn's default; see
/// `docs/learning.md`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PairSettings {
    /// Voxel counts along x, y, z of the relative position.
    pub position_bins: Option<[u32; 3]>,
    /// Half-ranges (metres) of the relative position along x, y, z.
    pub position_range: Option<[f64; 3]>,
    /// Bins per rotation component.
    pub rotation_bins: Option<u32>,
    /// Criticality threshold θ ∈ (0, 1]: fraction of demonstrations that must visit a cell.
    pub threshold: Option<f64>,
    /// Upper bound on Gaussian components per region (BIC chooses up to this).
    pub max_components: Option<u32>,
    /// Fraction of a region's own samples the membership threshold must accept.
    pub likelihood_cover: Option<f64>,
    /// Whether `clear_<t1>_<t2>_<k>(x)` relations ("no t2 in region k of x") are invented. `auto`
    /// leaves them out of the regions where two t2 fit at once (a box holding cans), where
    /// "region k is empty" would wrongly become a precondition of putting one more in.
    pub clear: Option<Switch>,
    /// Whether `nowhere_<t1>_<t2>_<k>(y)` relations ("y is in region k of no t1") are invented.
    /// `auto` leaves them out of the regions where y fits in two t1 at once.
    pub nowhere: Option<Switch>,
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

/// The `learn { … }` block: its settings as written, and the per-pair overrides merged over them.
#[derive(Clone, Debug, PartialEq)]
pub struct Learning {
    /// The block-level settings, as written (for every pair without an override).
    pub defaults: PairSettings,
    /// Settings per overridden pair: the pair's own settings merged over the block-level ones.
    pub pairs: BTreeMap<TypePair, PairSettings>,
    /// Pairs excluded from learning, in both orders.
    pub ignored_pairs: BTreeSet<TypePair>,
    /// `symmetry on|off|auto`: whether relative poses are compared up to the turns that map the
    /// object types' shapes onto themselves. Left out, or `auto`: per pair, where the
    /// demonstrations show that it pays (see `docs/learning.md`, "Symmetric shapes").
    pub symmetry: Option<Switch>,
}

impl Learning {
    /// The settings for an ordered pair; an override written in either order applies, else the
    /// block-level settings.
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
