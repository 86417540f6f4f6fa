//! Validated data sets: the sample matrix that fitting and calibration work on, row-major for per-point work
//! and in column blocks for the vectorised EM and k-means loops.

use crate::error::GmmError;

/// Points per block of the column-blocked layout. Every reduction over points sums within a block first and
/// then over blocks in order, so results do not depend on how blocks are spread over threads; 256 points of
/// up to 9 coordinates plus the per-block scratch stay in the L1 cache.
pub(crate) const BLOCK: usize = 256;

/// `count` points of `dimension` finite coordinates.
///
/// Stored twice: row-major, and as consecutive blocks of [`BLOCK`] points (the last one shorter) in which
/// coordinate `i` of the block's points is contiguous, so that loops over points vectorise.
#[derive(Debug, Clone)]
pub(crate) struct Samples {
    values: Vec<f64>,
    dimension: usize,
    blocked: Vec<f64>,
}

impl Samples {
    /// Checks that there is at least one point, that all points have the same non-zero length and that every
    /// coordinate is finite.
    pub(crate) fn from_rows(rows: &[Vec<f64>]) -> Result<Self, GmmError> {
        let dimension = rows.first().ok_or(GmmError::NoData)?.len();
        let mut values = Vec::with_capacity(rows.len() * dimension);
        for (index, row) in rows.iter().enumerate() {
            if row.len() != dimension {
                return Err(GmmError::ShapeMismatch {
                    what: format!("data point {index}"),
                    expected: dimension,
                    found: row.len(),
                });
            }
            values.extend_from_slice(row);
        }
        Self::from_row_major(values, dimension)
    }

    /// Checks a row-major matrix of `dimension` columns.
    pub(crate) fn from_row_major(values: Vec<f64>, dimension: usize) -> Result<Self, GmmError> {
        if dimension == 0 {
            return Err(GmmError::ZeroDimension);
        }
        if values.is_empty() {
            return Err(GmmError::NoData);
        }
        if !values.len().is_multiple_of(dimension) {
            return Err(GmmError::ShapeMismatch {
                what: "row-major data".to_owned(),
                expected: values.len().div_ceil(dimension) * dimension,
                found: values.len(),
            });
        }
        if let Some(index) = values.iter().position(|value| !value.is_finite()) {
            return Err(GmmError::NotFinite { what: format!("data point {}", index / dimension) });
        }
        let count = values.len() / dimension;
        let mut blocked = Vec::with_capacity(values.len());
        for start in (0..count).step_by(BLOCK) {
            let end = (start + BLOCK).min(count);
            for axis in 0..dimension {
                blocked.extend((start..end).map(|point| values[point * dimension + axis]));
            }
        }
        Ok(Self { values, dimension, blocked })
    }

    pub(crate) fn dimension(&self) -> usize {
        self.dimension
    }

    pub(crate) fn count(&self) -> usize {
        self.values.len() / self.dimension
    }

    pub(crate) fn row(&self, index: usize) -> &[f64] {
        &self.values[index * self.dimension..(index + 1) * self.dimension]
    }

    pub(crate) fn rows(&self) -> impl Iterator<Item = &[f64]> {
        self.values.chunks_exact(self.dimension)
    }

    /// Number of blocks of the column-blocked layout.
    pub(crate) fn block_count(&self) -> usize {
        self.count().div_ceil(BLOCK)
    }

    /// Points in block `block`: [`BLOCK`], except for a shorter last block.
    pub(crate) fn block_len(&self, block: usize) -> usize {
        BLOCK.min(self.count() - block * BLOCK)
    }

    /// Block `block`, coordinate-major: coordinate `i` of its `n` points is `[i·n, (i+1)·n)`.
    pub(crate) fn block(&self, block: usize) -> &[f64] {
        let start = block * BLOCK * self.dimension;
        &self.blocked[start..start + self.block_len(block) * self.dimension]
    }

    /// Number of distinct points (identical bit patterns in every coordinate), counted up to `limit`: model
    /// selection only needs to know whether there are at least as many distinct points as components.
    pub(crate) fn distinct_count_up_to(&self, limit: usize) -> usize {
        let same = |left: &[f64], right: &[f64]| {
            left.iter().zip(right).all(|(a, b)| a.to_bits() == b.to_bits())
        };
        let mut distinct: Vec<&[f64]> = Vec::with_capacity(limit.min(self.count()));
        for row in self.rows() {
            if distinct.len() >= limit {
                break;
            }
            if !distinct.iter().any(|seen| same(seen, row)) {
                distinct.push(row);
            }
        }
        distinct.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_malformed_data() {
        assert_eq!(Samples::from_rows(&[]).err(), Some(GmmError::NoData));
        assert_eq!(Samples::from_rows(&[vec![]]).err(), Some(GmmError::ZeroDimension));
        assert!(matches!(
            Samples::from_rows(&[vec![1.0, 2.0], vec![1.0]]),
            Err(GmmError::ShapeMismatch { expected: 2, found: 1, .. })
        ));
        assert!(matches!(
            Samples::from_rows(&[vec![1.0, f64::NAN]]),
            Err(GmmError::NotFinite { .. })
        ));
        assert!(matches!(
            Samples::from_row_major(vec![1.0, 2.0, 3.0], 2),
            Err(GmmError::ShapeMismatch { .. })
        ));
    }

    #[test]
    fn counts_distinct_points() {
        let samples = Samples::from_rows(&[
            vec![1.0, 2.0],
            vec![0.0, 5.0],
            vec![1.0, 2.0],
            vec![1.0, 3.0],
            vec![0.0, 5.0],
        ])
        .expect("well-formed data");
        assert_eq!(samples.count(), 5);
        assert_eq!(samples.distinct_count_up_to(10), 3);
        assert_eq!(samples.distinct_count_up_to(2), 2);
        assert_eq!(samples.row(3), &[1.0, 3.0]);
    }

    #[test]
    fn blocks_hold_the_columns_of_consecutive_points() {
        let rows: Vec<Vec<f64>> =
            (0..BLOCK + 3).map(|index| vec![index as f64, -(index as f64)]).collect();
        let samples = Samples::from_rows(&rows).expect("well-formed data");
        assert_eq!(samples.block_count(), 2);
        assert_eq!(samples.block_len(1), 3);
        let last = samples.block(1);
        assert_eq!(last.len(), 6);
        assert_eq!(&last[..3], &[BLOCK as f64, BLOCK as f64 + 1.0, BLOCK as f64 + 2.0]);
        assert_eq!(last[3], -(BLOCK as f64));
        assert_eq!(samples.block(0)[BLOCK + 1], -1.0);
    }
}
