"""Variable-weight combination (seed 004 Sec. III). Known answers: the reduced OLS equals the
constrained least-squares formula Eq. (22); y = 0.3 x1 + 0.7 x2 gives alpha = 0.3 at every window;
weights sum to 1; the combination is no worse than the worse member on a seed-004-like warm-up."""

import numpy as np
import pytest
import scipy.signal

from learners.combination import Combination, rolling_alpha, variable_weight_coefficients
from learners.linear import MLR


def test_reduced_form_equals_constrained_ls_eq22():
    rng = np.random.default_rng(0)
    n = 30
    x1, x2 = rng.normal(10, 3, n), rng.normal(10, 3, n)
    y = 0.6 * x1 + 0.4 * x2 + rng.normal(0, 0.5, n)
    t = np.arange(1, n + 1)
    P = np.column_stack([np.ones(n), t, t ** 2])
    K = np.hstack([x1[:, None] * P, x2[:, None] * P])            # Eq. (14)
    T0 = np.array([[1, 1, 1, 1, 1, 1], [1, 2, 4, 1, 2, 4], [1, 3, 9, 1, 3, 9]], float)   # Eq. (19)
    R3 = np.ones(3)
    KtK_inv = np.linalg.inv(K.T @ K)
    k_star = KtK_inv @ K.T @ y
    k_hat = k_star - KtK_inv @ T0.T @ np.linalg.solve(T0 @ KtK_inv @ T0.T, T0 @ k_star - R3)   # Eq. (22)
    alpha, beta = variable_weight_coefficients(y, x1, x2, degree=2)
    assert np.allclose(alpha, k_hat[:3], rtol=1e-6, atol=1e-9)
    assert np.allclose(beta, k_hat[3:], rtol=1e-6, atol=1e-9)
    assert np.allclose(P @ alpha + P @ beta, 1.0)               # alpha(t) + beta(t) = 1 for all t


def test_rolling_alpha_recovers_constant_weight():
    rng = np.random.default_rng(1)
    x1, x2 = rng.normal(size=50), rng.normal(size=50)
    alpha, start = rolling_alpha(0.3 * x1 + 0.7 * x2, x1, x2)
    assert start == 4 and len(alpha) == 47
    assert np.allclose(alpha, 0.3, atol=1e-8)


def _warm_up(n=60, seed=2):
    """Seed-004-like: 10-min samples of a spindle warm-up, x = 194.83 - 1.762 T + nonlinearity + AR(1)."""
    rng = np.random.default_rng(seed)
    k = np.arange(n)
    T = 23.0 + 15.0 * (1.0 - np.exp(-k / 12.0)) + 0.2 * rng.normal(size=n)
    r = scipy.signal.lfilter([1.0], [1.0, -0.213], rng.normal(scale=np.sqrt(1.379), size=n))
    return T[:, None], 194.83 - 1.762 * T + 3.0 * np.sin(T / 4.0) + r


def test_weights_sum_to_one_and_no_worse_than_worse_member():
    X, y = _warm_up()
    c = Combination(random_state=0).fit(X[:30], y[:30])
    alpha, beta = c.predict_weights(X[30:])
    assert np.allclose(alpha + beta, 1.0)
    assert np.all((alpha >= 0) & (alpha <= 1))
    rmse = lambda p: float(np.sqrt(np.mean((p - y[30:]) ** 2)))  # noqa: E731
    members = [rmse(e.predict(X[30:])) for e in c.estimators_]
    assert rmse(c.predict(X[30:])) <= max(members) + 1e-12
    # and the same with two complementary members given as estimators
    c2 = Combination(members=(MLR(), "lssvm")).fit(X[:30], y[:30])
    members2 = [rmse(e.predict(X[30:])) for e in c2.estimators_]
    assert rmse(c2.predict(X[30:])) <= max(members2) + 1e-12


def test_needs_two_members():
    X, y = _warm_up()
    with pytest.raises(ValueError):
        Combination(members=("mlr",)).fit(X, y)
