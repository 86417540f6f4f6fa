//! A region's membership test and generator, behind [`RegionClassifier`]: the paper's Gaussian
//! mixture over continuous pose features with a log-density threshold, and the box of positions
//! its cells span.
//!
//! A pose's margin is its log density minus ε; sampling draws a feature and projects it back to a
//! pose. How a model is fitted to a region's cells is the learner's (`lamp_learn::region_model`).

use lamp_gmm::GaussianMixture;
use rand::RngExt as _;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::abstraction::RegionClassifier;
use crate::features::{FEATURE_DIMENSION, features_pose, pose_features};
use crate::free_turn::FreeTurn;
use crate::snapshot::Pose;
use crate::symmetry::PairSymmetry;

/// The features of a region with a free turn: the position and the swing's two components.
pub const SWING_FEATURE_DIMENSION: usize = 5;

/// Draws of the mixture per sample before one outside the region's extent is returned anyway.
pub const EXTENT_DRAWS: usize = 64;

/// The model of one region: a mixture over pose features, the log-density threshold ε of
/// membership, and the box its cells span in position.
///
/// A pose is in the region iff its position lies in that box and its log density is at least ε.
/// The box matters: a mixture fitted to a region of uniform cells leaks a component's tail past
/// the cells (a Gaussian of a box's spread accepts points well beyond its edges when the other
/// features match closely), and such a pose was never seen in a demonstration — a can beside the
/// box would count as in it.
///
/// A region that leaves a turn of the secondary free ([`FreeTurn`]) models poses by their position
/// and the swing left once the turn is taken out (five features), and draws the turn's angle
/// uniformly.
///
/// Serialised as `{ "g", "mixture", "threshold", "extent" }` and, for a free turn, `"free_turn"`,
/// and, for a pair compared up to its shapes' symmetries, `"symmetry"`,
/// the mixture in lamp-gmm's parameter layout; deserialising the mixture validates it, and
/// [`RegionModel::validate`] checks the rest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RegionModel {
    g: u8,
    mixture: GaussianMixture,
    /// ε: a pose is inside iff its log density is at least this.
    threshold: f64,
    /// Per axis, the lowest and highest position coordinate of the region's cells.
    extent: [[f64; 2]; 3],
    /// The turn of the secondary the region leaves free, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    free_turn: Option<FreeTurn>,
    /// The shapes' symmetries the region compares relative poses up to, if any: the mixture and
    /// extent are over orbit representatives ([`PairSymmetry`]), a pose's density is summed over
    /// its orbit, and a draw is turned to a place of the orbit at random.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    symmetry: Option<PairSymmetry>,
}

impl RegionModel {
    /// A model from its parts, checked as a deserialised one is ([`RegionModel::validate`]); with a
    /// free turn, the mixture is over [`RegionModel::feature_dimension`] features.
    pub fn new(
        g: u8,
        mixture: GaussianMixture,
        threshold: f64,
        extent: [[f64; 2]; 3],
        free_turn: Option<FreeTurn>,
    ) -> Result<Self, String> {
        let model = RegionModel { g, mixture, threshold, extent, free_turn, symmetry: None };
        model.validate()?;
        Ok(model)
    }

    /// The model comparing relative poses up to `symmetry` (its mixture and extent are over
    /// representatives, [`PairSymmetry::canonical`]).
    ///
    /// Representatives fold the space of relative poses: a can anywhere on a square box's floor,
    /// compared up to the box's half turn, is folded onto one side of a line through the floor's
    /// centre, and the mixture fitted to the folded poses thins out along that line as at any
    /// edge, though on the floor the line is no edge at all. So a pose's density is summed over
    /// the members of its orbit (the reflection that corrects a density estimate at a fold): deep
    /// inside the folded region one member carries it all and nothing changes, and on the line the
    /// two sides' tails add up to what the floor has elsewhere. The secondary's turns are left
    /// out where the region leaves the secondary's vertical turn free, as they then change no
    /// feature and would only count one pose several times.
    pub fn with_symmetry(self, symmetry: Option<PairSymmetry>) -> Self {
        RegionModel { symmetry, ..self }
    }

    /// The representative of `relative` the region is over: itself without a symmetry.
    pub fn representative(&self, relative: &Pose) -> Pose {
        match &self.symmetry {
            Some(symmetry) => symmetry.canonical(relative),
            None => *relative,
        }
    }

