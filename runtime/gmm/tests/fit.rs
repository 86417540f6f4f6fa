//! Fitting: recovery of known mixtures, BIC model selection, degenerate data, determinism and calibration.

use lamp_gmm::{
    FitConfig, GaussianMixture, GmmError, calibrate_threshold, fit, fit_from, fit_row_major,
    fit_with_report,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn truth() -> GaussianMixture {
    GaussianMixture::new(
        vec![0.4, 0.6],
        vec![vec![0.0, 0.0, 0.0], vec![5.0, 4.0, -3.0]],
        vec![
            vec![1.0, 0.4, 0.0, 0.4, 0.8, 0.1, 0.0, 0.1, 0.5],
            vec![0.6, 0.0, -0.2, 0.0, 1.2, 0.0, -0.2, 0.0, 0.9],
        ],
    )
    .expect("valid mixture")
}

fn draw(mixture: &GaussianMixture, count: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count).map(|_| mixture.sample(&mut rng)).collect()
}

#[test]
fn recovers_a_two_component_mixture_and_bic_picks_two() {
    let data = draw(&truth(), 3000, 1);
    let report = fit_with_report(&data, &FitConfig::default(), &mut ChaCha8Rng::seed_from_u64(2))
        .expect("fit succeeds");
    assert_eq!(report.candidates.len(), 4);
    let fitted = &report.mixture;
    assert_eq!(fitted.component_count(), 2, "candidates: {:?}", report.candidates);
    // Match components by mean (the order is arbitrary).
    let truth = truth();
    for (true_weight, (true_mean, true_covariance)) in
        truth.weights().iter().zip(truth.means().iter().zip(truth.covariances()))
    {
        let nearest = (0..2)
            .min_by(|&left, &right| {
                let distance = |index: usize| -> f64 {
                    fitted.means()[index].iter().zip(true_mean).map(|(a, b)| (a - b).powi(2)).sum()
                };
                distance(left).total_cmp(&distance(right))
            })
            .expect("two components");
        assert!((fitted.weights()[nearest] - true_weight).abs() < 0.03);
        for (fitted_value, true_value) in fitted.means()[nearest].iter().zip(true_mean) {
            assert!((fitted_value - true_value).abs() < 0.1, "means {:?}", fitted.means());
        }
        for (fitted_value, true_value) in fitted.covariances()[nearest].iter().zip(true_covariance)
        {
            assert!(
                (fitted_value - true_value).abs() < 0.12,
                "covariances {:?}",
                fitted.covariances()
            );
        }
    }
    let bics: Vec<f64> = report.candidates.iter().map(|candidate| candidate.bic).collect();
    assert!(bics[1] < bics[0] && bics[1] < bics[2] && bics[1] < bics[3], "{bics:?}");
    assert!(report.candidates.iter().all(|candidate| candidate.converged));
}

#[test]
fn bic_picks_one_component_for_one_gaussian() {
    let single = GaussianMixture::new(
        vec![1.0],
        vec![vec![1.0, 2.0, 3.0, 4.0]],
        vec![vec![1.0, 0.2, 0.0, 0.0, 0.2, 2.0, 0.3, 0.0, 0.0, 0.3, 0.5, 0.0, 0.0, 0.0, 0.0, 0.1]],
    )
    .expect("valid Gaussian");
    let data = draw(&single, 2000, 5);
    let fitted =
        fit(&data, &FitConfig::default(), &mut ChaCha8Rng::seed_from_u64(6)).expect("fit succeeds");
    assert_eq!(fitted.component_count(), 1);
    // The single-component fit is the sample mean and the biased sample covariance plus regularisation.
    let count = data.len() as f64;
    for axis in 0..4 {
        let mean: f64 = data.iter().map(|point| point[axis]).sum::<f64>() / count;
        assert!((fitted.means()[0][axis] - mean).abs() < 1e-9);
        let variance: f64 =
            data.iter().map(|point| (point[axis] - mean).powi(2)).sum::<f64>() / count;
        assert!((fitted.covariances()[0][axis * 5] - (variance + 1e-6)).abs() < 1e-9);
    }
}

#[test]
fn fitting_is_deterministic_for_a_seed() {
    let data = draw(&truth(), 500, 3);
    let config = FitConfig { restarts: 2, ..FitConfig::default() };
    let first = fit(&data, &config, &mut ChaCha8Rng::seed_from_u64(9)).expect("fit succeeds");
    let second = fit(&data, &config, &mut ChaCha8Rng::seed_from_u64(9)).expect("fit succeeds");
    assert_eq!(first, second);
    let flat: Vec<f64> = data.iter().flatten().copied().collect();
    let third =
        fit_row_major(&flat, 3, &config, &mut ChaCha8Rng::seed_from_u64(9)).expect("fit succeeds");
    assert_eq!(first, third);
}

