//! Validated data sets: the row-major sample matrix that fitting and calibration work on.

use crate::error::GmmError;

/// `count` points of `dimension` finite coordinates, stored row-major.
#[derive(Debug, Clone)]
pub(crate) struct Samples {
    values: Vec<f64>,
    dimension: usize,
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
        Ok(Self { values, dimension })
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

    /// Number of distinct points (exact equality of all coordinates).
    pub(crate) fn distinct_count(&self) -> usize {
        let mut rows: Vec<&[f64]> = self.rows().collect();
        rows.sort_by(|left, right| {
            left.iter()
                .zip(right.iter())
                .map(|(a, b)| a.total_cmp(b))
                .find(|ordering| ordering.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        rows.dedup();
        rows.len()
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
        assert_eq!(samples.distinct_count(), 3);
        assert_eq!(samples.row(3), &[1.0, 3.0]);
    }
}
