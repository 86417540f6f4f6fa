//! Expectation–maximisation for full-covariance mixtures, step for step as scikit-learn's `GaussianMixture`
//! (responsibilities, `reg_covar` on the diagonal, convergence on the change of the mean log-likelihood).
//!
//! The loops run over the column blocks of [`Samples`]: within a block, each loop runs over points, so it
//! vectorises; each block yields partial sums that are added in block order, so a fit gives bit-identical
//! results on any number of threads. Responsibilities are kept in one buffer laid out like the data
//! (block by block, component-major inside a block) and reused across iterations.

use crate::data::{BLOCK, Samples};
use crate::error::GmmError;
use crate::kernels::{block_moments, block_scatter, difference_buffer, log_terms, normalise};
use crate::linalg::cholesky_lower;
use crate::parallel::{Spread, map_blocks, map_blocks_mut};
use crate::parameters::Parameters;

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
    pub(crate) parameters: Parameters,
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
    /// Whether each pass spreads its blocks over the rayon pool.
    pub(crate) spread: Spread,
}

/// Responsibility masses (with [`EMPTY_COMPONENT_MASS`]) and responsibility-weighted means of every component.
struct Moments {
    masses: Vec<f64>,
    /// `k × d`, component-major.
    means: Vec<f64>,
}

/// Adds up per-block moment partials (as written by [`block_moments`], after `skip` leading values) in block
/// order.
fn combine_moments(
    partials: &[Vec<f64>],
    skip: usize,
    components: usize,
    dimension: usize,
) -> Moments {
    let mut totals = vec![0.0; components * (1 + dimension)];
    for partial in partials {
        for (total, value) in totals.iter_mut().zip(&partial[skip..]) {
            *total += value;
        }
    }
    let masses: Vec<f64> =
        totals[..components].iter().map(|mass| mass + EMPTY_COMPONENT_MASS).collect();
    let mut means = totals[components..].to_vec();
    for (mean, mass) in means.chunks_exact_mut(dimension).zip(&masses) {
        for value in mean {
            *value /= mass;
        }
    }
    Moments { masses, means }
}

/// The E-step: writes the responsibilities (block layout) and returns the mean log-likelihood per point with
/// the moments the M-step needs.
fn expectation(
    parameters: &Parameters,
    samples: &Samples,
    responsibilities: &mut [f64],
    spread: Spread,
) -> (f64, Moments) {
    let components = parameters.component_count();
    let dimension = parameters.dimension;
    let partials = map_blocks_mut(spread, responsibilities, components * BLOCK, |index, terms| {
        let block = samples.block(index);
        let len = samples.block_len(index);
        let mut differences = difference_buffer(dimension, len);
        for component in 0..components {
            let out = &mut terms[component * len..(component + 1) * len];
            log_terms(parameters, component, block, len, &mut differences, out);
        }
        let mut partial = vec![normalise(terms, components, len)];
        block_moments(block, terms, components, len, &mut partial);
        partial
    });
    let total: f64 = partials.iter().map(|partial| partial[0]).sum();
    let moments = combine_moments(&partials, 1, components, dimension);
    (total / samples.count() as f64, moments)
}

/// Mean log-likelihood per point, ln p(x) averaged over the data (scikit-learn's `score`).
pub(crate) fn mean_log_likelihood(
    parameters: &Parameters,
    samples: &Samples,
    spread: Spread,
) -> f64 {
    let components = parameters.component_count();
    let dimension = parameters.dimension;
    let partials = map_blocks(spread, samples.block_count(), |index| {
        let block = samples.block(index);
        let len = samples.block_len(index);
        let mut differences = difference_buffer(dimension, len);
        let mut terms = vec![0.0; components * len];
        for component in 0..components {
            let out = &mut terms[component * len..(component + 1) * len];
            log_terms(parameters, component, block, len, &mut differences, out);
        }
        normalise(&mut terms, components, len)
    });
    partials.iter().sum::<f64>() / samples.count() as f64
}

