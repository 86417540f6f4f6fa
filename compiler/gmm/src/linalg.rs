//! Small dense linear algebra on row-major slices: Cholesky factors, triangular solves and log-sum-exp.
//!
//! Mixture dimensions are small (3 to 9), so flat `Vec<f64>` storage with hand-written loops is faster in the
//! EM inner loop than allocating nalgebra matrices per sample; nalgebra is used only to factorise.

use nalgebra::DMatrix;

/// ln(2π), the constant in every Gaussian log-normaliser.
pub(crate) const LN_2PI: f64 = 1.837_877_066_409_345_5;

/// The lower Cholesky factor `L` (row-major, `L·Lᵀ = covariance`) of a symmetric matrix, or `None` if the
/// matrix is not positive definite.
pub(crate) fn cholesky_lower(covariance: &[f64], dimension: usize) -> Option<Vec<f64>> {
    let matrix = DMatrix::from_row_slice(dimension, dimension, covariance);
    let factor = nalgebra::Cholesky::new(matrix)?.l();
    let mut lower = vec![0.0; dimension * dimension];
    for row in 0..dimension {
        for column in 0..=row {
            lower[row * dimension + column] = factor[(row, column)];
        }
    }
    // nalgebra accepts tiny or subnormal pivots; a factor that cannot be inverted in floating point is not usable.
    let usable = (0..dimension).all(|index| {
        let pivot = lower[index * dimension + index];
        pivot.is_finite() && pivot > f64::MIN_POSITIVE
    });
    usable.then_some(lower)
}

/// ln det(L·Lᵀ) = 2 Σ ln L_ii.
pub(crate) fn log_determinant(lower: &[f64], dimension: usize) -> f64 {
    2.0 * (0..dimension).map(|index| lower[index * dimension + index].ln()).sum::<f64>()
}

/// The squared Mahalanobis norm `|L⁻¹ (x − μ)|²`, by forward substitution into `scratch`.
pub(crate) fn mahalanobis_squared(
    lower: &[f64],
    mean: &[f64],
    point: &[f64],
    scratch: &mut [f64],
) -> f64 {
    let dimension = mean.len();
    let mut total = 0.0;
    for row in 0..dimension {
        let base = row * dimension;
        let mut value = point[row] - mean[row];
        for column in 0..row {
            value -= lower[base + column] * scratch[column];
        }
        value /= lower[base + row];
        scratch[row] = value;
        total += value * value;
    }
    total
}

/// ln Σ exp(values), stable for large magnitudes; −∞ for an empty slice or all −∞.
pub(crate) fn log_sum_exp(values: &[f64]) -> f64 {
    let maximum = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if maximum == f64::NEG_INFINITY || maximum.is_nan() {
        return maximum;
    }
    if maximum == f64::INFINITY {
        return f64::INFINITY;
    }
    maximum + values.iter().map(|value| (value - maximum).exp()).sum::<f64>().ln()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_reproduces_the_matrix() {
        let covariance = [4.0, 2.0, 0.6, 2.0, 2.0, 0.5, 0.6, 0.5, 3.0];
        let lower = cholesky_lower(&covariance, 3).expect("matrix is positive definite");
        for row in 0..3 {
            for column in 0..3 {
                let product: f64 = (0..3).map(|k| lower[row * 3 + k] * lower[column * 3 + k]).sum();
                assert!((product - covariance[row * 3 + column]).abs() < 1e-12);
            }
        }
        assert!(cholesky_lower(&[1.0, 2.0, 2.0, 1.0], 2).is_none());
        assert!(cholesky_lower(&[0.0, 0.0, 0.0, 1.0], 2).is_none());
    }

    #[test]
    fn mahalanobis_of_a_diagonal_covariance() {
        let lower =
            cholesky_lower(&[4.0, 0.0, 0.0, 9.0], 2).expect("diagonal is positive definite");
        let mut scratch = [0.0; 2];
        let value = mahalanobis_squared(&lower, &[1.0, 1.0], &[3.0, 4.0], &mut scratch);
        assert!((value - (1.0 + 1.0)).abs() < 1e-12);
        assert!((log_determinant(&lower, 2) - 36.0_f64.ln()).abs() < 1e-12);
    }

    #[test]
    fn log_sum_exp_is_stable() {
        assert!((log_sum_exp(&[1000.0, 1000.0]) - (1000.0 + 2.0_f64.ln())).abs() < 1e-12);
        assert!((log_sum_exp(&[-1000.0, -1000.0]) - (-1000.0 + 2.0_f64.ln())).abs() < 1e-12);
        assert_eq!(log_sum_exp(&[f64::NEG_INFINITY, f64::NEG_INFINITY]), f64::NEG_INFINITY);
        assert!((log_sum_exp(&[f64::NEG_INFINITY, 0.0]) - 0.0).abs() < 1e-15);
    }
}
