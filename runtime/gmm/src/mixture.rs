//! The `GaussianMixture` value: validated parameters, cached Cholesky factors, log density, sampling and the
//! serialised layout.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};

use crate::error::GmmError;
use crate::linalg::{LN_2PI, cholesky_lower, log_determinant, log_sum_exp, mahalanobis_squared};

/// How far the weights may sum from one: loose enough for weights written by hand with six or more decimals or
/// accumulated by EM, tight enough to catch weights that were never normalised.
pub const WEIGHT_SUM_TOLERANCE: f64 = 1e-6;

/// Largest asymmetry `|C_ij − C_ji|` accepted, relative to the largest entry of the matrix: round-off from
/// computing `Σ r (x−μ)(x−μ)ᵀ` stays many orders of magnitude below this.
pub const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// A finite mixture of multivariate normal distributions with full covariances.
///
/// Build one with [`GaussianMixture::new`] or fit one with [`crate::fit`]; the constructor guarantees that the
/// weights are non-negative and sum to one and that every covariance is symmetric positive definite, so every
/// method below is total.
/// Serialised (serde) as [`MixtureParameters`]; deserialisation runs the same validation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "MixtureParameters", into = "MixtureParameters")]
pub struct GaussianMixture {
    dimension: usize,
    weights: Vec<f64>,
    means: Vec<Vec<f64>>,
    /// Row-major `dimension × dimension`, symmetric.
    covariances: Vec<Vec<f64>>,
    /// Lower Cholesky factor of each covariance, row-major.
    factors: Vec<Vec<f64>>,
    /// ln w_k − ½ (d ln 2π + ln det Σ_k): everything in ln(w_k N(x; μ_k, Σ_k)) except the Mahalanobis term.
    log_normalisers: Vec<f64>,
}

/// The stable serialised layout of a [`GaussianMixture`]: plain arrays, covariances row-major.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MixtureParameters {
    /// Length of every feature vector.
    pub dimension: usize,
    /// Mixing weights, one per component, summing to one.
    pub weights: Vec<f64>,
    /// Component means, each of length `dimension`.
    pub means: Vec<Vec<f64>>,
    /// Component covariances, each `dimension × dimension` entries in row-major order.
    pub covariances: Vec<Vec<f64>>,
}

impl GaussianMixture {
    /// Validates and builds a mixture.
    ///
    /// `means[k]` has `d` entries and `covariances[k]` has `d·d` entries in row-major order, where `d` is the
    /// length of the first mean.
    /// Errors when the shapes disagree, a value is not finite, a weight is negative, the weights do not sum to
    /// one within [`WEIGHT_SUM_TOLERANCE`], or a covariance is not symmetric ([`SYMMETRY_TOLERANCE`]) and
    /// positive definite.
    /// A covariance that is symmetric within the tolerance is stored exactly symmetrised.
    pub fn new(
        weights: Vec<f64>,
        means: Vec<Vec<f64>>,
        covariances: Vec<Vec<f64>>,
    ) -> Result<Self, GmmError> {
        let dimension = means.first().ok_or(GmmError::NoComponents)?.len();
        Self::with_dimension(dimension, weights, means, covariances)
    }

