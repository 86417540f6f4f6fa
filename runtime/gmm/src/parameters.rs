//! Mixture parameters in the flat layout EM works on, with what the E-step needs (inverse Cholesky factors,
//! log normalisers) derived once per M-step; converts to and from the validated [`GaussianMixture`].

use crate::linalg::{LN_2PI, invert_lower, log_determinant};
use crate::mixture::GaussianMixture;

/// Mixture parameters in flat arrays, with what the E-step needs precomputed once per M-step.
#[derive(Debug, Clone)]
pub(crate) struct Parameters {
    pub(crate) dimension: usize,
    pub(crate) weights: Vec<f64>,
    /// `k × d`, component-major.
    pub(crate) means: Vec<f64>,
    /// `k × d × d`, each row-major and symmetric.
    pub(crate) covariances: Vec<f64>,
    /// Lower Cholesky factors `L_k`, `k × d × d`.
    pub(crate) factors: Vec<f64>,
    /// `L_k⁻¹`, `k × d × d`.
    pub(crate) inverse_factors: Vec<f64>,
    /// ln w_k − ½ (d ln 2π + ln det Σ_k).
    pub(crate) log_normalisers: Vec<f64>,
}

impl Parameters {
    /// Derives the inverse factors and log normalisers from validated weights, means and factors.
    pub(crate) fn new(
        dimension: usize,
        weights: Vec<f64>,
        means: Vec<f64>,
        covariances: Vec<f64>,
        factors: Vec<f64>,
    ) -> Self {
        let square = dimension * dimension;
        let inverse_factors = factors
            .chunks_exact(square)
            .flat_map(|factor| invert_lower(factor, dimension))
            .collect();
        let log_normalisers = weights
            .iter()
            .zip(factors.chunks_exact(square))
            .map(|(weight, factor)| {
                weight.ln() - 0.5 * (dimension as f64 * LN_2PI + log_determinant(factor, dimension))
            })
            .collect();
        Self { dimension, weights, means, covariances, factors, inverse_factors, log_normalisers }
    }

    /// The parameters of a validated mixture.
    pub(crate) fn from_mixture(mixture: &GaussianMixture) -> Self {
        Self::new(
            mixture.dimension(),
            mixture.weights().to_vec(),
            mixture.means().concat(),
            mixture.covariances().concat(),
            mixture.cholesky_factors().concat(),
        )
    }

    /// The mixture value; the factors come from a successful Cholesky factorisation, so no validation is needed.
    pub(crate) fn into_mixture(self) -> GaussianMixture {
        let dimension = self.dimension;
        let split = |values: Vec<f64>, size: usize| -> Vec<Vec<f64>> {
            values.chunks_exact(size).map(<[f64]>::to_vec).collect()
        };
        GaussianMixture::from_factored(
            dimension,
            self.weights,
            split(self.means, dimension),
            split(self.covariances, dimension * dimension),
            split(self.factors, dimension * dimension),
        )
    }

    pub(crate) fn component_count(&self) -> usize {
        self.weights.len()
    }
}