    /// The turn the region leaves free, if any.
    pub fn free_turn(&self) -> Option<FreeTurn> {
        self.free_turn
    }

    /// The number of features the mixture of a model that leaves `free_turn` free is over: the
    /// position and the 6-D rotation, or the position and the swing's two components.
    pub fn feature_dimension(free_turn: Option<&FreeTurn>) -> usize {
        if free_turn.is_some() { SWING_FEATURE_DIMENSION } else { FEATURE_DIMENSION }
    }

    /// The features of a pose for a model that leaves `free_turn` free (for fitting one): with a
    /// free turn, the position and the two components of the rotation's swing, so that the mixture
    /// spends no component on following the circle that every angle of the turn makes.
    pub fn features_with(free_turn: Option<&FreeTurn>, relative: &Pose) -> Vec<f64> {
        match free_turn {
            Some(turn) => {
                let position = relative.translation.vector;
                let [first, second] = turn.swing(&relative.rotation);
                vec![position.x, position.y, position.z, first, second]
            }
            None => pose_features(relative).to_vec(),
        }
    }

    /// The pose of a feature drawn from the mixture; with a free turn, at the turn's reference angle.
    fn feature_pose(&self, features: &[f64]) -> Pose {
        match &self.free_turn {
            Some(turn) => {
                let at = |index: usize| features.get(index).copied().unwrap_or(0.0);
                let rotation = turn.rotation([at(3), at(4)], 0.0);
                Pose::from_parts(nalgebra::Translation3::new(at(0), at(1), at(2)), rotation)
            }
            None => features_pose(features),
        }
    }

    /// Draws a relative pose: a feature from the mixture, its rotation columns projected to a
    /// rotation, redrawn (up to [`EXTENT_DRAWS`] times) while its position is outside the
    /// region's extent; with a free turn, its angle drawn uniformly.
    pub fn sample(&self, rng: &mut ChaCha8Rng) -> Pose {
        self.sample_with(rng, |mixture, rng| mixture.sample(rng))
    }

    /// Draws a relative pose as [`RegionModel::sample`] does, from the mixture's components
    /// `among` alone (by their weights); none in range draws the whole mixture.
    pub fn sample_among(&self, among: &[usize], rng: &mut ChaCha8Rng) -> Pose {
        self.sample_with(rng, |mixture, rng| mixture.sample_among(among, rng))
    }

    fn sample_with(
        &self,
        rng: &mut ChaCha8Rng,
        draw: impl Fn(&GaussianMixture, &mut ChaCha8Rng) -> Vec<f64>,
    ) -> Pose {
        let mut pose = self.feature_pose(&draw(&self.mixture, rng));
        for _ in 1..EXTENT_DRAWS {
            if self.outside(&pose) == 0.0 {
                break;
            }
            pose = self.feature_pose(&draw(&self.mixture, rng));
        }
        if let Some(turn) = &self.free_turn {
            let angle = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
            pose.rotation = turn.turned(&pose.rotation, angle);
        }
        // A representative is one place of its orbit: with the primary's frame turned, the same
        // placement at each of the others (a can in any part of a box, not one side of it).
        if let Some(symmetry) = self.symmetry.as_ref().filter(|symmetry| symmetry.primary.len() > 1)
        {
            pose = symmetry.primary_member(&pose, rng.random_range(0..symmetry.primary.len()));
        }
        pose
    }

    /// Per mixture component, the angle (radians, in `[0, π]`) of the rotation that turns
    /// `relative`'s orientation into that of the component's mean; with a free turn, of their
    /// orientations with the turn taken out, since every angle of it is in the region.
    pub fn component_turns(&self, relative: &Pose) -> Vec<f64> {
        let relative = self.representative(relative);
        let here = match &self.free_turn {
            Some(turn) => turn.untwisted(&relative.rotation),
            None => relative.rotation,
        };
        self.mixture
            .means()
            .iter()
            .map(|mean| {
                let there = self.feature_pose(mean).rotation;
                let there = match &self.free_turn {
                    Some(turn) => turn.untwisted(&there),
                    None => there,
                };
                here.angle_to(&there)
            })
            .collect()
    }

    /// How far (summed over axes, metres) a pose's position is outside the region's extent.
    fn outside(&self, relative: &Pose) -> f64 {
        let position = relative.translation.vector;
        (0..3)
            .map(|axis| {
                let [low, high] = self.extent[axis];
                (low - position[axis]).max(position[axis] - high).max(0.0)
            })
            .sum()
    }

