//! k-means clustering (k-means++ seeding, then Lloyd iterations) used to initialise EM, as scikit-learn's
//! `init_params="kmeans"` does.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::data::{BLOCK, Samples};
use crate::parallel::{Spread, dots, map_blocks_mut};

/// Upper bound on Lloyd iterations; they stop earlier as soon as no assignment changes or the centres
/// settle.
const LLOYD_MAX_ITERATIONS: usize = 100;

/// Lloyd iterations stop once the centres move, in total squared distance, by at most this fraction of the
/// mean per-coordinate variance of the data (scikit-learn's `KMeans(tol=1e-4)`).
const SHIFT_TOLERANCE: f64 = 1e-4;

/// Cluster labels in `0..clusters` for every point.
///
/// `clusters` must be at least one and at most the number of points.
/// As in scikit-learn's Lloyd loop, iterations stop when no label changes or when the centres moved by at
/// most [`SHIFT_TOLERANCE`] times the mean variance; in the latter case the points are relabelled once more,
/// so that every label names the nearest final centre.
pub(crate) fn cluster(
    samples: &Samples,
    clusters: usize,
    rng: &mut ChaCha8Rng,
    spread: Spread,
) -> Vec<usize> {
    let dimension = samples.dimension();
    let mut centres = seed_plus_plus(samples, clusters, rng);
    let tolerance = SHIFT_TOLERANCE * mean_variance(samples);
    let mut labels = vec![usize::MAX; samples.count()];
    for _ in 0..LLOYD_MAX_ITERATIONS {
        let (changed, sums, sizes) = assign(samples, &centres, clusters, &mut labels, spread);
        if !changed {
            return labels;
        }
        let updated = recompute_centres(samples, &mut labels, sums, sizes, dimension);
        let shift = squared_distance(&updated, &centres);
        centres = updated;
        if shift <= tolerance {
            break;
        }
    }
    assign(samples, &centres, clusters, &mut labels, spread);
    labels
}

fn squared_distance(left: &[f64], right: &[f64]) -> f64 {
    left.iter().zip(right).map(|(a, b)| (a - b) * (a - b)).sum()
}

/// Mean over the coordinates of their (population) variance.
fn mean_variance(samples: &Samples) -> f64 {
    let dimension = samples.dimension();
    let count = samples.count() as f64;
    let mut means = vec![0.0; dimension];
    for row in samples.rows() {
        for (mean, value) in means.iter_mut().zip(row) {
            *mean += value;
        }
    }
    for mean in &mut means {
        *mean /= count;
    }
    let mut total = 0.0;
    for row in samples.rows() {
        total += squared_distance(row, &means);
    }
    total / count / dimension as f64
}

/// Greedy k-means++ (Arthur and Vassilvitskii; scikit-learn's variant): each new centre is the best of
/// `2 + ln k` candidates drawn proportionally to the squared distance to the nearest existing centre.
/// Returns the centres, `clusters × d` row-major.
fn seed_plus_plus(samples: &Samples, clusters: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let count = samples.count();
    let dimension = samples.dimension();
    let trials = 2 + (clusters as f64).ln().floor() as usize;
    let first = rng.random_range(0..count);
    let mut centres = Vec::with_capacity(clusters * dimension);
    centres.extend_from_slice(samples.row(first));
    let mut closest = vec![0.0; count];
    distances_to(samples, samples.row(first), &mut closest);
    let mut distances = vec![0.0; count];
    let mut updated = vec![0.0; count];
    let mut best_updated = vec![0.0; count];
    while centres.len() < clusters * dimension {
        let total: f64 = closest.iter().sum();
        let mut best: Option<(f64, usize)> = None;
        for _ in 0..trials {
            let candidate = if total > 0.0 {
                draw_proportional(&closest, total * rng.random::<f64>())
            } else {
                // Every point coincides with a centre: any point is as good as another.
                rng.random_range(0..count)
            };
            distances_to(samples, samples.row(candidate), &mut distances);
            for ((new, &old), &distance) in updated.iter_mut().zip(&closest).zip(&distances) {
                *new = old.min(distance);
            }
            let potential: f64 = updated.iter().sum();
            if best.is_none_or(|(best_potential, _)| potential < best_potential) {
                best = Some((potential, candidate));
                std::mem::swap(&mut updated, &mut best_updated);
            }
        }
        let Some((_, candidate)) = best else { break };
        centres.extend_from_slice(samples.row(candidate));
        std::mem::swap(&mut closest, &mut best_updated);
    }
    centres
}