    fn with_dimension(
        dimension: usize,
        weights: Vec<f64>,
        means: Vec<Vec<f64>>,
        mut covariances: Vec<Vec<f64>>,
    ) -> Result<Self, GmmError> {
        if weights.is_empty() && means.is_empty() && covariances.is_empty() {
            return Err(GmmError::NoComponents);
        }
        if weights.len() != means.len() || weights.len() != covariances.len() {
            return Err(GmmError::ComponentCountMismatch {
                weights: weights.len(),
                means: means.len(),
                covariances: covariances.len(),
            });
        }
        if dimension == 0 {
            return Err(GmmError::ZeroDimension);
        }
        for (index, &weight) in weights.iter().enumerate() {
            if !weight.is_finite() {
                return Err(GmmError::NotFinite { what: format!("weight {index}") });
            }
            if weight < 0.0 {
                return Err(GmmError::NegativeWeight { index, value: weight });
            }
        }
        let sum: f64 = weights.iter().sum();
        if (sum - 1.0).abs() > WEIGHT_SUM_TOLERANCE {
            return Err(GmmError::WeightsNotNormalised { sum });
        }
        for (component, mean) in means.iter().enumerate() {
            check_finite_vector(mean, dimension, &format!("mean of component {component}"))?;
        }
        let mut factors = Vec::with_capacity(covariances.len());
        for (component, covariance) in covariances.iter_mut().enumerate() {
            let what = format!("covariance of component {component}");
            check_finite_vector(covariance, dimension * dimension, &what)?;
            symmetrise(covariance, dimension)
                .ok_or(GmmError::CovarianceNotSymmetric { component })?;
            let factor = cholesky_lower(covariance, dimension)
                .ok_or(GmmError::CovarianceNotPositiveDefinite { component })?;
            factors.push(factor);
        }
        Ok(Self::from_factored(dimension, weights, means, covariances, factors))
    }

    /// Assembles a mixture from parameters whose factors are already known to be valid.
    pub(crate) fn from_factored(
        dimension: usize,
        weights: Vec<f64>,
        means: Vec<Vec<f64>>,
        covariances: Vec<Vec<f64>>,
        factors: Vec<Vec<f64>>,
    ) -> Self {
        let log_normalisers = weights
            .iter()
            .zip(&factors)
            .map(|(weight, factor)| {
                weight.ln() - 0.5 * (dimension as f64 * LN_2PI + log_determinant(factor, dimension))
            })
            .collect();
        Self { dimension, weights, means, covariances, factors, log_normalisers }
    }

    /// Length of the feature vectors this mixture is over.
    pub fn dimension(&self) -> usize {
        self.dimension
    }

    /// Number of mixture components.
    pub fn component_count(&self) -> usize {
        self.weights.len()
    }

    /// Mixing weights (sum to one).
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// Component means.
    pub fn means(&self) -> &[Vec<f64>] {
        &self.means
    }

    /// Component covariances, each row-major `dimension × dimension`.
    pub fn covariances(&self) -> &[Vec<f64>] {
        &self.covariances
    }

    /// Lower Cholesky factors `L_k` (row-major, `L_k·L_kᵀ = Σ_k`).
    pub fn cholesky_factors(&self) -> &[Vec<f64>] {
        &self.factors
    }

    /// ln p(x) = ln Σ_k w_k N(x; μ_k, Σ_k), computed with log-sum-exp so that far-away points give large
    /// negative values rather than −∞.
    ///
    /// A point whose length differs from [`Self::dimension`] has no density under the mixture: the result is
    /// −∞. A point with a NaN coordinate gives NaN.
    pub fn log_density(&self, point: &[f64]) -> f64 {
        if point.len() != self.dimension {
            return f64::NEG_INFINITY;
        }
        let mut scratch = vec![0.0; self.dimension];
        let mut terms = vec![0.0; self.component_count()];
        self.component_log_terms(point, &mut scratch, &mut terms);
        log_sum_exp(&terms)
    }

    /// ln(w_k N(x; μ_k, Σ_k)) for every component, into `terms`.
    pub(crate) fn component_log_terms(
        &self,
        point: &[f64],
        scratch: &mut [f64],
        terms: &mut [f64],
    ) {
        for (component, term) in terms.iter_mut().enumerate() {
            let distance = mahalanobis_squared(
                &self.factors[component],
                &self.means[component],
                point,
                scratch,
            );
            *term = self.log_normalisers[component] - 0.5 * distance;
        }
    }

    /// Whether `point` is inside the region `{x : ln p(x) ≥ threshold}`; see [`crate::calibrate_threshold`].
    pub fn contains(&self, point: &[f64], threshold: f64) -> bool {
        self.log_density(point) >= threshold
    }

