//! The demonstration pool and the subsets drawn from it: one seeded draw per (count, run),
//! stratified so that the fraction of cut demonstrations matches the pool's.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::error::EvalError;

/// One demonstration of the pool.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PoolDemo {
    /// The file's name, as in the demonstration digest.
    pub name: String,
    /// Whether the demonstration was cut short (its header's `cut_at` provenance names a step);
    /// a file without that provenance counts as a full demonstration.
    pub cut: bool,
    /// Objects it shows: bodies of a movable type.
    pub objects: usize,
}

/// Parses `--demos`: positive whole numbers separated by commas, each once, in the order given.
pub fn parse_counts(text: &str) -> Result<Vec<usize>, EvalError> {
    let error = || EvalError::Counts { text: text.to_string() };
    let mut counts = Vec::new();
    for part in text.split(',') {
        let count: usize = part.trim().parse().map_err(|_| error())?;
        if count == 0 || counts.contains(&count) {
            return Err(error());
        }
        counts.push(count);
    }
    Ok(counts)
}

/// SplitMix64's finaliser: a bijective mix of 64 bits.
fn splitmix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// The seed of the draw for `count` demonstrations in run `run`: the evaluation's seed mixed with
/// the count and the run (SplitMix64), so that every (count, run) has its own stream.
pub fn subset_seed(seed: u64, count: usize, run: usize) -> u64 {
    let mut x = splitmix(seed);
    for value in [count as u64, run as u64] {
        x = splitmix(x ^ splitmix(value));
    }
    x
}

/// How many of a subset of `count` (at most `pool`) demonstrations are cut short, for a pool of
/// `pool` demonstrations of which `cut` are: `round(count · cut / pool)`, halves rounded up, never
/// more than there are, nor so few that the full ones run out. The rest reach their goal.
pub fn cut_places(count: usize, pool: usize, cut: usize) -> usize {
    if pool == 0 {
        return 0;
    }
    let places = ((2 * count * cut + pool) / (2 * pool)).min(cut);
    places.max(count.saturating_sub(pool - cut))
}