#[test]
fn fitting_does_not_depend_on_the_number_of_threads() {
    // Several blocks of points, several restarts: the runs and the blocks really are spread over threads.
    let data = draw(&truth(), 2500, 8);
    let on_threads = |threads: usize, config: FitConfig| {
        let pool =
            rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
        pool.install(|| fit_with_report(&data, &config, &mut ChaCha8Rng::seed_from_u64(5)))
            .expect("fit succeeds")
    };
    // Eight runs (each run on one thread), then a single run (its passes over the data spread instead).
    for config in [
        FitConfig { restarts: 2, ..FitConfig::default() },
        FitConfig { max_components: 1, ..FitConfig::default() },
    ] {
        let sequential = on_threads(1, config);
        assert_eq!(sequential, on_threads(2, config));
        assert_eq!(sequential, on_threads(3, config));
    }
    let start = on_threads(1, FitConfig::default()).mixture;
    let refit_on = |threads: usize| {
        let pool =
            rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
        pool.install(|| fit_from(&start, &data, &FitConfig::default())).expect("EM succeeds")
    };
    assert_eq!(refit_on(1), refit_on(2));
}

#[test]
fn fitting_draws_one_32_byte_key_from_the_caller() {
    use rand::Rng;
    let data = draw(&truth(), 300, 12);
    let mut rng = ChaCha8Rng::seed_from_u64(40);
    fit(&data, &FitConfig::default(), &mut rng).expect("fit succeeds");
    let mut expected = ChaCha8Rng::seed_from_u64(40);
    let mut key = [0_u8; 32];
    expected.fill_bytes(&mut key);
    // The caller's generator moved on by exactly the key, whatever the data and configuration.
    assert_eq!(rng.next_u64(), expected.next_u64());
}

#[test]
fn fit_from_converges_to_the_same_mixture_as_fit() {
    let data = draw(&truth(), 1000, 4);
    let config = FitConfig { tolerance: 1e-10, max_iterations: 500, ..FitConfig::default() };
    let fitted = fit(&data, &config, &mut ChaCha8Rng::seed_from_u64(4)).expect("fit succeeds");
    // A perturbed start converges back to the same optimum.
    let start = GaussianMixture::new(
        vec![0.5, 0.5],
        vec![vec![0.5, 0.5, 0.5], vec![4.0, 3.0, -2.0]],
        vec![vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]; 2],
    )
    .expect("valid start");
    let refitted = fit_from(&start, &data, &config).expect("EM succeeds");
    for point in data.iter().take(50) {
        let difference = (fitted.log_density(point) - refitted.log_density(point)).abs();
        assert!(difference < 1e-6, "{difference}");
    }
    assert!(matches!(
        fit_from(&start, &[vec![1.0, 2.0]], &config),
        Err(GmmError::ShapeMismatch { expected: 3, found: 2, .. })
    ));
}

fn assert_usable(mixture: &GaussianMixture, probe: &[f64]) {
    let value = mixture.log_density(probe);
    assert!(!value.is_nan(), "log density is NaN");
    for covariance in mixture.covariances() {
        assert!(covariance.iter().all(|entry| entry.is_finite()));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    assert!(mixture.sample(&mut rng).iter().all(|value| value.is_finite()));
}

#[test]
fn degenerate_data_never_panics_or_gives_nan() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let config = FitConfig::default();
    // Identical points: only k = 1 is tried, and the covariance is the regularisation.
    let identical = vec![vec![1.0, 2.0, 3.0]; 50];
    let fitted = fit(&identical, &config, &mut rng).expect("fit succeeds");
    assert_eq!(fitted.component_count(), 1);
    assert!((fitted.covariances()[0][0] - 1e-6).abs() < 1e-12);
    assert_usable(&fitted, &[1.0, 2.0, 3.0]);
    // One point, and two distinct points.
    assert_usable(
        &fit(&[vec![0.5, 0.5, 0.5]], &config, &mut rng).expect("fit succeeds"),
        &[0.0; 3],
    );
    let two = vec![vec![0.0, 0.0, 0.0], vec![1.0, 1.0, 1.0]];
    assert_usable(&fit(&two, &config, &mut rng).expect("fit succeeds"), &[0.5; 3]);
    // A zero-variance dimension among varying ones.
    let flat_axis: Vec<Vec<f64>> =
        (0..200).map(|index| vec![f64::from(index % 17), 4.0, f64::from(index % 5)]).collect();
    assert_usable(&fit(&flat_axis, &config, &mut rng).expect("fit succeeds"), &[3.0, 4.0, 1.0]);
    // Zero regularisation on identical points falls back to diagonal jitter.
    let unregularised = FitConfig { regularisation: 0.0, ..config };
    assert_usable(
        &fit(&identical, &unregularised, &mut rng).expect("fit succeeds"),
        &[1.0, 2.0, 3.0],
    );
    // Few points in many dimensions.
    let few: Vec<Vec<f64>> = (0..4).map(|index| vec![f64::from(index); 9]).collect();
    assert_usable(&fit(&few, &config, &mut rng).expect("fit succeeds"), &[0.0; 9]);
    // Large offsets with small spread.
    let offset: Vec<Vec<f64>> =
        (0..100).map(|index| vec![1e6 + f64::from(index) * 1e-4, -1e6, 1e6]).collect();
    assert_usable(&fit(&offset, &config, &mut rng).expect("fit succeeds"), &[1e6, -1e6, 1e6]);
}