    /// One draw: a component chosen with probability equal to its weight, then `μ + L·z` with `z` standard
    /// normal.
    pub fn sample(&self, rng: &mut ChaCha8Rng) -> Vec<f64> {
        let uniform: f64 = rng.random();
        let mut remaining = uniform;
        // Round-off can leave `remaining` positive after the last weight; the last component takes it.
        let mut chosen = self.component_count() - 1;
        for (component, &weight) in self.weights.iter().enumerate() {
            if remaining < weight {
                chosen = component;
                break;
            }
            remaining -= weight;
        }
        self.sample_component(chosen, rng)
    }

    /// One draw from the components `among` alone: one of them chosen with probability proportional to
    /// its weight, then `μ + L·z`. Indices out of range are ignored; with none left (or all of zero
    /// weight), the whole mixture is drawn ([`GaussianMixture::sample`]).
    pub fn sample_among(&self, among: &[usize], rng: &mut ChaCha8Rng) -> Vec<f64> {
        let members: Vec<usize> =
            among.iter().copied().filter(|&component| component < self.component_count()).collect();
        let total: f64 = members.iter().map(|&component| self.weights[component]).sum();
        let Some(&last) = members.last().filter(|_| total > 0.0) else { return self.sample(rng) };
        let uniform: f64 = rng.random();
        let mut remaining = uniform * total;
        let mut chosen = last;
        for &component in &members {
            if remaining < self.weights[component] {
                chosen = component;
                break;
            }
            remaining -= self.weights[component];
        }
        self.sample_component(chosen, rng)
    }

    /// One draw of component `chosen` (an index below [`GaussianMixture::component_count`]): `μ + L·z`
    /// with `z` standard normal.
    fn sample_component(&self, chosen: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
        let standard: Vec<f64> =
            (0..self.dimension).map(|_| StandardNormal.sample(&mut *rng)).collect();
        let factor = &self.factors[chosen];
        self.means[chosen]
            .iter()
            .enumerate()
            .map(|(row, mean)| {
                let offset: f64 = (0..=row)
                    .map(|column| factor[row * self.dimension + column] * standard[column])
                    .sum();
                mean + offset
            })
            .collect()
    }

    /// The parameters in their serialised layout.
    pub fn parameters(&self) -> MixtureParameters {
        MixtureParameters {
            dimension: self.dimension,
            weights: self.weights.clone(),
            means: self.means.clone(),
            covariances: self.covariances.clone(),
        }
    }
}

impl TryFrom<MixtureParameters> for GaussianMixture {
    type Error = GmmError;

    fn try_from(parameters: MixtureParameters) -> Result<Self, GmmError> {
        Self::with_dimension(
            parameters.dimension,
            parameters.weights,
            parameters.means,
            parameters.covariances,
        )
    }
}

impl From<GaussianMixture> for MixtureParameters {
    fn from(mixture: GaussianMixture) -> Self {
        Self {
            dimension: mixture.dimension,
            weights: mixture.weights,
            means: mixture.means,
            covariances: mixture.covariances,
        }
    }
}

fn check_finite_vector(values: &[f64], expected: usize, what: &str) -> Result<(), GmmError> {
    if values.len() != expected {
        return Err(GmmError::ShapeMismatch {
            what: what.to_owned(),
            expected,
            found: values.len(),
        });
    }
    if values.iter().any(|value| !value.is_finite()) {
        return Err(GmmError::NotFinite { what: what.to_owned() });
    }
    Ok(())
}

/// Replaces a nearly symmetric matrix by its symmetric part; `None` if it is not nearly symmetric.
fn symmetrise(matrix: &mut [f64], dimension: usize) -> Option<()> {
    let scale = matrix.iter().fold(0.0_f64, |largest, value| largest.max(value.abs()));
    for row in 0..dimension {
        for column in (row + 1)..dimension {
            let upper = matrix[row * dimension + column];
            let lower = matrix[column * dimension + row];
            if (upper - lower).abs() > SYMMETRY_TOLERANCE * scale {
                return None;
            }
            let average = 0.5 * (upper + lower);
            matrix[row * dimension + column] = average;
            matrix[column * dimension + row] = average;
        }
    }
    Some(())
}
