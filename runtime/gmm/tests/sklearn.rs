//! Cross-check against scikit-learn's `GaussianMixture`: fixed-parameter log densities and EM from the same
//! initial parameters. Skips when scikit-learn is missing unless `LAMP_REQUIRE_ORACLES=1`.

use std::path::Path;
use std::process::Command;

use lamp_gmm::{FitConfig, GaussianMixture, fit_from};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

/// Same formulas, same order of operations up to BLAS blocking: agreement to round-off.
const FIXED_RELATIVE_TOLERANCE: f64 = 1e-9;

/// EM from the same start may stop one iteration apart when the convergence test is marginal.
const FITTED_RELATIVE_TOLERANCE: f64 = 0.01;

fn oracles_required() -> bool {
    std::env::var("LAMP_REQUIRE_ORACLES").is_ok_and(|value| value == "1")
}

fn sklearn_available() -> bool {
    Command::new("python3")
        .args(["-c", "import sklearn, numpy"])
        .output()
        .is_ok_and(|output| output.status.success())
}

fn run_oracle(directory: &Path, case: &Value) -> Value {
    let case_path = directory.join("case.json");
    let result_path = directory.join("result.json");
    std::fs::write(&case_path, case.to_string()).expect("temporary directory is writable");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/sklearn_oracle.py");
    let output = Command::new("python3")
        .arg(script)
        .arg(&case_path)
        .arg(&result_path)
        .output()
        .expect("python3 runs");
    assert!(output.status.success(), "oracle failed: {}", String::from_utf8_lossy(&output.stderr));
    let text = std::fs::read_to_string(&result_path).expect("oracle wrote its result");
    serde_json::from_str(&text).expect("oracle result is JSON")
}

fn numbers(value: &Value) -> Vec<f64> {
    value
        .as_array()
        .expect("an array")
        .iter()
        .map(|entry| entry.as_f64().expect("a number"))
        .collect()
}

fn relative_error(ours: f64, theirs: f64) -> f64 {
    (ours - theirs).abs() / theirs.abs().max(1.0)
}

#[expect(clippy::print_stdout, reason = "the agreement figures are the test's report")]
fn check_case(truth: &GaussianMixture, start: &GaussianMixture, count: usize, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let data: Vec<Vec<f64>> = (0..count).map(|_| truth.sample(&mut rng)).collect();
    let config = FitConfig::default();
    let case = json!({
        "data": data,
        "mixture": start,
        "tolerance": config.tolerance,
        "regularisation": config.regularisation,
        "max_iterations": config.max_iterations,
    });
    let directory = tempfile::tempdir().expect("temporary directory");
    let result = run_oracle(directory.path(), &case);

    let fixed = numbers(&result["fixed"]);
    let worst_fixed = data
        .iter()
        .zip(&fixed)
        .map(|(point, &theirs)| relative_error(start.log_density(point), theirs))
        .fold(0.0, f64::max);
    assert!(
        worst_fixed < FIXED_RELATIVE_TOLERANCE,
        "fixed parameters: worst relative error {worst_fixed}"
    );

    let fitted = fit_from(start, &data, &config).expect("EM succeeds");
    let theirs = numbers(&result["fitted"]);
    let worst_fitted = data
        .iter()
        .zip(&theirs)
        .map(|(point, &theirs)| relative_error(fitted.log_density(point), theirs))
        .fold(0.0, f64::max);
    assert!(
        worst_fitted < FITTED_RELATIVE_TOLERANCE,
        "fitted: worst relative error {worst_fitted} (scikit-learn took {} iterations)",
        result["iterations"]
    );
    println!(
        "{count} points, {} components: worst relative error {worst_fixed:e} (fixed), {worst_fitted:e} (fitted)",
        start.component_count()
    );
    let weights = numbers(&result["fitted_weights"]);
    for (ours, theirs) in fitted.weights().iter().zip(&weights) {
        assert!((ours - theirs).abs() < 0.01, "weights {:?} vs {weights:?}", fitted.weights());
    }
}

#[test]
fn agrees_with_scikit_learn() {
    if !sklearn_available() {
        assert!(
            !oracles_required(),
            "scikit-learn is required (LAMP_REQUIRE_ORACLES=1) but not importable"
        );
        println!("skipped: python3 with scikit-learn and numpy is not available");
        return;
    }
    // Two overlapping clusters in 3-D, started from a rough guess.
    let truth = GaussianMixture::new(
        vec![0.35, 0.65],
        vec![vec![0.0, 0.0, 0.0], vec![2.0, 1.5, -1.0]],
        vec![
            vec![1.0, 0.4, 0.0, 0.4, 0.8, 0.1, 0.0, 0.1, 0.5],
            vec![0.6, 0.0, -0.2, 0.0, 1.2, 0.0, -0.2, 0.0, 0.9],
        ],
    )
    .expect("valid mixture");
    let start = GaussianMixture::new(
        vec![0.5, 0.5],
        vec![vec![-0.5, 0.2, 0.3], vec![2.5, 1.0, -0.5]],
        vec![
            vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            vec![2.0, 0.5, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 1.0],
        ],
    )
    .expect("valid start");
    check_case(&truth, &start, 600, 31);

    // Three components in 6-D with a nearly flat axis, as region features can be.
    let mut means = Vec::new();
    let mut covariances = Vec::new();
    for component in 0..3 {
        let shift = f64::from(component) * 3.0;
        means.push(vec![shift, -shift, 0.5 * shift, 1.0, shift * shift * 0.1, 0.0]);
        let mut covariance = vec![0.0; 36];
        for axis in 0..6 {
            covariance[axis * 7] = if axis == 5 { 1e-4 } else { 0.5 + 0.1 * axis as f64 };
        }
        covariance[1] = 0.2;
        covariance[6] = 0.2;
        covariances.push(covariance);
    }
    let truth = GaussianMixture::new(vec![0.2, 0.3, 0.5], means.clone(), covariances.clone())
        .expect("valid mixture");
    let perturbed: Vec<Vec<f64>> = means
        .iter()
        .map(|mean| {
            mean.iter().enumerate().map(|(axis, value)| value + 0.3 * (axis as f64 - 2.5)).collect()
        })
        .collect();
    let start = GaussianMixture::new(vec![1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0], perturbed, covariances)
        .expect("valid start");
    check_case(&truth, &start, 900, 37);
}