#[test]
fn invalid_inputs_are_typed_errors() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let config = FitConfig::default();
    assert_eq!(fit(&[], &config, &mut rng), Err(GmmError::NoData));
    assert!(matches!(
        fit(&[vec![f64::INFINITY]], &config, &mut rng),
        Err(GmmError::NotFinite { .. })
    ));
    let data = vec![vec![0.0], vec![1.0]];
    for bad in [
        FitConfig { max_components: 0, ..config },
        FitConfig { max_iterations: 0, ..config },
        FitConfig { restarts: 0, ..config },
        FitConfig { tolerance: f64::NAN, ..config },
        FitConfig { regularisation: -1.0, ..config },
    ] {
        assert!(matches!(fit(&data, &bad, &mut rng), Err(GmmError::InvalidConfig { .. })));
    }
}

#[test]
fn calibration_follows_the_quantile_rule() {
    let mixture =
        GaussianMixture::new(vec![1.0], vec![vec![0.0]], vec![vec![1.0]]).expect("valid Gaussian");
    let points: Vec<Vec<f64>> = (0..10).map(|index| vec![f64::from(index)]).collect();
    let densities: Vec<f64> = points.iter().map(|point| mixture.log_density(point)).collect();
    // Densities decrease with |x|, so the m-th largest is at x = m − 1.
    assert_eq!(calibrate_threshold(&mixture, &points, 1.0), Ok(densities[9]));
    assert_eq!(calibrate_threshold(&mixture, &points, 0.9), Ok(densities[8]));
    assert_eq!(calibrate_threshold(&mixture, &points, 0.85), Ok(densities[8]));
    assert_eq!(calibrate_threshold(&mixture, &points, 0.01), Ok(densities[0]));
    for cover in [1.0, 0.9, 0.73, 0.5, 0.2] {
        let threshold = calibrate_threshold(&mixture, &points, cover).expect("valid calibration");
        let inside = points.iter().filter(|point| mixture.contains(point, threshold)).count();
        assert!(inside as f64 >= cover * 10.0 - 1e-9, "{cover}: {inside}");
        assert!((inside as f64) < cover * 10.0 + 1.0, "{cover}: {inside}");
    }
    assert_eq!(
        calibrate_threshold(&mixture, &points, 0.0),
        Err(GmmError::InvalidCover { cover: 0.0 })
    );
    assert!(calibrate_threshold(&mixture, &points, 1.5).is_err());
    assert!(calibrate_threshold(&mixture, &points, f64::NAN).is_err());
    assert_eq!(calibrate_threshold(&mixture, &[], 0.5), Err(GmmError::NoData));
    assert!(matches!(
        calibrate_threshold(&mixture, &[vec![0.0, 1.0]], 0.5),
        Err(GmmError::ShapeMismatch { .. })
    ));
}

#[test]
fn calibrated_fit_covers_its_region_and_rejects_far_points() {
    let data = draw(&truth(), 1000, 21);
    let fitted = fit(&data, &FitConfig::default(), &mut ChaCha8Rng::seed_from_u64(22))
        .expect("fit succeeds");
    let threshold = calibrate_threshold(&fitted, &data, 0.95).expect("valid calibration");
    let fresh = draw(&truth(), 2000, 23);
    let covered =
        fresh.iter().filter(|point| fitted.contains(point, threshold)).count() as f64 / 2000.0;
    assert!((covered - 0.95).abs() < 0.03, "{covered}");
    assert!(!fitted.contains(&[2.5, 2.0, -1.5], threshold));
    assert!(!fitted.contains(&[20.0, 0.0, 0.0], threshold));
}
