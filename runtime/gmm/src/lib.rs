//! Gaussian mixtures: EM fitting with BIC model selection, log-likelihood and sampling.
//!
//! Each learned region is modelled by a [`GaussianMixture`] over a small feature vector.
//! The learner fits one with [`fit`]; the runtime draws from it with [`GaussianMixture::sample`] and tests
//! membership with [`GaussianMixture::contains`] against a threshold from [`calibrate_threshold`].

mod data;
mod em;
mod error;
mod fit;
mod kernels;
mod kmeans;
mod linalg;
mod mixture;
mod parallel;
mod parameters;
mod threshold;

pub use error::GmmError;
pub use fit::{
    CandidateScore, FitConfig, FitReport, fit, fit_from, fit_row_major, fit_with_report,
};
pub use mixture::{GaussianMixture, MixtureParameters, SYMMETRY_TOLERANCE, WEIGHT_SUM_TOLERANCE};
pub use threshold::calibrate_threshold;
