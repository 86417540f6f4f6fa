"""Times scikit-learn on the workload of benches/fit.rs: 5 000 points in 6-D, BIC over k = 1..4.

Usage: python3 benches/sklearn_fit.py
Prints the median wall time of ten full model selections, and the OpenMP / BLAS thread pools scikit-learn
used (set OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 to time it on one thread).
"""

import time

import numpy as np
from sklearn.mixture import GaussianMixture

DIMENSION = 6
POINTS = 5000


def source_points(generator):
    weights = np.array([0.2, 0.3, 0.5])
    means, covariances = [], []
    for component in range(3):
        shift = component * 3.0
        means.append([shift * (1.0 if axis % 2 == 0 else -0.5) for axis in range(DIMENSION)])
        covariance = np.diag([0.5 + 0.1 * axis for axis in range(DIMENSION)])
        covariance[0, 1] = covariance[1, 0] = 0.2
        covariances.append(covariance)
    labels = generator.choice(3, size=POINTS, p=weights)
    return np.array([generator.multivariate_normal(means[label], covariances[label]) for label in labels])


def select(data, seed):
    best = None
    for components in range(1, 5):
        model = GaussianMixture(
            n_components=components,
            covariance_type="full",
            tol=1e-3,
            reg_covar=1e-6,
            max_iter=100,
            n_init=1,
            init_params="kmeans",
            random_state=seed,
        ).fit(data)
        bic = model.bic(data)
        if best is None or bic < best[0]:
            best = (bic, components)
    return best


def main():
    data = source_points(np.random.default_rng(1))
    select(data, 0)
    times = []
    for repetition in range(10):
        start = time.perf_counter()
        bic, components = select(data, repetition)
        times.append(time.perf_counter() - start)
    print(f"scikit-learn fit, BIC k=1..4, {POINTS}x{DIMENSION}: median {np.median(times) * 1e3:.1f} ms (chose k={components})")
    try:
        from threadpoolctl import threadpool_info
    except ImportError:
        return
    pools = sorted({(pool["user_api"], pool["internal_api"], pool["num_threads"]) for pool in threadpool_info()})
    print("thread pools: " + ", ".join(f"{api} ({library}) {threads} threads" for api, library, threads in pools))


if __name__ == "__main__":
    main()
