"""MLR and PCR (seed 003). Known answers: PCR with every component equals OLS; ridge -> OLS as alpha -> 0."""

import numpy as np
import pytest

from learners.linear import MLR, PCR


def _data(n=60, seed=0):
    rng = np.random.default_rng(seed)
    base = rng.normal(size=(n, 1))
    X = 20.0 + np.hstack([base + 0.1 * rng.normal(size=(n, 1)) for _ in range(4)]) * [1.0, 2.0, 0.5, 3.0]
    y = 1.5 * X[:, 0] - 0.7 * X[:, 2] + 0.2 * X[:, 3] + 4.0 + 0.05 * rng.normal(size=n)
    return X, y


def test_mlr_recovers_exact_linear_law():
    # Known answer: noise-free y = 3 + 2 x0 - x1 is recovered exactly by OLS.
    rng = np.random.default_rng(1)
    X = rng.normal(size=(20, 2))
    y = 3.0 + 2.0 * X[:, 0] - X[:, 1]
    m = MLR().fit(X, y)
    assert np.allclose(m.coef_, [2.0, -1.0], rtol=1e-12, atol=1e-12) and np.isclose(m.intercept_, 3.0, rtol=1e-12)
    assert np.allclose(m.predict(X), y, rtol=1e-12, atol=1e-12)


def test_ridge_shrinks_and_tends_to_ols():
    X, y = _data()
    ols = MLR().fit(X, y)
    assert np.allclose(MLR(alpha=1e-10).fit(X, y).coef_, ols.coef_, atol=1e-5)
    ridge = MLR(alpha=10.0).fit(X, y)
    assert np.linalg.norm(ridge.coef_) < np.linalg.norm(ols.coef_)


def test_pcr_with_all_components_equals_ols():
    # Known answer: keeping every principal component spans the full input space, so PCR == OLS.
    X, y = _data()
    pcr = PCR(n_components=X.shape[1]).fit(X, y)
    ols = MLR().fit(X, y)
    assert np.allclose(pcr.coef_, ols.coef_, rtol=1e-10, atol=1e-10)
    assert np.isclose(pcr.intercept_, ols.intercept_, rtol=1e-10)
    assert np.allclose(pcr.predict(X), ols.predict(X), rtol=1e-10, atol=1e-10)


def test_pcr_variance_fraction_keeps_first_component_for_collinear_sensors():
    # Seed 003 keeps PC1 only (92.9 % > 85 %) for highly correlated temperatures.
    X, y = _data()
    pcr = PCR().fit(X, y)
    assert pcr.n_components_ == 1
    assert pcr.explained_variance_ratio_[0] > 0.85
    assert np.isclose(pcr.explained_variance_.sum(), X.shape[1])  # trace of a correlation matrix
    # raw-unit equation (seed 003 Eq. 15) reproduces predictions made through the component scores
    scores = pcr.transform_scores(X)
    assert np.allclose(pcr.predict(X), y.mean() + scores @ pcr.score_coef_)


def test_pcr_rejects_bad_fraction():
    X, y = _data()
    with pytest.raises(ValueError):
        PCR(n_components=1.5).fit(X, y)


def test_ridge_one_feature_closed_form():
    """Ridge on one centred feature, min ||yc - b xc||^2 + alpha b^2: b = Sxy / (Sxx + alpha), b0 = ybar - b xbar.

    x = (-1, 0, 1), y = 2x + 5, alpha = 2: Sxx = 2, Sxy = 4, so b = 4 / 4 = 1 and b0 = 5.
    """
    x = np.array([-1.0, 0.0, 1.0])
    m = MLR(alpha=2.0).fit(x[:, None], 2.0 * x + 5.0)
    assert m.coef_[0] == pytest.approx(1.0, abs=1e-12)
    assert m.intercept_ == pytest.approx(5.0, abs=1e-12)


def test_pcr_scores_new_rows_with_the_training_mean_and_standard_deviation():
    """PCR's scores of new rows: t = ((x - mean_train) / sd_train(ddof 1)) V^T, and the prediction
    mean(y_train) + t beta, on rows shifted 3 units away from the training set (scaling them by
    their own statistics would give other scores)."""
    rng = np.random.default_rng(0)
    X = 20 + rng.normal(size=(40, 3)) * [1.0, 2.0, 0.5]
    y = X @ [1.0, -0.5, 2.0]
    pcr = PCR(n_components=2).fit(X, y)
    new = X[:10] + 3.0
    expect = ((new - X.mean(axis=0)) / X.std(axis=0, ddof=1)) @ pcr.components_.T
    np.testing.assert_allclose(pcr.transform_scores(new), expect, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(pcr.predict(new), y.mean() + expect @ pcr.score_coef_, rtol=1e-12)
