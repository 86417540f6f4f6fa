//! Fitting speed: 5 000 points in 6-D from three clusters, BIC over k = 1..=4 (compare with
//! `benches/sklearn_fit.py`, which times scikit-learn on the same mixture and settings), on the global rayon
//! pool (all cores, or `RAYON_NUM_THREADS`) and on a one-thread pool.

use criterion::{Criterion, criterion_group, criterion_main};
use lamp_gmm::{FitConfig, GaussianMixture, fit};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;

const DIMENSION: usize = 6;
const POINTS: usize = 5_000;

/// Three clusters; `benches/sklearn_fit.py` builds the same one.
fn source() -> GaussianMixture {
    let mut means = Vec::new();
    let mut covariances = Vec::new();
    for component in 0..3 {
        let shift = component as f64 * 3.0;
        means.push(
            (0..DIMENSION).map(|axis| shift * if axis % 2 == 0 { 1.0 } else { -0.5 }).collect(),
        );
        let mut covariance = vec![0.0; DIMENSION * DIMENSION];
        for axis in 0..DIMENSION {
            covariance[axis * (DIMENSION + 1)] = 0.5 + 0.1 * axis as f64;
        }
        covariance[1] = 0.2;
        covariance[DIMENSION] = 0.2;
        covariances.push(covariance);
    }
    GaussianMixture::new(vec![0.2, 0.3, 0.5], means, covariances).expect("valid source mixture")
}

fn bench_fit(criterion: &mut Criterion) {
    let source = source();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let data: Vec<Vec<f64>> = (0..POINTS).map(|_| source.sample(&mut rng)).collect();
    let config = FitConfig { max_components: 4, ..FitConfig::default() };
    let mut group = criterion.benchmark_group("fit");
    group.sample_size(10);
    group.bench_function("bic_k1_to_4_5000x6", |bencher| {
        bencher.iter(|| {
            let mut rng = ChaCha8Rng::seed_from_u64(2);
            black_box(fit(black_box(&data), &config, &mut rng).expect("fit succeeds"))
        });
    });
    let one_thread =
        rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("one-thread pool");
    group.bench_function("bic_k1_to_4_5000x6_one_thread", |bencher| {
        bencher.iter(|| {
            one_thread.install(|| {
                let mut rng = ChaCha8Rng::seed_from_u64(2);
                black_box(fit(black_box(&data), &config, &mut rng).expect("fit succeeds"))
            })
        });
    });
    group.finish();
}

criterion_group!(benches, bench_fit);
criterion_main!(benches);
