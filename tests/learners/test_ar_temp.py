"""ar-temp (seed 004 Eqs. 30-34). Known answer: on data generated from the seed's fitted model,
the refit recovers C0 = 194.83, Cs = -1.762, phi_1 = 0.213, sigma_a^2 = 1.379 and so Eq. (34),
x(t) = 153.33 + 0.213 x(t-1) - 1.762 T_t + 0.375 T_(t-1), and reproduces its predictions."""

import numpy as np
import pytest
import scipy.signal

from learners.ar_temp import ARTemp

C0, CS, PHI, SIGMA2 = 194.83, -1.762, 0.213, 1.379


def _seed_process(n, seed=0):
    rng = np.random.default_rng(seed)
    k = np.arange(n)
    T = 23.0 + 15.0 * (1.0 - np.exp(-k / 400.0)) + 2.0 * np.sin(k / 37.0) + 0.5 * rng.normal(size=n)
    r = scipy.signal.lfilter([1.0], [1.0, -PHI], rng.normal(scale=np.sqrt(SIGMA2), size=n))  # r_t = phi r_t-1 + a_t
    return T[:, None], C0 + CS * T + r


def _hand_series():
    """x = 1..5, y = 3 + 2x + r with r = (1, -1, 0, -1, 1), orthogonal to 1 and x: r is the OLS residual."""
    x = np.arange(1.0, 6.0)
    return x[:, None], 3.0 + 2.0 * x + np.array([1.0, -1.0, 0.0, -1.0, 1.0])


def test_recovers_seed_004_equation_34():
    X, y = _seed_process(50000)
    m = ARTemp().fit(X, y)
    assert m.intercept_ == pytest.approx(C0, abs=0.3)
    assert m.coef_[0] == pytest.approx(CS, abs=0.01)
    assert m.phi_ == pytest.approx(PHI, abs=0.02)
    assert m.innovation_variance_ == pytest.approx(SIGMA2, rel=0.05)
    # Eq. (34) coefficients: C0(1 - phi) = 153.33, phi = 0.213, Cs = -1.762, -phi Cs = 0.375
    assert m.arx_intercept_ == pytest.approx(153.33, abs=2.0)   # C0 (1 - phi): phi's sampling sd ~0.0045 x 195
    assert m.arx_temp_coef_[0] == pytest.approx(-1.762, abs=0.01)
    assert m.arx_temp_lag_coef_[0] == pytest.approx(0.375, abs=0.04)


def test_one_step_predictions_match_seed_equation_34():
    X, y = _seed_process(50000)
    m = ARTemp().fit(X, y)
    T = X[:, 0]
    eq34 = 153.33 + 0.213 * y[:-1] - 1.762 * T[1:] + 0.375 * T[:-1]
    ours = m.predict_one_step(X, y)[1:]
    assert np.sqrt(np.mean((ours - eq34) ** 2)) < 0.05          # um, vs innovation sd 1.17 um
    # and they forecast better than the regression alone (the AR(1) term carries information)
    trend = m.intercept_ + X @ m.coef_
    assert np.mean((ours - y[1:]) ** 2) < np.mean((trend[1:] - y[1:]) ** 2)


def test_free_run_is_the_recursive_equation_34():
    # predict() iterates Eq. (34) with x^ in place of x, from r^_0 = last training residual.
    X, y = _seed_process(300, seed=1)
    m = ARTemp(initial_residual="last").fit(X[:200], y[:200])
    Xt = X[200:]
    prev_x, prev_T = y[199], X[199]   # the measured last training sample starts the recursion
    expect = []
    for row in Xt:
        x = m.arx_intercept_ + m.arx_lag_coef_ * prev_x + row @ m.arx_temp_coef_ + prev_T @ m.arx_temp_lag_coef_
        expect.append(x)
        prev_x, prev_T = x, row
    assert np.allclose(m.predict(Xt), expect)
    # hand series (see _hand_series): C0 = 3, Cs = 2, phi = -0.5, r_5 = 1, so Eq. (34) reads
    # x_t = 4.5 - 0.5 x_{t-1} + 2 T_t + T_{t-1} from x_5 = 14, T_5 = 5: x_6 = 14.5, x_7 = 17.25
    X5, y5 = _hand_series()
    h = ARTemp(initial_residual="last").fit(X5, y5)
    np.testing.assert_allclose(h.predict([[6.0], [7.0]]), [14.5, 17.25], rtol=0, atol=1e-12)
    # default "zero": the forecast is the temperature regression itself
    z = ARTemp().fit(X[:200], y[:200])
    assert np.allclose(z.predict(Xt), z.intercept_ + Xt @ z.coef_)


def test_yule_walker_on_hand_series():
    """Yule-Walker with divisor n (module docstring): gamma(k) = sum_t r_t r_{t-k} / n, phi_1 = gamma(1) / gamma(0),
    sigma_a^2 = gamma(0) (1 - phi_1^2).

    r = (1, -1, 0, -1, 1): gamma(0) = 4/5 = 0.8, gamma(1) = (-1 + 0 + 0 - 1)/5 = -0.4, phi_1 = -0.5,
    sigma_a^2 = 0.8 * 0.75 = 0.6; C0 = 3, Cs = 2, r_n = 1.
    """
    m = ARTemp().fit(*_hand_series())
    assert m.intercept_ == pytest.approx(3.0, abs=1e-12)
    assert m.coef_[0] == pytest.approx(2.0, abs=1e-12)
    assert m.phi_ == pytest.approx(-0.5, abs=1e-12)
    assert m.innovation_variance_ == pytest.approx(0.6, abs=1e-12)
    assert m.last_residual_ == pytest.approx(1.0, abs=1e-12)


def test_rss_bookkeeping():
    X, y = _seed_process(500, seed=2)
    m = ARTemp().fit(X, y)
    assert m.rss_ar_ < m.rss_regression_    # seed: 61.56 < 67.21


def test_rss_of_the_hand_series():
    """On the hand series (r = (1, -1, 0, -1, 1), phi = -0.5): the regression's RSS is sum r^2 = 4,
    the AR(1)'s is the sum of the innovations a_t = r_t - phi r_(t-1) = (-.5, -.5, -1, .5)
    squared, 1.75."""
    m = ARTemp().fit(*_hand_series())
    assert m.rss_regression_ == pytest.approx(4.0, abs=1e-12)
    assert m.rss_ar_ == pytest.approx(1.75, abs=1e-12)
