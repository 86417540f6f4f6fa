//! Expectation–maximisation for full-covariance mixtures, step for step as scikit-learn's `GaussianMixture`
//! (responsibilities, `reg_covar` on the diagonal, convergence on the change of the mean log-likelihood).

use crate::data::Samples;
use crate::error::GmmError;
use crate::linalg::{cholesky_lower, log_sum_exp};
use crate::mixture::GaussianMixture;

/// Added to every component's responsibility mass, as scikit-learn does (`10 · eps`), so that a component that
/// lost all its points still has a finite mean and weight instead of 0 / 0.
const EMPTY_COMPONENT_MASS: f64 = 10.0 * f64::EPSILON;

/// Smallest diagonal jitter tried, relative to the mean variance, when a covariance (with the configured
/// regularisation) has no Cholesky factor; only reachable with zero regularisation on degenerate data.
const JITTER_FLOOR: f64 = 1e-10;

/// How many tenfold increases of the jitter are tried before giving up.
const JITTER_ATTEMPTS: usize = 12;

/// The outcome of one EM run.
#[derive(Debug, Clone)]
pub(crate) struct EmRun {
    pub(crate) mixture: GaussianMixture,
    /// EM iterations performed (E-step plus M-step pairs).
    pub(crate) iterations: usize,
    /// Whether the mean log-likelihood changed by less than the tolerance before the iteration limit.
    pub(crate) converged: bool,
}

/// Settings EM itself needs.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EmSettings {
    pub(crate) max_iterations: usize,
    pub(crate) tolerance: f64,
    pub(crate) regularisation: f64,
}

/// Mean log-likelihood of the data and the normalised responsibilities (row-major, points × components).
pub(crate) fn expectation(mixture: &GaussianMixture, samples: &Samples) -> (f64, Vec<f64>) {
    let components = mixture.component_count();
    let mut responsibilities = vec![0.0; samples.count() * components];
    let mut scratch = vec![0.0; samples.dimension()];
    let mut total = 0.0;
    for (row, terms) in samples.rows().zip(responsibilities.chunks_exact_mut(components)) {
        mixture.component_log_terms(row, &mut scratch, terms);
        let log_density = log_sum_exp(terms);
        total += log_density;
        for term in terms.iter_mut() {
            *term = (*term - log_density).exp();
        }
    }
    (total / samples.count() as f64, responsibilities)
}

/// Maximum-likelihood parameters for given responsibilities (row-major, points × components), with
/// `regularisation` added to every covariance diagonal.
pub(crate) fn maximisation(
    samples: &Samples,
    responsibilities: &[f64],
    components: usize,
    regularisation: f64,
) -> Result<GaussianMixture, GmmError> {
    let dimension = samples.dimension();
    let mut masses = vec![EMPTY_COMPONENT_MASS; components];
    let mut means = vec![vec![0.0; dimension]; components];
    for (row, weights) in samples.rows().zip(responsibilities.chunks_exact(components)) {
        for (component, &weight) in weights.iter().enumerate() {
            masses[component] += weight;
            for (sum, value) in means[component].iter_mut().zip(row) {
                *sum += weight * value;
            }
        }
    }
    for (mean, mass) in means.iter_mut().zip(&masses) {
        for value in mean.iter_mut() {
            *value /= mass;
        }
    }
    let mut covariances = vec![vec![0.0; dimension * dimension]; components];
    let mut difference = vec![0.0; dimension];
    for (row, weights) in samples.rows().zip(responsibilities.chunks_exact(components)) {
        for (component, &weight) in weights.iter().enumerate() {
            if weight == 0.0 {
                continue;
            }
            for ((delta, value), mean) in difference.iter_mut().zip(row).zip(&means[component]) {
                *delta = value - mean;
            }
            let covariance = &mut covariances[component];
            for first in 0..dimension {
                let scaled = weight * difference[first];
                for second in 0..=first {
                    covariance[first * dimension + second] += scaled * difference[second];
                }
            }
        }
    }
    let mut factors = Vec::with_capacity(components);
    for (component, (covariance, mass)) in covariances.iter_mut().zip(&masses).enumerate() {
        for first in 0..dimension {
            for second in 0..=first {
                let value = covariance[first * dimension + second] / mass;
                covariance[first * dimension + second] = value;
                covariance[second * dimension + first] = value;
            }
            covariance[first * dimension + first] += regularisation;
        }
        factors.push(factor_with_jitter(covariance, dimension, regularisation, component)?);
    }
    let total_mass: f64 = masses.iter().sum();
    let weights = masses.iter().map(|mass| mass / total_mass).collect();
    Ok(GaussianMixture::from_factored(dimension, weights, means, covariances, factors))
}

/// The Cholesky factor of `covariance`, adding growing diagonal jitter (and keeping it in `covariance`) if the
/// matrix is numerically singular.
fn factor_with_jitter(
    covariance: &mut [f64],
    dimension: usize,
    regularisation: f64,
    component: usize,
) -> Result<Vec<f64>, GmmError> {
    if let Some(factor) = cholesky_lower(covariance, dimension) {
        return Ok(factor);
    }
    let mean_variance =
        (0..dimension).map(|index| covariance[index * dimension + index].abs()).sum::<f64>()
            / dimension as f64;
    let mut jitter = regularisation.max(JITTER_FLOOR * mean_variance.max(1.0));
    let mut added = 0.0;
    for _ in 0..JITTER_ATTEMPTS {
        for index in 0..dimension {
            covariance[index * dimension + index] += jitter - added;
        }
        added = jitter;
        if let Some(factor) = cholesky_lower(covariance, dimension) {
            return Ok(factor);
        }
        jitter *= 10.0;
    }
    Err(GmmError::CovarianceNotPositiveDefinite { component })
}

/// Runs EM from `initial` until the mean log-likelihood changes by less than the tolerance or the iteration
/// limit is reached.
///
/// Like scikit-learn, the log-likelihood tested for convergence is the one computed in the E-step, that is, of
/// the parameters before the last M-step; the returned mixture is the one after it.
pub(crate) fn run(
    initial: GaussianMixture,
    samples: &Samples,
    settings: EmSettings,
) -> Result<EmRun, GmmError> {
    let components = initial.component_count();
    let mut mixture = initial;
    let mut lower_bound = f64::NEG_INFINITY;
    let mut iterations = 0;
    let mut converged = false;
    while iterations < settings.max_iterations {
        iterations += 1;
        let previous = lower_bound;
        let (mean_log_likelihood, responsibilities) = expectation(&mixture, samples);
        mixture = maximisation(samples, &responsibilities, components, settings.regularisation)?;
        lower_bound = mean_log_likelihood;
        if (lower_bound - previous).abs() < settings.tolerance {
            converged = true;
            break;
        }
    }
    Ok(EmRun { mixture, iterations, converged })
}
