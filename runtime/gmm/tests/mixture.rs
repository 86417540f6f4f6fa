//! The mixture value: validation, closed-form log densities, sampling statistics and the serialised layout.

use approx::assert_relative_eq;
use lamp_gmm::{GaussianMixture, GmmError};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const LN_2PI: f64 = 1.837_877_066_409_345_5;

fn correlated_3d() -> GaussianMixture {
    GaussianMixture::new(
        vec![1.0],
        vec![vec![1.0, -2.0, 0.5]],
        vec![vec![4.0, 1.2, 0.0, 1.2, 2.0, -0.3, 0.0, -0.3, 0.5]],
    )
    .expect("valid single Gaussian")
}

#[test]
fn single_gaussian_log_density_matches_the_closed_form() {
    let mixture = correlated_3d();
    let point = [2.0, -1.0, 0.0];
    // Σ⁻¹ and det Σ worked out by hand with cofactors.
    let covariance = [[4.0, 1.2, 0.0], [1.2, 2.0, -0.3], [0.0, -0.3, 0.5]];
    let determinant = 4.0 * (2.0 * 0.5 - 0.09) - 1.2 * (1.2 * 0.5) + 0.0;
    let cofactor = [
        [2.0 * 0.5 - 0.09, -(1.2 * 0.5), 1.2 * -0.3],
        [-(1.2 * 0.5), 4.0 * 0.5, -(4.0 * -0.3)],
        [1.2 * -0.3, -(4.0 * -0.3), 4.0 * 2.0 - 1.44],
    ];
    let difference = [1.0, 1.0, -0.5];
    let mut quadratic = 0.0;
    for row in 0..3 {
        for column in 0..3 {
            quadratic += difference[row] * cofactor[row][column] / determinant * difference[column];
        }
    }
    let expected = -0.5 * (3.0 * LN_2PI + f64::ln(determinant) + quadratic);
    assert_relative_eq!(mixture.log_density(&point), expected, max_relative = 1e-12);
    assert_eq!(mixture.dimension(), 3);
    assert_eq!(mixture.component_count(), 1);
    assert_eq!(covariance[1][2], mixture.covariances()[0][5]);
}

#[test]
fn two_component_density_is_the_weighted_sum() {
    let mixture = GaussianMixture::new(
        vec![0.3, 0.7],
        vec![vec![0.0, 0.0], vec![3.0, 1.0]],
        vec![vec![1.0, 0.0, 0.0, 1.0], vec![0.25, 0.0, 0.0, 4.0]],
    )
    .expect("valid mixture");
    let point = [1.0, 0.5];
    let first = f64::exp(-0.5 * (1.0 + 0.25)) / (2.0 * std::f64::consts::PI);
    let second = f64::exp(-0.5 * (4.0 / 0.25 + 0.25 / 4.0)) / (2.0 * std::f64::consts::PI * 1.0);
    let expected = f64::ln(0.3 * first + 0.7 * second);
    assert_relative_eq!(mixture.log_density(&point), expected, max_relative = 1e-12);
    // Far away, the densities underflow but log-sum-exp keeps the value finite.
    let far = mixture.log_density(&[1e4, -1e4]);
    assert!(far.is_finite() && far < -1e6);
    assert_eq!(mixture.log_density(&[1.0]), f64::NEG_INFINITY);
    assert!(mixture.contains(&[0.0, 0.0], mixture.log_density(&[0.0, 0.0])));
    assert!(!mixture.contains(&[1e4, 0.0], -100.0));
}

#[test]
fn constructor_rejects_invalid_parameters() {
    let identity = vec![1.0, 0.0, 0.0, 1.0];
    let origin = vec![0.0, 0.0];
    let build = |weights: Vec<f64>, means: Vec<Vec<f64>>, covariances: Vec<Vec<f64>>| {
        GaussianMixture::new(weights, means, covariances).err()
    };
    assert_eq!(build(vec![], vec![], vec![]), Some(GmmError::NoComponents));
    assert_eq!(build(vec![1.0], vec![vec![]], vec![vec![]]), Some(GmmError::ZeroDimension));
    assert!(matches!(
        build(vec![0.5, 0.5], vec![origin.clone()], vec![identity.clone()]),
        Some(GmmError::ComponentCountMismatch { weights: 2, means: 1, covariances: 1 })
    ));
    assert_eq!(build(vec![0.5, 0.5], vec![origin.clone(); 2], vec![identity.clone(); 2]), None);
    assert!(matches!(
        build(vec![0.5, 0.6], vec![origin.clone(); 2], vec![identity.clone(); 2]),
        Some(GmmError::WeightsNotNormalised { .. })
    ));
    assert!(matches!(
        build(vec![1.5, -0.5], vec![origin.clone(); 2], vec![identity.clone(); 2]),
        Some(GmmError::NegativeWeight { index: 1, .. })
    ));
    assert!(matches!(
        build(vec![f64::NAN], vec![origin.clone()], vec![identity.clone()]),
        Some(GmmError::NotFinite { .. })
    ));
    assert!(matches!(
        build(vec![1.0], vec![vec![0.0, 0.0, 0.0]], vec![identity.clone()]),
        Some(GmmError::ShapeMismatch { expected: 9, found: 4, .. })
    ));
    assert!(matches!(
        build(vec![1.0], vec![origin.clone()], vec![vec![1.0, 0.5, 0.0, 1.0]]),
        Some(GmmError::CovarianceNotSymmetric { component: 0 })
    ));
    assert!(matches!(
        build(vec![1.0], vec![origin.clone()], vec![vec![1.0, 2.0, 2.0, 1.0]]),
        Some(GmmError::CovarianceNotPositiveDefinite { component: 0 })
    ));
    assert!(matches!(
        build(vec![1.0], vec![origin], vec![vec![1.0, 0.0, 0.0, 0.0]]),
        Some(GmmError::CovarianceNotPositiveDefinite { component: 0 })
    ));
}

