"""scikit-learn oracle for lamp-gmm: reads a JSON case, writes scikit-learn's log densities.

Usage: python3 sklearn_oracle.py CASE.json RESULT.json
The case holds data points, a mixture (weights, means, row-major covariances) and EM settings.
The result holds `fixed`: score_samples of the given mixture, and `fitted`: score_samples after EM started
from the given mixture (weights_init, means_init, precisions_init), plus the fitted parameters.
"""

import json
import sys

import numpy as np
from sklearn.mixture import GaussianMixture
from sklearn.mixture._gaussian_mixture import _compute_precision_cholesky


def main(case_path, result_path):
    with open(case_path) as handle:
        case = json.load(handle)
    data = np.asarray(case["data"], dtype=float)
    dimension = case["mixture"]["dimension"]
    weights = np.asarray(case["mixture"]["weights"], dtype=float)
    means = np.asarray(case["mixture"]["means"], dtype=float)
    covariances = np.asarray(case["mixture"]["covariances"], dtype=float).reshape(-1, dimension, dimension)
    components = len(weights)

    fixed = GaussianMixture(n_components=components, covariance_type="full")
    fixed.weights_ = weights
    fixed.means_ = means
    fixed.covariances_ = covariances
    fixed.precisions_cholesky_ = _compute_precision_cholesky(covariances, "full")
    fixed_scores = fixed.score_samples(data)

    fitted = GaussianMixture(
        n_components=components,
        covariance_type="full",
        tol=case["tolerance"],
        reg_covar=case["regularisation"],
        max_iter=case["max_iterations"],
        weights_init=weights,
        means_init=means,
        precisions_init=np.linalg.inv(covariances),
    )
    fitted.fit(data)
    result = {
        "fixed": fixed_scores.tolist(),
        "fitted": fitted.score_samples(data).tolist(),
        "fitted_weights": fitted.weights_.tolist(),
        "iterations": int(fitted.n_iter_),
    }
    with open(result_path, "w") as handle:
        json.dump(result, handle)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
