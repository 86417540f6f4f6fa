//! Membership thresholds: the log-density level ε above which a given fraction of a region's own points lie.

use crate::data::Samples;
use crate::error::GmmError;
use crate::mixture::GaussianMixture;

/// Slack on `cover · n` before rounding up, so that a cover such as 0.9 on 10 points asks for 9 points and not,
/// through round-off in 0.9 · 10, for 10.
const COUNT_ROUNDING_SLACK: f64 = 1e-9;

/// The threshold ε such that at least a fraction `cover` of `inside_points` satisfy `log_density(x) ≥ ε`.
///
/// Rule: with the n log densities sorted in decreasing order, ε is the m-th largest, where
/// m = ⌈cover · n⌉ (at least 1); so `cover = 1` gives the smallest log density of the points, and ties make the
/// covered fraction larger than asked, never smaller.
/// Errors when there are no points, a point has the wrong dimension or a non-finite coordinate, or `cover` is not
/// in (0, 1].
pub fn calibrate_threshold(
    mixture: &GaussianMixture,
    inside_points: &[Vec<f64>],
    cover: f64,
) -> Result<f64, GmmError> {
    if !(cover > 0.0 && cover <= 1.0) {
        return Err(GmmError::InvalidCover { cover });
    }
    let samples = Samples::from_rows(inside_points)?;
    if samples.dimension() != mixture.dimension() {
        return Err(GmmError::ShapeMismatch {
            what: "inside points".to_owned(),
            expected: mixture.dimension(),
            found: samples.dimension(),
        });
    }
    let mut densities: Vec<f64> = samples.rows().map(|row| mixture.log_density(row)).collect();
    densities.sort_by(|left, right| right.total_cmp(left));
    let count = densities.len();
    let required = ((cover * count as f64 - COUNT_ROUNDING_SLACK).ceil() as usize).clamp(1, count);
    Ok(densities[required - 1])
}