#[test]
fn samples_have_the_mixture_mean_and_covariance() {
    let mixture = GaussianMixture::new(
        vec![0.25, 0.75],
        vec![vec![-2.0, 0.0, 1.0], vec![2.0, 1.0, 1.0]],
        vec![
            vec![1.0, 0.3, 0.0, 0.3, 0.5, 0.1, 0.0, 0.1, 0.2],
            vec![0.5, -0.2, 0.0, -0.2, 1.0, 0.0, 0.0, 0.0, 0.3],
        ],
    )
    .expect("valid mixture");
    // Law of total mean and variance for the mixture.
    let mut mean = [0.0; 3];
    for (weight, component_mean) in mixture.weights().iter().zip(mixture.means()) {
        for axis in 0..3 {
            mean[axis] += weight * component_mean[axis];
        }
    }
    let mut covariance = [[0.0; 3]; 3];
    for component in 0..2 {
        let weight = mixture.weights()[component];
        let component_mean = &mixture.means()[component];
        for row in 0..3 {
            for column in 0..3 {
                covariance[row][column] += weight
                    * (mixture.covariances()[component][row * 3 + column]
                        + (component_mean[row] - mean[row])
                            * (component_mean[column] - mean[column]));
            }
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let count = 40_000;
    let draws: Vec<Vec<f64>> = (0..count).map(|_| mixture.sample(&mut rng)).collect();
    let mut sample_mean = [0.0; 3];
    for draw in &draws {
        for axis in 0..3 {
            sample_mean[axis] += draw[axis] / count as f64;
        }
    }
    let mut sample_covariance = [[0.0; 3]; 3];
    for draw in &draws {
        for row in 0..3 {
            for column in 0..3 {
                sample_covariance[row][column] += (draw[row] - sample_mean[row])
                    * (draw[column] - sample_mean[column])
                    / (count - 1) as f64;
            }
        }
    }
    // Standard errors at 40 000 draws are about 0.01 for means and 0.02 for (co)variances of this size.
    for axis in 0..3 {
        assert!(
            (sample_mean[axis] - mean[axis]).abs() < 0.04,
            "mean {axis}: {sample_mean:?} vs {mean:?}"
        );
        for column in 0..3 {
            let error = (sample_covariance[axis][column] - covariance[axis][column]).abs();
            assert!(
                error < 0.06,
                "covariance ({axis}, {column}): {sample_covariance:?} vs {covariance:?}"
            );
        }
    }
    // The same seed gives the same draws.
    let mut again = ChaCha8Rng::seed_from_u64(11);
    assert_eq!(mixture.sample(&mut again), draws[0]);
}

#[test]
fn draws_among_some_components_come_from_those_alone() {
    // Three unit-variance components far apart on one axis.
    let identity = vec![1.0, 0.0, 0.0, 1.0];
    let mixture = GaussianMixture::new(
        vec![0.5, 0.3, 0.2],
        vec![vec![-100.0, 0.0], vec![0.0, 0.0], vec![100.0, 0.0]],
        vec![identity.clone(), identity.clone(), identity],
    )
    .expect("valid mixture");
    let nearest = |draw: &[f64]| ((draw[0] + 150.0) / 100.0).floor() as usize;
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut counts = [0usize; 3];
    for _ in 0..4000 {
        counts[nearest(&mixture.sample_among(&[1, 2], &mut rng))] += 1;
    }
    assert_eq!(counts[0], 0, "no draw from a component left out: {counts:?}");
    // In proportion to the weights of those drawn from: 0.3 : 0.2, 2400 : 1600 ± 3 %.
    assert!((counts[1] as f64 - 2400.0).abs() < 120.0, "{counts:?}");
    // An empty or out-of-range choice draws the whole mixture, exactly as `sample` does.
    let (mut first, mut second) = (ChaCha8Rng::seed_from_u64(9), ChaCha8Rng::seed_from_u64(9));
    assert_eq!(mixture.sample_among(&[7], &mut first), mixture.sample(&mut second));
}

#[test]
fn serialisation_round_trips_and_validates() {
    let mixture = correlated_3d();
    let json = serde_json::to_string(&mixture).expect("serialisable");
    assert_eq!(
        json,
        "{\"dimension\":3,\"weights\":[1.0],\"means\":[[1.0,-2.0,0.5]],\
         \"covariances\":[[4.0,1.2,0.0,1.2,2.0,-0.3,0.0,-0.3,0.5]]}"
    );
    let back: GaussianMixture = serde_json::from_str(&json).expect("valid layout");
    assert_eq!(back, mixture);
    assert_eq!(back.log_density(&[0.0, 0.0, 0.0]), mixture.log_density(&[0.0, 0.0, 0.0]));
    let not_positive = "{\"dimension\":2,\"weights\":[1.0],\"means\":[[0.0,0.0]],\
                        \"covariances\":[[1.0,2.0,2.0,1.0]]}";
    let error =
        serde_json::from_str::<GaussianMixture>(not_positive).expect_err("must be rejected");
    assert!(error.to_string().contains("not positive definite"), "{error}");
    let wrong_dimension = "{\"dimension\":3,\"weights\":[1.0],\"means\":[[0.0,0.0]],\
                           \"covariances\":[[1.0,0.0,0.0,1.0]]}";
    assert!(serde_json::from_str::<GaussianMixture>(wrong_dimension).is_err());
}