    /// How widely the region spreads in position: the generalized variance (the determinant)
    /// of the mixture's position covariance as a whole, in m⁶. An action that makes several
    /// regions true at once is realised by sampling the narrowest and testing the others, the
    /// way one samples an intersection: draws from a wide region rarely land in a narrow one.
    pub fn position_spread(&self) -> f64 {
        let dimension = self.mixture.dimension();
        let mut mean = nalgebra::Vector3::<f64>::zeros();
        let mut second = nalgebra::Matrix3::<f64>::zeros();
        for ((weight, centre), covariance) in
            self.mixture.weights().iter().zip(self.mixture.means()).zip(self.mixture.covariances())
        {
            let centre = nalgebra::Vector3::new(centre[0], centre[1], centre[2]);
            let within =
                nalgebra::Matrix3::from_fn(|row, column| covariance[row * dimension + column]);
            mean += *weight * centre;
            second += *weight * (within + centre * centre.transpose());
        }
        (second - mean * mean.transpose()).determinant().max(0.0)
    }

    /// The number of mixture components BIC chose.
    pub fn component_count(&self) -> usize {
        self.mixture.component_count()
    }

    /// The mixture over pose features.
    pub fn mixture(&self) -> &GaussianMixture {
        &self.mixture
    }

    /// The log-density threshold ε of membership.
    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    /// The held flag of the region.
    pub fn held_flag(&self) -> u8 {
        self.g
    }

    /// Checks a deserialised model (the mixture itself was validated when it was built).
    pub fn validate(&self) -> Result<(), String> {
        let expected = Self::feature_dimension(self.free_turn.as_ref());
        if self.mixture.dimension() != expected {
            return Err(format!(
                "the mixture is over {} features, not {expected}",
                self.mixture.dimension()
            ));
        }
        if !self.threshold.is_finite() {
            return Err("the likelihood threshold is not finite".to_string());
        }
        if self.g > 1 {
            return Err(format!("the held flag is {}, not 0 or 1", self.g));
        }
        if self
            .extent
            .iter()
            .any(|[low, high]| !(low.is_finite() && high.is_finite() && low <= high))
        {
            return Err("the region's extent is not a box".to_string());
        }
        if let Some(turn) = &self.free_turn {
            turn.validate()?;
        }
        if let Some(symmetry) = &self.symmetry {
            symmetry.validate()?;
        }
        Ok(())
    }
}

impl RegionModel {
    /// The log density of `relative` itself, or how far its position is outside the extent.
    fn own_log_density(&self, relative: &Pose) -> Result<f64, f64> {
        let outside = self.outside(relative);
        if outside > 0.0 {
            return Err(outside);
        }
        Ok(self.mixture.log_density(&Self::features_with(self.free_turn.as_ref(), relative)))
    }

    /// The log of the density summed over `relative`'s orbit (members outside the extent add
    /// nothing), or, with every member outside, how far the nearest is.
    fn orbit_log_density(&self, symmetry: &PairSymmetry, relative: &Pose) -> Result<f64, f64> {
        let secondary_turns = self.free_turn.is_none_or(|turn| turn.axis != 2);
        // log Σ exp, kept as the largest term and the sum of the others' ratios to it.
        let mut largest = f64::NEG_INFINITY;
        let mut ratios = 0.0;
        let mut nearest_outside = f64::INFINITY;
        for member in symmetry.members(relative, secondary_turns) {
            match self.own_log_density(&member) {
                // A member the mixture gives no density adds nothing.
                Ok(log_density) if log_density == f64::NEG_INFINITY => {}
                Ok(log_density) if log_density > largest => {
                    ratios = ratios * (largest - log_density).exp() + 1.0;
                    largest = log_density;
                }
                Ok(log_density) => ratios += (log_density - largest).exp(),
                Err(outside) => nearest_outside = nearest_outside.min(outside),
            }
        }
        if ratios == 0.0 { Err(nearest_outside) } else { Ok(largest + ratios.ln()) }
    }
}

impl RegionClassifier for RegionModel {
    fn margin(&self, relative: &Pose) -> f64 {
        let log_density = match &self.symmetry {
            Some(symmetry) => self.orbit_log_density(symmetry, relative),
            None => self.own_log_density(relative),
        };
        match log_density {
            Ok(log_density) => log_density - self.threshold,
            // Below zero, and lower the further out.
            Err(outside) => -1.0 - outside,
        }
    }
}