/// Squared distances of all points to `centre`, in point order.
fn distances_to(samples: &Samples, centre: &[f64], out: &mut [f64]) {
    for (index, out) in out.chunks_mut(BLOCK).enumerate() {
        let block = samples.block(index);
        let len = out.len();
        out.fill(0.0);
        for (axis, &coordinate) in centre.iter().enumerate() {
            for (distance, value) in out.iter_mut().zip(&block[axis * len..(axis + 1) * len]) {
                let delta = value - coordinate;
                *distance += delta * delta;
            }
        }
    }
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

/// Assigns every point to its nearest centre (lowest index on ties). Returns whether any label changed, and
/// the coordinate sums (`clusters × d`) and sizes of the new clusters.
fn assign(
    samples: &Samples,
    centres: &[f64],
    clusters: usize,
    labels: &mut [usize],
    spread: Spread,
) -> (bool, Vec<f64>, Vec<usize>) {
    let dimension = samples.dimension();
    let partials = map_blocks_mut(spread, labels, BLOCK, |index, labels| {
        let block = samples.block(index);
        let len = labels.len();
        let nearest = nearest_centres(block, len, centres, dimension);
        let mut changed = false;
        for (label, &best) in labels.iter_mut().zip(&nearest) {
            changed |= *label != best;
            *label = best;
        }
        // Sums as dot products with 0/1 membership, which vectorise where a scatter by label would not.
        let columns: Vec<&[f64]> = block.chunks_exact(len).collect();
        let mut membership = vec![0.0; len];
        let mut sums = Vec::with_capacity(clusters * dimension);
        let mut sizes = Vec::with_capacity(clusters);
        for cluster in 0..clusters {
            for (member, &best) in membership.iter_mut().zip(&nearest) {
                *member = if best == cluster { 1.0 } else { 0.0 };
            }
            sizes.push(nearest.iter().filter(|&&best| best == cluster).count());
            dots(&membership, &columns, &mut sums);
        }
        (changed, sums, sizes)
    });
    let mut changed = false;
    let mut sums = vec![0.0; clusters * dimension];
    let mut sizes = vec![0_usize; clusters];
    for (block_changed, block_sums, block_sizes) in partials {
        changed |= block_changed;
        for (total, value) in sums.iter_mut().zip(block_sums) {
            *total += value;
        }
        for (total, value) in sizes.iter_mut().zip(block_sizes) {
            *total += value;
        }
    }
    (changed, sums, sizes)
}

/// Points whose squared distances to the centres are compared together, kept in registers.
const TILE: usize = 8;

/// The nearest centre (lowest index on ties) of each of the `len` points of a block.
fn nearest_centres(block: &[f64], len: usize, centres: &[f64], dimension: usize) -> Vec<usize> {
    let mut nearest = vec![0_usize; len];
    let whole = len / TILE * TILE;
    for start in (0..whole).step_by(TILE) {
        let mut best = [f64::INFINITY; TILE];
        let mut best_index = [0_usize; TILE];
        for (cluster, centre) in centres.chunks_exact(dimension).enumerate() {
            let mut distance = [0.0; TILE];
            for (axis, &coordinate) in centre.iter().enumerate() {
                let values = &block[axis * len + start..axis * len + start + TILE];
                for lane in 0..TILE {
                    let delta = values[lane] - coordinate;
                    distance[lane] += delta * delta;
                }
            }
            for lane in 0..TILE {
                if distance[lane] < best[lane] {
                    best[lane] = distance[lane];
                    best_index[lane] = cluster;
                }
            }
        }
        nearest[start..start + TILE].copy_from_slice(&best_index);
    }
    for (point, label) in nearest.iter_mut().enumerate().skip(whole) {
        let mut best = f64::INFINITY;
        for (cluster, centre) in centres.chunks_exact(dimension).enumerate() {
            let distance: f64 = centre
                .iter()
                .enumerate()
                .map(|(axis, coordinate)| (block[axis * len + point] - coordinate).powi(2))
                .sum();
            if distance < best {
                best = distance;
                *label = cluster;
            }
        }
    }
    nearest
}

/// Cluster means; an emptied cluster is moved onto the point farthest from its own centre, as scikit-learn
/// relocates empty clusters, so that no EM component starts without data.
fn recompute_centres(
    samples: &Samples,
    labels: &mut [usize],
    sums: Vec<f64>,
    mut sizes: Vec<usize>,
    dimension: usize,
) -> Vec<f64> {
    let mut centres = sums;
    for (centre, &size) in centres.chunks_exact_mut(dimension).zip(&sizes) {
        for value in centre {
            *value /= size.max(1) as f64;
        }
    }
    for empty in 0..sizes.len() {
        if sizes[empty] != 0 {
            continue;
        }
        let farthest = samples
            .rows()
            .zip(labels.iter())
            .enumerate()
            .filter(|(_, (_, label))| sizes[**label] > 1)
            .map(|(index, (row, &label))| {
                (index, squared_distance(row, &centres[label * dimension..(label + 1) * dimension]))
            })
            .max_by(|left, right| left.1.total_cmp(&right.1));
        if let Some((index, _)) = farthest {
            sizes[labels[index]] -= 1;
            sizes[empty] = 1;
            labels[index] = empty;
            centres[empty * dimension..(empty + 1) * dimension].copy_from_slice(samples.row(index));
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
        let labels = cluster(&samples, 2, &mut ChaCha8Rng::seed_from_u64(7), Spread::InPlace);
        for pair in labels.chunks_exact(2) {
            assert_ne!(pair[0], pair[1]);
        }
        assert!(labels.iter().step_by(2).all(|&label| label == labels[0]));
    }

    #[test]
    fn labels_name_the_nearest_centre_across_blocks() {
        // Three blobs over several blocks: every label must be the blob of its point.
        let rows: Vec<Vec<f64>> = (0..3 * BLOCK + 5)
            .map(|index| {
                let blob = (index % 3) as f64 * 20.0;
                let jitter = (index as f64 * 0.7).sin();
                vec![blob + jitter, -blob + 0.5 * jitter, jitter]
            })
            .collect();
        let samples = Samples::from_rows(&rows).expect("well-formed data");
        let labels = cluster(&samples, 3, &mut ChaCha8Rng::seed_from_u64(3), Spread::Pool);
        for (index, &label) in labels.iter().enumerate() {
            assert_eq!(label, labels[index % 3], "point {index}");
        }
        let mut distinct = labels[..3].to_vec();
        distinct.sort_unstable();
        assert_eq!(distinct, vec![0, 1, 2]);
    }

    #[test]
    fn identical_points_do_not_break_seeding() {
        let samples = Samples::from_rows(&vec![vec![1.0, 1.0]; 5]).expect("well-formed data");
        let labels = cluster(&samples, 2, &mut ChaCha8Rng::seed_from_u64(1), Spread::InPlace);
        assert_eq!(labels.len(), 5);
        assert!(labels.iter().all(|&label| label < 2));
    }
}
