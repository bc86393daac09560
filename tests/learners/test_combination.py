"""Variable-weight combination (seed 004 Sec. III). Known answers: the reduced OLS equals the
constrained least-squares formula Eq. (22); y = 0.3 x1 + 0.7 x2 gives alpha = 0.3 at every window;
weights sum to 1; the combination is no worse than the worse member on a seed-004-like warm-up."""

import numpy as np
import pytest
import scipy.signal
from sklearn.base import BaseEstimator, RegressorMixin

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


def _gm11_closed_form(seq, steps):
    """GM(1,1) written out: x1 = 1-AGO of x0, z(k) = (x1(k-1) + x1(k)) / 2, (a, b) the least squares
    of x0(k) = -a z(k) + b over k = 2..n (slope/intercept of the 2x2 normal equations), and the
    forecast x0(k) = (1 - e^a) (x0(1) - b/a) e^(-a (k-1)) for k = n+1..n+steps."""
    x0 = np.asarray(seq, dtype=float)
    n = x0.size
    x1 = np.cumsum(x0)
    z, Y = 0.5 * (x1[1:] + x1[:-1]), x0[1:]
    m = n - 1
    a = -(m * np.sum(z * Y) - np.sum(z) * np.sum(Y)) / (m * np.sum(z * z) - np.sum(z) ** 2)
    b = (np.sum(Y) + a * np.sum(z)) / m
    k = np.arange(n + 1, n + steps + 1)
    return (1.0 - np.exp(a)) * (x0[0] - b / a) * np.exp(-a * (k - 1))


def test_weight_forecast_is_the_gm11_forecast_of_the_next_steps():
    """_weight_forecast(seq, 4) = the GM(1,1) values x0(n+1..n+4) =
    (1 - e^a) (x0(1) - b/a) e^(-a (k-1)), (a, b) the LS fit of x0(k) + a z(k) = b (written out in
    _gm11_closed_form); also what learners.grey.gm11_forecast returns. Rounding only: rel 1e-12."""
    from learners.combination import _weight_forecast
    from learners.grey import gm11_forecast

    seq = [0.61, 0.63, 0.62, 0.66, 0.67, 0.69, 0.70]
    exact = _gm11_closed_form(seq, 4)
    assert np.all((exact > 0.70) & (exact < 0.80))             # a rising sequence keeps rising
    np.testing.assert_allclose(_weight_forecast(seq, 4), exact, rtol=1e-12)
    np.testing.assert_allclose(gm11_forecast(seq, 4), exact, rtol=1e-12)


class _Column(RegressorMixin, BaseEstimator):
    """A member whose prediction is column ``j`` of X (no fitting): the members' outputs are known."""

    def __init__(self, j=0):
        self.j = j

    def fit(self, X, y):
        self.n_features_in_ = np.shape(X)[1]
        return self

    def predict(self, X):
        return np.asarray(X, dtype=float)[:, self.j]


def test_predicted_weights_are_the_clipped_gm11_forecast_of_the_training_weights():
    """predict_weights(X) for the m rows after the record: alpha = clip(GM(1,1) forecast of
    alpha_train_ (x0(n+1..n+m) = (1 - e^a) (x0(1) - b/a) e^(-a (k-1)), written out), 0, 1), beta =
    1 - alpha. The members output two columns and y = alpha(t) x1 + (1 - alpha(t)) x2 with
    alpha(t) = 0.55 + 0.004 t, so alpha_train_ rises inside (0, 1) and the 120-row forecast crosses
    1 (the clip bites at its end). Rounding only: rel 1e-12."""
    rng = np.random.default_rng(5)
    n, m = 30, 120
    X = rng.normal(20.0, 3.0, (n + m, 2))
    t = np.arange(1, n + m + 1)
    y = (0.55 + 0.004 * t) * X[:, 0] + (0.45 - 0.004 * t) * X[:, 1]
    c = Combination(members=(_Column(0), _Column(1))).fit(X[:n], y[:n])
    np.testing.assert_allclose(c.alpha_train_, 0.55 + 0.004 * np.arange(4, n + 1), rtol=1e-8)
    exact = np.clip(_gm11_closed_form(c.alpha_train_, m), 0.0, 1.0)
    assert exact[0] > 0.65 and exact[-1] == 1.0 and exact[0] < 1.0
    alpha, beta = c.predict_weights(X[n:])
    np.testing.assert_allclose(alpha, exact, rtol=1e-12)
    np.testing.assert_allclose(beta, 1.0 - exact, rtol=0, atol=1e-12)     # 1 - alpha: alpha's rounding


def test_predict_is_alpha_times_first_member_plus_beta_times_second():
    """predict = alpha x1 + beta x2 with x1 = X[:, 0], x2 = X[:, 1] (stub members) and y = x1: the
    constrained fit gives alpha = 1, beta = 0 at every window, so predict(X_test) = X_test[:, 0]
    (swapping the members' roles, beta x1 + alpha x2, would give X_test[:, 1])."""
    rng = np.random.default_rng(11)
    X = rng.normal(20.0, 3.0, (40, 2))
    c = Combination(members=(_Column(0), _Column(1))).fit(X[:30], X[:30, 0])
    np.testing.assert_allclose(c.alpha_train_, 1.0, atol=1e-9)
    np.testing.assert_allclose(c.predict(X[30:]), X[30:, 0], atol=1e-8)
