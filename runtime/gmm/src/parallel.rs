//! Data parallelism over blocks of points that gives bit-identical results on any number of threads: every
//! block yields its own partial result, and callers combine the partials in block order. Also the in-block
//! sums and dot products, written so that they vectorise while adding in an order fixed by the code.

use rayon::prelude::*;

/// Whether the blocks of a pass over the data go to the rayon pool. Results are the same either way; spreading
/// one pass pays off only when the pool has no other work, since every pass then waits for its slowest part
/// (and on a loaded machine for a preempted thread).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Spread {
    /// Blocks go to the rayon pool.
    Pool,
    /// Blocks run in order on the calling thread.
    InPlace,
}

/// `work(block)` for every block in `0..blocks`, in block order.
pub(crate) fn map_blocks<T, F>(spread: Spread, blocks: usize, work: F) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    if spread == Spread::InPlace || blocks <= 1 {
        (0..blocks).map(work).collect()
    } else {
        (0..blocks).into_par_iter().map(work).collect()
    }
}

/// [`map_blocks`] where block `b` also owns `buffer[b·chunk .. (b+1)·chunk]` (the last chunk may be shorter).
pub(crate) fn map_blocks_mut<E, T, F>(
    spread: Spread,
    buffer: &mut [E],
    chunk: usize,
    work: F,
) -> Vec<T>
where
    E: Send,
    T: Send,
    F: Fn(usize, &mut [E]) -> T + Sync + Send,
{
    if spread == Spread::InPlace || buffer.len() <= chunk {
        buffer.chunks_mut(chunk).enumerate().map(|(block, part)| work(block, part)).collect()
    } else {
        buffer.par_chunks_mut(chunk).enumerate().map(|(block, part)| work(block, part)).collect()
    }
}

/// Independent partial sums in [`sum`]: enough to vectorise and to hide the latency of additions.
const LANES: usize = 8;

/// Lanes per product in [`dots`], which already has several products in flight.
const SHARED_LANES: usize = 4;

/// Products computed together by [`dots`]: the left operand is loaded once for all of them.
const GROUP: usize = 4;

/// Appends `left · right` for every `right` in `rights`, in order. Products are computed in groups that share
/// the loads of `left`; each one is summed in [`SHARED_LANES`] fixed lanes, so results depend only on the input.
pub(crate) fn dots(left: &[f64], rights: &[&[f64]], out: &mut Vec<f64>) {
    let mut groups = rights.chunks_exact(GROUP);
    for group in groups.by_ref() {
        out.extend(dot_group::<GROUP>(left, [group[0], group[1], group[2], group[3]]));
    }
    match *groups.remainder() {
        [first, second, third] => out.extend(dot_group::<3>(left, [first, second, third])),
        [first, second] => out.extend(dot_group::<2>(left, [first, second])),
        [first] => out.extend(dot_group::<1>(left, [first])),
        _ => {}
    }
}

fn dot_group<const COUNT: usize>(left: &[f64], rights: [&[f64]; COUNT]) -> [f64; COUNT] {
    let mut lanes = [[0.0; SHARED_LANES]; COUNT];
    let whole = left.len() / SHARED_LANES * SHARED_LANES;
    for start in (0..whole).step_by(SHARED_LANES) {
        let a = &left[start..start + SHARED_LANES];
        for (accumulator, right) in lanes.iter_mut().zip(&rights) {
            let b = &right[start..start + SHARED_LANES];
            for lane in 0..SHARED_LANES {
                accumulator[lane] += a[lane] * b[lane];
            }
        }
    }
    let mut results = [0.0; COUNT];
    for ((result, accumulator), right) in results.iter_mut().zip(&lanes).zip(&rights) {
        let tail: f64 = left[whole..].iter().zip(&right[whole..]).map(|(a, b)| a * b).sum();
        *result = (accumulator[0] + accumulator[1]) + (accumulator[2] + accumulator[3]) + tail;
    }
    results
}

/// Pairwise sum of the lanes.
fn combine(lanes: [f64; LANES]) -> f64 {
    ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3]))
        + ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]))
}

/// Σ values, summed in [`LANES`] interleaved lanes so that the loop vectorises while the order of additions
/// stays fixed by the code (and thus the result by the input).
pub(crate) fn sum(values: &[f64]) -> f64 {
    let mut lanes = [0.0; LANES];
    let chunks = values.chunks_exact(LANES);
    let tail: f64 = chunks.remainder().iter().sum();
    for chunk in chunks {
        for lane in 0..LANES {
            lanes[lane] += chunk[lane];
        }
    }
    combine(lanes) + tail
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_come_back_in_order() {
        for spread in [Spread::Pool, Spread::InPlace] {
            assert_eq!(map_blocks(spread, 5, |block| block * 10), vec![0, 10, 20, 30, 40]);
            let mut buffer = vec![0.0; 7];
            let lengths = map_blocks_mut(spread, &mut buffer, 3, |block, part| {
                part.fill(block as f64);
                part.len()
            });
            assert_eq!(lengths, vec![3, 3, 1]);
            assert_eq!(buffer, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0]);
        }
    }

    #[test]
    fn lane_sums_match_plain_sums() {
        let left: Vec<f64> = (0..11).map(|index| index as f64).collect();
        let right: Vec<f64> = (0..11).map(|index| 2.0 - index as f64).collect();
        assert_eq!(sum(&left), 55.0);
        let third: Vec<f64> = (0..11).map(|index| (index % 3) as f64).collect();
        let mut grouped = Vec::new();
        dots(&left, &[&right, &third, &left, &right, &third], &mut grouped);
        let plain = |other: &[f64]| -> f64 { left.iter().zip(other).map(|(a, b)| a * b).sum() };
        assert_eq!(
            grouped,
            vec![plain(&right), plain(&third), plain(&left), plain(&right), plain(&third)]
        );
    }
}