/// Draws `count` demonstrations of `pool` for run `run`: indices into `pool`, ascending.
///
/// The cut demonstrations get `round(count · cut / pool)` of the places (halves rounded up, never
/// more than there are), the full ones the rest; each stratum is drawn without replacement by a
/// partial Fisher–Yates shuffle, cut ones first, from one ChaCha8 generator seeded with
/// [`subset_seed`]. The draw depends only on the pool (in the order given), the seed, the count
/// and the run.
pub fn draw_subset(
    pool: &[PoolDemo],
    count: usize,
    seed: u64,
    run: usize,
) -> Result<Vec<usize>, EvalError> {
    if count > pool.len() {
        return Err(EvalError::PoolTooSmall { count, pool: pool.len() });
    }
    let (mut cut, mut full): (Vec<usize>, Vec<usize>) =
        (0..pool.len()).partition(|&index| pool[index].cut);
    let cut_places = cut_places(count, pool.len(), cut.len());
    let full_places = count - cut_places;
    let mut rng = ChaCha8Rng::seed_from_u64(subset_seed(seed, count, run));
    let mut chosen = Vec::with_capacity(count);
    for (stratum, places) in [(&mut cut, cut_places), (&mut full, full_places)] {
        for place in 0..places {
            let pick = place + rng.random_range(0..(stratum.len() - place) as u64) as usize;
            stratum.swap(place, pick);
            chosen.push(stratum[place]);
        }
    }
    chosen.sort_unstable();
    Ok(chosen)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pool(cut: usize, full: usize) -> Vec<PoolDemo> {
        assert!(cut <= full);
        (0..cut + full)
            .map(|index| PoolDemo {
                name: format!("demo_{index:04}.mcap"),
                // Interleaved, so that the strata are not contiguous (needs `cut <= full`).
                cut: index % 2 == 0 && index / 2 < cut,
                objects: 1,
            })
            .collect()
    }

    #[test]
    fn cut_places_says_how_many_of_a_drawn_subset_are_cut() {
        for (cut, full) in [(3, 7), (5, 5), (0, 4), (10, 11)] {
            let pool = pool(cut, full);
            for count in 1..=pool.len() {
                let drawn = draw_subset(&pool, count, 7, 1).expect("a subset");
                let drawn_cut = drawn.iter().filter(|&&index| pool[index].cut).count();
                assert_eq!(cut_places(count, pool.len(), cut), drawn_cut, "{cut} {full} {count}");
            }
        }
    }

    #[test]
    fn counts_parse_in_order_and_refuse_zero_duplicates_and_words() {
        assert_eq!(parse_counts("200, 100,50").expect("valid"), vec![200, 100, 50]);
        for bad in ["", "0", "10,10", "ten", "10,", "-5"] {
            assert_eq!(parse_counts(bad), Err(EvalError::Counts { text: bad.into() }), "{bad}");
        }
    }

    #[test]
    fn a_draw_keeps_the_pools_fraction_of_cut_demonstrations() {
        let pool: Vec<PoolDemo> = (0..200)
            .map(|index| PoolDemo {
                name: format!("demo_{index:04}.mcap"),
                cut: index % 4 == 1 || index % 4 == 2,
                objects: 1,
            })
            .collect();
        assert_eq!(pool.iter().filter(|demo| demo.cut).count(), 100);
        for (count, expected_cut) in [(200, 100), (100, 50), (25, 13), (10, 5), (1, 1)] {
            for run in 1..=5 {
                let subset = draw_subset(&pool, count, 7, run).expect("the pool is large enough");
                assert_eq!(subset.len(), count);
                let cut = subset.iter().filter(|&&index| pool[index].cut).count();
                assert_eq!(cut, expected_cut, "count {count}, run {run}");
                let mut unique = subset.clone();
                unique.dedup();
                assert_eq!(unique, subset, "ascending, without repeats");
            }
        }
    }

    #[test]
    fn a_lopsided_pool_is_rounded_and_clamped_to_its_strata() {
        // 3 cut of 10: 4 places give round(1.2) = 1 cut; 9 places give round(2.7) = 3 cut.
        let pool = pool(3, 7);
        let cut_of = |subset: &[usize]| subset.iter().filter(|&&i| pool[i].cut).count();
        assert_eq!(cut_of(&draw_subset(&pool, 4, 1, 1).expect("fits")), 1);
        assert_eq!(cut_of(&draw_subset(&pool, 9, 1, 1).expect("fits")), 3);
        assert_eq!(draw_subset(&pool, 10, 1, 1).expect("fits"), (0..10).collect::<Vec<_>>());
        // Only full demonstrations: the rounding never asks for a cut one.
        let full: Vec<PoolDemo> =
            pool.iter().map(|demo| PoolDemo { cut: false, ..demo.clone() }).collect();
        assert_eq!(draw_subset(&full, 5, 1, 1).expect("fits").len(), 5);
    }

    #[test]
    fn draws_are_seeded_by_seed_count_and_run() {
        let pool = pool(20, 20);
        let a = draw_subset(&pool, 10, 1, 1).expect("fits");
        assert_eq!(a, draw_subset(&pool, 10, 1, 1).expect("fits"), "reproducible");
        assert_ne!(a, draw_subset(&pool, 10, 1, 2).expect("fits"), "another run");
        assert_ne!(a, draw_subset(&pool, 10, 2, 1).expect("fits"), "another seed");
        assert_ne!(subset_seed(1, 10, 2), subset_seed(1, 2, 10), "count and run are not swapped");
    }

    #[test]
    fn a_count_beyond_the_pool_is_refused() {
        assert_eq!(
            draw_subset(&pool(2, 2), 5, 1, 1),
            Err(EvalError::PoolTooSmall { count: 5, pool: 4 })
        );
    }
}
