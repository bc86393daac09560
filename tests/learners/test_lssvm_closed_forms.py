"""LS-SVM input standardisation pinned by an identity (mutation-testing follow-up)."""

import numpy as np

from learners.lssvm import LSSVM


def test_standardize_equals_raw_model_on_z_scores():
    """standardize=True is the raw-unit model on z = (x - mean) / sd (sd with ddof = 1), at fit *and*
    at predict: K(z, z_i) = exp(-||z - z_i||^2 / (2 sigma^2)) on the z-scored inputs."""
    rng = np.random.default_rng(2)
    X = np.column_stack([rng.uniform(20, 30, 25), rng.uniform(900, 1100, 25)])   # very different scales
    y = 0.5 * X[:, 0] + 0.01 * X[:, 1] + rng.normal(0, 0.1, 25)
    Xnew = np.column_stack([rng.uniform(20, 30, 7), rng.uniform(900, 1100, 7)])
    mean, sd = X.mean(axis=0), X.std(axis=0, ddof=1)
    scaled = LSSVM(gamma=10.0, sigma=1.5, standardize=True).fit(X, y)
    raw = LSSVM(gamma=10.0, sigma=1.5).fit((X - mean) / sd, y)
    np.testing.assert_allclose(scaled.predict(Xnew), raw.predict((Xnew - mean) / sd), rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(scaled.predict(X), raw.predict((X - mean) / sd), rtol=1e-10, atol=1e-10)
