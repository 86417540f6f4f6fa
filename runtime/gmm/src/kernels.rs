//! The loops of EM over one block of points (coordinate-major, see [`crate::data::Samples`]): log terms,
//! normalised responsibilities, moments and the weighted scatter. Each runs over points in its inner loop, so
//! it vectorises, and sums in an order fixed by the code.

use crate::linalg::exp_of_non_positive;
use crate::parallel::{dots, sum};
use crate::parameters::Parameters;

/// Points handled together by the Mahalanobis kernel: their partial results stay in registers while the
/// coefficients of `L⁻¹` are streamed once per tile.
const TILE: usize = 8;

/// Writes ln(w_k N(x; μ_k, Σ_k)) for the `len` points of `block` into `out`.
///
/// `differences` holds `d` rows of `stride ≥ len` entries (a whole number of tiles); the padding is zero, so
/// whole tiles can be computed and only the first `len` results kept.
pub(crate) fn log_terms(
    parameters: &Parameters,
    component: usize,
    block: &[f64],
    len: usize,
    differences: &mut [f64],
    out: &mut [f64],
) {
    let dimension = parameters.dimension;
    let stride = differences.len() / dimension;
    let mean = &parameters.means[component * dimension..(component + 1) * dimension];
    let inverse = &parameters.inverse_factors
        [component * dimension * dimension..(component + 1) * dimension * dimension];
    for (axis, &centre) in mean.iter().enumerate() {
        let target = &mut differences[axis * stride..axis * stride + len];
        for (difference, value) in target.iter_mut().zip(&block[axis * len..(axis + 1) * len]) {
            *difference = value - centre;
        }
    }
    let log_normaliser = parameters.log_normalisers[component];
    for (tile, outputs) in out[..len].chunks_mut(TILE).enumerate() {
        let start = tile * TILE;
        let mut squared = [0.0; TILE];
        for row in 0..dimension {
            let mut projected = [0.0; TILE];
            for (axis, &coefficient) in
                inverse[row * dimension..=row * (dimension + 1)].iter().enumerate()
            {
                let differences = &differences[axis * stride + start..axis * stride + start + TILE];
                for lane in 0..TILE {
                    projected[lane] += coefficient * differences[lane];
                }
            }
            for lane in 0..TILE {
                squared[lane] += projected[lane] * projected[lane];
            }
        }
        for (output, distance) in outputs.iter_mut().zip(squared) {
            *output = log_normaliser - 0.5 * distance;
        }
    }
}

/// Scratch for the differences of one block: zero padding up to whole tiles.
pub(crate) fn difference_buffer(dimension: usize, len: usize) -> Vec<f64> {
    vec![0.0; dimension * len.div_ceil(TILE) * TILE]
}

/// Replaces the log terms of one block (component-major, `k × len`) by normalised responsibilities and returns
/// the sum of the points' log densities.
///
/// ln p(x) = m + ln Σ_k exp(t_k − m) with m the largest term; the responsibilities are exp(t_k − m) divided by
/// that sum, which needs one exponential per term. Each step is a loop over points, so that it vectorises.
pub(crate) fn normalise(terms: &mut [f64], components: usize, len: usize) -> f64 {
    if components == 1 {
        let total = terms[..len].iter().sum();
        terms[..len].fill(1.0);
        return total;
    }
    let mut largest = terms[..len].to_vec();
    for column in terms[len..components * len].chunks_exact(len) {
        for (maximum, &term) in largest.iter_mut().zip(column) {
            *maximum = maximum.max(term);
        }
    }
    let mut scale = vec![0.0; len];
    for column in terms[..components * len].chunks_exact_mut(len) {
        for ((term, sum), &maximum) in column.iter_mut().zip(&mut scale).zip(&largest) {
            *term = exp_of_non_positive(*term - maximum);
            *sum += *term;
        }
    }
    // One division per point rather than per term; the extra rounding is one unit in the last place.
    let inverse_scale: Vec<f64> = scale.iter().map(|sum| 1.0 / sum).collect();
    for column in terms[..components * len].chunks_exact_mut(len) {
        for (term, inverse) in column.iter_mut().zip(&inverse_scale) {
            *term *= inverse;
        }
    }
    let mut total = 0.0;
    for (point, (&maximum, sum)) in largest.iter().zip(&scale).enumerate() {
        if maximum.is_finite() {
            total += maximum + sum.ln();
        } else {
            // Every component's density underflowed the exponent range: share the point equally.
            for component in 0..components {
                terms[component * len + point] = 1.0 / components as f64;
            }
            total += maximum;
        }
    }
    total
}

/// Appends each component's responsibility mass and responsibility-weighted coordinate sums for one block.
pub(crate) fn block_moments(
    block: &[f64],
    responsibilities: &[f64],
    components: usize,
    len: usize,
    out: &mut Vec<f64>,
) {
    for component in 0..components {
        out.push(sum(&responsibilities[component * len..(component + 1) * len]));
    }
    let columns: Vec<&[f64]> = block.chunks_exact(len).collect();
    for component in 0..components {
        dots(&responsibilities[component * len..(component + 1) * len], &columns, out);
    }
}

/// Appends, for every component, the lower triangle (row by row) of Σ_n r_n (x_n − μ)(x_n − μ)ᵀ over one block.
pub(crate) fn block_scatter(
    block: &[f64],
    responsibilities: &[f64],
    means: &[f64],
    len: usize,
    out: &mut Vec<f64>,
) {
    let dimension = block.len() / len;
    let mut differences = vec![0.0; dimension * len];
    let mut weighted = vec![0.0; dimension * len];
    for (component, mean) in means.chunks_exact(dimension).enumerate() {
        let weights = &responsibilities[component * len..(component + 1) * len];
        for (axis, &centre) in mean.iter().enumerate() {
            let range = axis * len..(axis + 1) * len;
            for (((difference, scaled), value), weight) in differences[range.clone()]
                .iter_mut()
                .zip(&mut weighted[range.clone()])
                .zip(&block[range])
                .zip(weights)
            {
                *difference = value - centre;
                *scaled = weight * *difference;
            }
        }
        let columns: Vec<&[f64]> = differences.chunks_exact(len).collect();
        for first in 0..dimension {
            dots(&weighted[first * len..(first + 1) * len], &columns[..=first], out);
        }
    }
}
