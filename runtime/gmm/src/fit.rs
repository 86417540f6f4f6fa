//! Fitting: k-means initialisation, EM with restarts, and the choice of the component count by BIC.
//!
//! Every (component count, restart) run is independent and draws from its own ChaCha stream, so the runs
//! go to the rayon pool and the result does not depend on the number of threads.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::data::Samples;
use crate::em::{self, EmSettings};
use crate::error::GmmError;
use crate::kmeans;
use crate::mixture::GaussianMixture;
use crate::parallel::Spread;
use crate::parameters::Parameters;

/// How a mixture is fitted. The defaults are scikit-learn's, with a cap of four components.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitConfig {
    /// Largest component count tried; BIC chooses among `1..=max_components`.
    pub max_components: usize,
    /// Upper bound on EM iterations per run (scikit-learn `max_iter`).
    pub max_iterations: usize,
    /// EM stops when the mean log-likelihood per point changes by less than this (scikit-learn `tol`).
    pub tolerance: f64,
    /// Added to every covariance diagonal so that covariances stay positive definite (scikit-learn
    /// `reg_covar`), in squared feature units.
    pub regularisation: f64,
    /// EM runs from different k-means initialisations per component count; the best final log-likelihood
    /// wins (scikit-learn `n_init`).
    pub restarts: usize,
}

impl Default for FitConfig {
    fn default() -> Self {
        Self {
            max_components: 4,
            max_iterations: 100,
            tolerance: 1e-3,
            regularisation: 1e-6,
            restarts: 1,
        }
    }
}

impl FitConfig {
    fn validate(&self) -> Result<(), GmmError> {
        let invalid = |reason: &str| Err(GmmError::InvalidConfig { reason: reason.to_owned() });
        if self.max_components == 0 {
            return invalid("max_components must be at least 1");
        }
        if self.max_iterations == 0 {
            return invalid("max_iterations must be at least 1");
        }
        if self.restarts == 0 {
            return invalid("restarts must be at least 1");
        }
        if !(self.tolerance.is_finite() && self.tolerance >= 0.0) {
            return invalid("tolerance must be finite and non-negative");
        }
        if !(self.regularisation.is_finite() && self.regularisation >= 0.0) {
            return invalid("regularisation must be finite and non-negative");
        }
        Ok(())
    }

    fn em_settings(&self, spread: Spread) -> EmSettings {
        EmSettings {
            max_iterations: self.max_iterations,
            tolerance: self.tolerance,
            regularisation: self.regularisation,
            spread,
        }
    }
}

/// How one component count fared in the model selection.
#[derive(Debug, Clone, PartialEq)]
pub struct CandidateScore {
    /// Component count `k`.
    pub components: usize,
    /// Mean log-likelihood per point of the best restart.
    pub mean_log_likelihood: f64,
    /// Bayesian information criterion `−2·N·mean_log_likelihood + p·ln N`, with
    /// `p = k·d + k·d(d+1)/2 + k − 1` free parameters; lower is better.
    pub bic: f64,
    /// EM iterations of the best restart.
    pub iterations: usize,
    /// Whether the best restart converged within `max_iterations`.
    pub converged: bool,
}

/// A fitted mixture and the scores of every candidate component count, in increasing `k`.
#[derive(Debug, Clone, PartialEq)]
pub struct FitReport {
    /// The candidate with the lowest BIC (the smaller `k` on a tie).
    pub mixture: GaussianMixture,
    /// One entry per component count tried.
    pub candidates: Vec<CandidateScore>,
}

/// Fits a mixture to `data` (one `Vec` per point, all of the same length) and chooses the component count by
/// BIC; see [`fit_with_report`].
pub fn fit(
    data: &[Vec<f64>],
    config: &FitConfig,
    rng: &mut ChaCha8Rng,
) -> Result<GaussianMixture, GmmError> {
    Ok(fit_with_report(data, config, rng)?.mixture)
}

/// [`fit`] for a row-major matrix of `dimension` columns.
pub fn fit_row_major(
    values: &[f64],
    dimension: usize,
    config: &FitConfig,
    rng: &mut ChaCha8Rng,
) -> Result<GaussianMixture, GmmError> {
    let samples = Samples::from_row_major(values.to_vec(), dimension)?;
    Ok(select(&samples, config, rng)?.mixture)
}

/// Fits a mixture for every component count `k = 1..=max_components` that does not exceed the number of
/// distinct points, and returns the one with the lowest BIC together with all scores.
///
/// For each `k` and each restart: k-means++ seeding and Lloyd iterations give hard assignments, whose
/// maximum-likelihood parameters start EM (scikit-learn `init_params="kmeans"`).
///
/// All randomness comes from `rng`, so a seed fixes the result: the fit draws one 32-byte key from `rng`
/// (32 bytes of its output, whatever the data and configuration), and the run for component count `k` and
/// restart `r` (from 0) uses `ChaCha8Rng::from_seed(key)` on stream `k · 2³² + r`.
/// The runs are independent, so they run in parallel on the rayon pool with the same result as in sequence.
pub fn fit_with_report(
    data: &[Vec<f64>],
    config: &FitConfig,
    rng: &mut ChaCha8Rng,
) -> Result<FitReport, GmmError> {
    let samples = Samples::from_rows(data)?;
    select(&samples, config, rng)
}

