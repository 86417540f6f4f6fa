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

/// `L⁻¹` (row-major, lower triangular) of a lower triangular factor with non-zero pivots, so that the
/// Mahalanobis term `|L⁻¹(x − μ)|²` becomes independent dot products instead of a chain of divisions.
pub(crate) fn invert_lower(lower: &[f64], dimension: usize) -> Vec<f64> {
    let mut inverse = vec![0.0; dimension * dimension];
    for column in 0..dimension {
        inverse[column * dimension + column] = 1.0 / lower[column * dimension + column];
        for row in (column + 1)..dimension {
            let mut value = 0.0;
            for middle in column..row {
                value -= lower[row * dimension + middle] * inverse[middle * dimension + column];
            }
            inverse[row * dimension + column] = value / lower[row * dimension + row];
        }
    }
    inverse
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

/// Below this, [`exp_of_non_positive`] returns exp(−708), about 3·10⁻³⁰⁸, instead of a subnormal or zero:
/// it is only used for terms added to a sum that holds 1, where that makes no difference.
const EXP_FLOOR: f64 = -708.0;

/// exp(x) for x ≤ 0, to within about one unit in the last place, written without branches or calls so that
/// loops over it vectorise (libm's `exp` is a call per value). Non-finite or positive input is not expected.
///
/// x = n·ln 2 + r with |r| ≤ ½ ln 2 (Cody–Waite split of ln 2), exp(r) by its Taylor series to r¹², whose
/// truncation error is below 2·10⁻¹⁶ relative, and 2ⁿ built in the exponent bits.
#[inline]
pub(crate) fn exp_of_non_positive(x: f64) -> f64 {
    // 1.5·2⁵²: adding it rounds to an integer, which then sits in the low bits of the sum.
    const ROUNDER: f64 = 6_755_399_441_055_744.0;
    // fdlibm's split of ln 2: the high part ends in eleven zero bits, so n·LN_2_HIGH is exact for |n| < 2¹¹.
    const LN_2_HIGH: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
    const LN_2_LOW: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
    const COEFFICIENTS: [f64; 13] = [
        1.0,
        1.0,
        1.0 / 2.0,
        1.0 / 6.0,
        1.0 / 24.0,
        1.0 / 120.0,
        1.0 / 720.0,
        1.0 / 5_040.0,
        1.0 / 40_320.0,
        1.0 / 362_880.0,
        1.0 / 3_628_800.0,
        1.0 / 39_916_800.0,
        1.0 / 479_001_600.0,
    ];
    let x = x.max(EXP_FLOOR);
    let shifted = x * std::f64::consts::LOG2_E + ROUNDER;
    let n = shifted - ROUNDER;
    let r = (x - n * LN_2_HIGH) - n * LN_2_LOW;
    let mut polynomial = COEFFICIENTS[12];
    for coefficient in COEFFICIENTS[..12].iter().rev() {
        polynomial = polynomial * r + coefficient;
    }
    // The low bits of `shifted` hold n + 0x3_8000_0000_0000 (the mantissa of ROUNDER); 2ⁿ has exponent n + 1023.
    let exponent = shifted.to_bits().wrapping_sub(ROUNDER.to_bits()).wrapping_add(1023) << 52;
    polynomial * f64::from_bits(exponent)
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
    fn inverse_factor_inverts() {
        let covariance = [4.0, 2.0, 0.6, 2.0, 2.0, 0.5, 0.6, 0.5, 3.0];
        let lower = cholesky_lower(&covariance, 3).expect("matrix is positive definite");
        let inverse = invert_lower(&lower, 3);
        for row in 0..3 {
            for column in 0..3 {
                let product: f64 =
                    (0..3).map(|k| inverse[row * 3 + k] * lower[k * 3 + column]).sum();
                let identity = if row == column { 1.0 } else { 0.0 };
                assert!((product - identity).abs() < 1e-12, "({row}, {column}): {product}");
            }
        }
        assert_eq!(inverse[1], 0.0);
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
    fn fast_exponential_matches_libm() {
        let mut worst: f64 = 0.0;
        for step in 0..200_000 {
            let x = -(step as f64) * 0.003_5 - (step % 7) as f64 * 1e-7;
            let expected = x.exp();
            let relative = (exp_of_non_positive(x) - expected).abs() / expected;
            worst = worst.max(relative);
        }
        assert!(worst < 5e-16, "worst relative error {worst:e}");
        assert_eq!(exp_of_non_positive(0.0), 1.0);
        for tiny in [-1e-300, -1e-17, -0.0] {
            assert!((exp_of_non_positive(tiny) - 1.0).abs() <= f64::EPSILON);
        }
        let floor = exp_of_non_positive(-1e4);
        assert!(floor > 0.0 && floor < 1e-307, "{floor:e}");
    }

    #[test]
    fn log_sum_exp_is_stable() {
        assert!((log_sum_exp(&[1000.0, 1000.0]) - (1000.0 + 2.0_f64.ln())).abs() < 1e-12);
        assert!((log_sum_exp(&[-1000.0, -1000.0]) - (-1000.0 + 2.0_f64.ln())).abs() < 1e-12);
        assert_eq!(log_sum_exp(&[f64::NEG_INFINITY, f64::NEG_INFINITY]), f64::NEG_INFINITY);
        assert!((log_sum_exp(&[f64::NEG_INFINITY, 0.0]) - 0.0).abs() < 1e-15);
    }
}
