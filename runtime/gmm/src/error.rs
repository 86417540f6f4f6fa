//! The one error type of lamp-gmm: every way a mixture, a data set or a fit configuration can be invalid.

use miette::Diagnostic;
use thiserror::Error;

/// Why a mixture could not be built, fitted or calibrated.
#[derive(Debug, Clone, PartialEq, Error, Diagnostic)]
pub enum GmmError {
    /// A mixture needs at least one component.
    #[error("a gaussian mixture needs at least one component")]
    #[diagnostic(code(lamp::gmm::no_components))]
    NoComponents,

    /// Feature vectors must have at least one coordinate.
    #[error("a gaussian mixture needs a dimension of at least one")]
    #[diagnostic(code(lamp::gmm::zero_dimension))]
    ZeroDimension,

    /// The weights, means and covariances describe different numbers of components.
    #[error(
        "{weights} weights, {means} means and {covariances} covariances do not describe the same components"
    )]
    #[diagnostic(code(lamp::gmm::component_count_mismatch))]
    ComponentCountMismatch {
        /// Number of weights given.
        weights: usize,
        /// Number of means given.
        means: usize,
        /// Number of covariance matrices given.
        covariances: usize,
    },

    /// A vector or matrix has the wrong number of entries for the mixture's dimension.
    #[error("{what} has {found} entries where {expected} were expected")]
    #[diagnostic(code(lamp::gmm::shape_mismatch))]
    ShapeMismatch {
        /// Which array is malformed, for example `mean of component 2`.
        what: String,
        /// Number of entries the dimension requires.
        expected: usize,
        /// Number of entries present.
        found: usize,
    },

    /// A weight, mean, covariance entry or data coordinate is NaN or infinite.
    #[error("{what} is not a finite number")]
    #[diagnostic(code(lamp::gmm::not_finite))]
    NotFinite {
        /// Which value is not finite.
        what: String,
    },

    /// A weight is negative.
    #[error("weight {index} is negative ({value})")]
    #[diagnostic(code(lamp::gmm::negative_weight))]
    NegativeWeight {
        /// Component index.
        index: usize,
        /// The offending weight.
        value: f64,
    },

    /// The weights do not sum to one.
    #[error("the weights sum to {sum}, not 1")]
    #[diagnostic(
        code(lamp::gmm::weights_not_normalised),
        help("Divide every weight by their sum before building the mixture.")
    )]
    WeightsNotNormalised {
        /// The sum found.
        sum: f64,
    },

    /// A covariance matrix is not symmetric.
    #[error("the covariance of component {component} is not symmetric")]
    #[diagnostic(code(lamp::gmm::covariance_not_symmetric))]
    CovarianceNotSymmetric {
        /// Component index.
        component: usize,
    },

    /// A covariance matrix has no Cholesky factor.
    #[error("the covariance of component {component} is not positive definite")]
    #[diagnostic(
        code(lamp::gmm::covariance_not_positive_definite),
        help("Add a small regularisation to the diagonal of the covariance.")
    )]
    CovarianceNotPositiveDefinite {
        /// Component index.
        component: usize,
    },

    /// There is nothing to fit or calibrate on.
    #[error("no data points were given")]
    #[diagnostic(code(lamp::gmm::no_data))]
    NoData,

    /// A fit configuration value is out of its range.
    #[error("invalid fit configuration: {reason}")]
    #[diagnostic(code(lamp::gmm::invalid_config))]
    InvalidConfig {
        /// Which value is wrong and why.
        reason: String,
    },

    /// The coverage asked of a threshold calibration is not in (0, 1].
    #[error("coverage {cover} is not in (0, 1]")]
    #[diagnostic(code(lamp::gmm::invalid_cover))]
    InvalidCover {
        /// The coverage asked for.
        cover: f64,
    },
}