/// Runs EM on `data` starting from the parameters of `initial` (same component count and dimension), without
/// any model selection; `config.max_components` and `config.restarts` are not used.
pub fn fit_from(
    initial: &GaussianMixture,
    data: &[Vec<f64>],
    config: &FitConfig,
) -> Result<GaussianMixture, GmmError> {
    config.validate()?;
    let samples = Samples::from_rows(data)?;
    if samples.dimension() != initial.dimension() {
        return Err(GmmError::ShapeMismatch {
            what: "data points".to_owned(),
            expected: initial.dimension(),
            found: samples.dimension(),
        });
    }
    let initial = Parameters::from_mixture(initial);
    let run = rayon::scope(|_| em::run(initial, &samples, config.em_settings(Spread::Pool)))?;
    Ok(run.parameters.into_mixture())
}

/// The stream of the run for `components` and `restart`; see [`fit_with_report`].
fn run_stream(key: [u8; 32], components: usize, restart: usize) -> ChaCha8Rng {
    let mut stream = ChaCha8Rng::from_seed(key);
    stream.set_stream(((components as u64) << 32) | restart as u64);
    stream
}

/// One k-means initialisation and EM run; returns the mean log-likelihood of the fitted parameters with the
/// run.
fn fit_once(
    samples: &Samples,
    config: &FitConfig,
    components: usize,
    mut rng: ChaCha8Rng,
    spread: Spread,
) -> Result<(f64, em::EmRun), GmmError> {
    let labels = kmeans::cluster(samples, components, &mut rng, spread);
    let initial = em::from_labels(samples, &labels, components, config.regularisation, spread)?;
    let run = em::run(initial, samples, config.em_settings(spread))?;
    Ok((em::mean_log_likelihood(&run.parameters, samples, spread), run))
}

fn select(
    samples: &Samples,
    config: &FitConfig,
    rng: &mut ChaCha8Rng,
) -> Result<FitReport, GmmError> {
    config.validate()?;
    let mut key = [0_u8; 32];
    rng.fill_bytes(&mut key);
    let largest = samples.distinct_count_up_to(config.max_components);
    // Largest k (and restart) first: those runs take longest, so the pool starts them early.
    let runs: Vec<(usize, usize)> = (1..=largest)
        .rev()
        .flat_map(|components| (0..config.restarts).rev().map(move |restart| (components, restart)))
        .collect();
    // With a run per thread, runs are the parallel unit: a run's passes over the data then need no
    // synchronisation. Fewer runs than threads also spread each pass's blocks.
    let spread =
        if runs.len() < rayon::current_num_threads() { Spread::Pool } else { Spread::InPlace };
    let mut outcomes: Vec<Result<(f64, em::EmRun), GmmError>> = runs
        .par_iter()
        .map(|&(components, restart)| {
            let stream = run_stream(key, components, restart);
            fit_once(samples, config, components, stream, spread)
        })
        .collect();
    // Back to increasing k, restarts in order, so that errors and ties resolve as in a sequential loop.
    outcomes.reverse();
    let mut outcomes = outcomes.into_iter();
    let point_count = samples.count() as f64;
    let dimension = samples.dimension() as f64;
    let mut candidates = Vec::with_capacity(largest);
    let mut best: Option<(f64, Parameters)> = None;
    for components in 1..=largest {
        let mut best_run: Option<(f64, em::EmRun)> = None;
        for outcome in outcomes.by_ref().take(config.restarts) {
            let (score, run) = outcome?;
            if best_run.as_ref().is_none_or(|(best_score, _)| score > *best_score) {
                best_run = Some((score, run));
            }
        }
        let Some((mean_log_likelihood, run)) = best_run else { continue };
        let k = components as f64;
        let parameters = k * dimension + k * dimension * (dimension + 1.0) / 2.0 + k - 1.0;
        let bic = -2.0 * point_count * mean_log_likelihood + parameters * point_count.ln();
        candidates.push(CandidateScore {
            components,
            mean_log_likelihood,
            bic,
            iterations: run.iterations,
            converged: run.converged,
        });
        if best.as_ref().is_none_or(|(best_bic, _)| bic < *best_bic) {
            best = Some((bic, run.parameters));
        }
    }
    let (_, parameters) = best.expect("at least one distinct point, so k = 1 is always tried");
    Ok(FitReport { mixture: parameters.into_mixture(), candidates })
}
