//! k-means clustering (k-means++ seeding, then Lloyd iterations) used to initialise EM, as scikit-learn's
//! `init_params="kmeans"` does.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::data::Samples;

/// Upper bound on Lloyd iterations; they stop earlier as soon as no assignment changes.
const LLOYD_MAX_ITERATIONS: usize = 100;

/// Cluster labels in `0..clusters` for every point.
///
/// `clusters` must be at least one and at most the number of points.
pub(crate) fn cluster(samples: &Samples, clusters: usize, rng: &mut ChaCha8Rng) -> Vec<usize> {
    let mut centres = seed_plus_plus(samples, clusters, rng);
    let mut labels = vec![usize::MAX; samples.count()];
    for _ in 0..LLOYD_MAX_ITERATIONS {
        let changed = assign(samples, &centres, &mut labels);
        if !changed {
            break;
        }
        centres = recompute_centres(samples, &mut labels, clusters);
    }
    labels
}

fn squared_distance(left: &[f64], right: &[f64]) -> f64 {
    left.iter().zip(right).map(|(a, b)| (a - b) * (a - b)).sum()
}

/// Greedy k-means++ (Arthur and Vassilvitskii; scikit-learn's variant): each new centre is the best of
/// `2 + ln k` candidates drawn proportionally to the squared distance to the nearest existing centre.
fn seed_plus_plus(samples: &Samples, clusters: usize, rng: &mut ChaCha8Rng) -> Vec<Vec<f64>> {
    let count = samples.count();
    let trials = 2 + (clusters as f64).ln().floor() as usize;
    let first = rng.random_range(0..count);
    let mut centres = vec![samples.row(first).to_vec()];
    let mut closest: Vec<f64> =
        samples.rows().map(|row| squared_distance(row, samples.row(first))).collect();
    while centres.len() < clusters {
        let total: f64 = closest.iter().sum();
        let mut best: Option<(f64, usize, Vec<f64>)> = None;
        for _ in 0..trials {
            let candidate = if total > 0.0 {
                draw_proportional(&closest, total * rng.random::<f64>())
            } else {
                // Every point coincides with a centre: any point is as good as another.
                rng.random_range(0..count)
            };
            let updated: Vec<f64> = samples
                .rows()
                .zip(&closest)
                .map(|(row, &old)| old.min(squared_distance(row, samples.row(candidate))))
                .collect();
            let potential: f64 = updated.iter().sum();
            if best.as_ref().is_none_or(|(best_potential, _, _)| potential < *best_potential) {
                best = Some((potential, candidate, updated));
            }
        }
        let Some((_, candidate, updated)) = best else { break };
        centres.push(samples.row(candidate).to_vec());
        closest = updated;
    }
    centres
}

/// The first index whose running sum of `weights` exceeds `target`.
fn draw_proportional(weights: &[f64], target: f64) -> usize {
    let mut running = 0.0;
    for (index, weight) in weights.iter().enumerate() {
        running += weight;
        if running > target {
            return index;
        }
    }
    // Round-off can leave the target just above the total: take the last point with positive weight.
    weights.iter().rposition(|&weight| weight > 0.0).unwrap_or(0)
}

/// Assigns every point to its nearest centre (lowest index on ties); whether any label changed.
fn assign(samples: &Samples, centres: &[Vec<f64>], labels: &mut [usize]) -> bool {
    let mut changed = false;
    for (row, label) in samples.rows().zip(labels.iter_mut()) {
        let mut nearest = 0;
        let mut nearest_distance = f64::INFINITY;
        for (index, centre) in centres.iter().enumerate() {
            let distance = squared_distance(row, centre);
            if distance < nearest_distance {
                nearest = index;
                nearest_distance = distance;
            }
        }
        if *label != nearest {
            *label = nearest;
            changed = true;
        }
    }
    changed
}

/// Cluster means; an emptied cluster is moved onto the point farthest from its own centre, as scikit-learn
/// relocates empty clusters, so that no EM component starts without data.
fn recompute_centres(samples: &Samples, labels: &mut [usize], clusters: usize) -> Vec<Vec<f64>> {
    let dimension = samples.dimension();
    let mut sums = vec![vec![0.0; dimension]; clusters];
    let mut sizes = vec![0_usize; clusters];
    for (row, &label) in samples.rows().zip(labels.iter()) {
        sizes[label] += 1;
        for (sum, value) in sums[label].iter_mut().zip(row) {
            *sum += value;
        }
    }
    let mut centres: Vec<Vec<f64>> = sums
        .into_iter()
        .zip(&sizes)
        .map(|(sum, &size)| sum.into_iter().map(|value| value / size.max(1) as f64).collect())
        .collect();
    for empty in 0..clusters {
        if sizes[empty] != 0 {
            continue;
        }
        let farthest = samples
            .rows()
            .zip(labels.iter())
            .enumerate()
            .filter(|(_, (_, label))| sizes[**label] > 1)
            .map(|(index, (row, label))| (index, squared_distance(row, &centres[*label])))
            .max_by(|left, right| left.1.total_cmp(&right.1));
        if let Some((index, _)) = farthest {
            sizes[labels[index]] -= 1;
            sizes[empty] = 1;
            labels[index] = empty;
            centres[empty] = samples.row(index).to_vec();
        }
    }
    centres
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn separates_two_blobs() {
        let mut rows = Vec::new();
        for index in 0..20 {
            let offset = f64::from(index) * 0.01;
            rows.push(vec![offset, -offset]);
            rows.push(vec![10.0 + offset, 10.0 - offset]);
        }
        let samples = Samples::from_rows(&rows).expect("well-formed data");
        let labels = cluster(&samples, 2, &mut ChaCha8Rng::seed_from_u64(7));
        for pair in labels.chunks_exact(2) {
            assert_ne!(pair[0], pair[1]);
        }
        assert!(labels.iter().step_by(2).all(|&label| label == labels[0]));
    }

    #[test]
    fn identical_points_do_not_break_seeding() {
        let samples = Samples::from_rows(&vec![vec![1.0, 1.0]; 5]).expect("well-formed data");
        let labels = cluster(&samples, 2, &mut ChaCha8Rng::seed_from_u64(1));
        assert_eq!(labels.len(), 5);
        assert!(labels.iter().all(|&label| label < 2));
    }
}