/// The M-step: maximum-likelihood parameters for the responsibilities and their moments, with `regularisation`
/// added to every covariance diagonal.
fn maximisation(
    samples: &Samples,
    responsibilities: &[f64],
    moments: Moments,
    regularisation: f64,
    spread: Spread,
) -> Result<Parameters, GmmError> {
    let Moments { masses, means } = moments;
    let components = masses.len();
    let dimension = samples.dimension();
    let partials = map_blocks(spread, samples.block_count(), |index| {
        let len = samples.block_len(index);
        let start = index * BLOCK * components;
        let mut partial = Vec::with_capacity(components * dimension * (dimension + 1) / 2);
        block_scatter(
            samples.block(index),
            &responsibilities[start..start + components * len],
            &means,
            len,
            &mut partial,
        );
        partial
    });
    let triangle = dimension * (dimension + 1) / 2;
    let mut scatter = vec![0.0; components * triangle];
    for partial in &partials {
        for (total, value) in scatter.iter_mut().zip(partial) {
            *total += value;
        }
    }
    let square = dimension * dimension;
    let mut covariances = vec![0.0; components * square];
    let mut factors = Vec::with_capacity(components * square);
    for (component, (covariance, mass)) in
        covariances.chunks_exact_mut(square).zip(&masses).enumerate()
    {
        let mut lower = scatter[component * triangle..(component + 1) * triangle].iter();
        for first in 0..dimension {
            for second in 0..=first {
                let value = lower.next().copied().unwrap_or_default() / mass;
                covariance[first * dimension + second] = value;
                covariance[second * dimension + first] = value;
            }
            covariance[first * dimension + first] += regularisation;
        }
        factors.extend(factor_with_jitter(covariance, dimension, regularisation, component)?);
    }
    let total_mass: f64 = masses.iter().sum();
    let weights = masses.iter().map(|mass| mass / total_mass).collect();
    Ok(Parameters::new(dimension, weights, means, covariances, factors))
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

/// The maximum-likelihood parameters of a hard assignment (`labels[n]` in `0..components`), as scikit-learn
/// starts EM from k-means labels.
pub(crate) fn from_labels(
    samples: &Samples,
    labels: &[usize],
    components: usize,
    regularisation: f64,
    spread: Spread,
) -> Result<Parameters, GmmError> {
    let mut responsibilities = vec![0.0; samples.count() * components];
    let partials =
        map_blocks_mut(spread, &mut responsibilities, components * BLOCK, |index, terms| {
            let len = samples.block_len(index);
            for (point, &label) in labels[index * BLOCK..index * BLOCK + len].iter().enumerate() {
                terms[label * len + point] = 1.0;
            }
            let mut partial = Vec::with_capacity(components * (1 + samples.dimension()));
            block_moments(samples.block(index), terms, components, len, &mut partial);
            partial
        });
    let moments = combine_moments(&partials, 0, components, samples.dimension());
    maximisation(samples, &responsibilities, moments, regularisation, spread)
}

/// Runs EM from `initial` until the mean log-likelihood changes by less than the tolerance or the iteration
/// limit is reached.
///
/// Like scikit-learn, the log-likelihood tested for convergence is the one computed in the E-step, that is, of
/// the parameters before the last M-step; the returned parameters are the ones after it.
pub(crate) fn run(
    initial: Parameters,
    samples: &Samples,
    settings: EmSettings,
) -> Result<EmRun, GmmError> {
    let mut responsibilities = vec![0.0; samples.count() * initial.component_count()];
    let mut parameters = initial;
    let mut lower_bound = f64::NEG_INFINITY;
    let mut iterations = 0;
    let mut converged = false;
    while iterations < settings.max_iterations {
        iterations += 1;
        let previous = lower_bound;
        let (mean_log_likelihood, moments) =
            expectation(&parameters, samples, &mut responsibilities, settings.spread);
        parameters = maximisation(
            samples,
            &responsibilities,
            moments,
            settings.regularisation,
            settings.spread,
        )?;
        lower_bound = mean_log_likelihood;
        if (lower_bound - previous).abs() < settings.tolerance {
            converged = true;
            break;
        }
    }
    Ok(EmRun { parameters, iterations, converged })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mixture::GaussianMixture;

    fn mixture() -> GaussianMixture {
        GaussianMixture::new(
            vec![0.3, 0.7],
            vec![vec![0.0, 1.0, -1.0], vec![2.0, 0.5, 0.0]],
            vec![
                vec![1.0, 0.4, 0.0, 0.4, 0.8, 0.1, 0.0, 0.1, 0.5],
                vec![0.6, 0.0, -0.2, 0.0, 1.2, 0.0, -0.2, 0.0, 0.9],
            ],
        )
        .expect("valid mixture")
    }

    fn points(count: usize) -> Vec<Vec<f64>> {
        (0..count)
            .map(|index| {
                let t = index as f64;
                vec![(t * 0.37).sin() * 2.0, (t * 0.11).cos(), (t * 0.05).sin() - 0.5]
            })
            .collect()
    }

    #[test]
    fn blocked_log_likelihood_matches_the_mixture() {
        let mixture = mixture();
        // More than one block, and a last block that is not a whole number of tiles.
        let rows = points(BLOCK + 13);
        let samples = Samples::from_rows(&rows).expect("well-formed data");
        let expected: f64 =
            rows.iter().map(|row| mixture.log_density(row)).sum::<f64>() / rows.len() as f64;
        let parameters = Parameters::from_mixture(&mixture);
        let ours = mean_log_likelihood(&parameters, &samples, Spread::Pool);
        assert_eq!(ours, mean_log_likelihood(&parameters, &samples, Spread::InPlace));
        assert!((ours - expected).abs() < 1e-12 * expected.abs(), "{ours} vs {expected}");
        let mut responsibilities = vec![0.0; rows.len() * 2];
        let (from_e_step, moments) =
            expectation(&parameters, &samples, &mut responsibilities, Spread::Pool);
        assert_eq!(from_e_step, ours);
        let mass: f64 = moments.masses.iter().sum();
        assert!((mass - rows.len() as f64).abs() < 1e-9);
    }

    #[test]
    fn one_hot_labels_give_cluster_statistics() {
        let rows = points(300);
        let samples = Samples::from_rows(&rows).expect("well-formed data");
        let labels: Vec<usize> = rows.iter().map(|row| usize::from(row[0] > 0.0)).collect();
        let parameters =
            from_labels(&samples, &labels, 2, 0.0, Spread::InPlace).expect("well-spread clusters");
        for component in 0..2 {
            let members: Vec<&Vec<f64>> = rows
                .iter()
                .zip(&labels)
                .filter(|(_, label)| **label == component)
                .map(|(row, _)| row)
                .collect();
            let count = members.len() as f64;
            let weight = parameters.weights[component];
            assert!((weight - count / rows.len() as f64).abs() < 1e-12);
            for axis in 0..3 {
                let mean = members.iter().map(|row| row[axis]).sum::<f64>() / count;
                assert!((parameters.means[component * 3 + axis] - mean).abs() < 1e-12);
                let variance =
                    members.iter().map(|row| (row[axis] - mean).powi(2)).sum::<f64>() / count;
                let fitted = parameters.covariances[component * 9 + axis * 4];
                assert!((fitted - variance).abs() < 1e-12, "{fitted} vs {variance}");
            }
        }
    }
}
