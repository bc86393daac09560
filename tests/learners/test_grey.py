"""Grey models against closed forms and data generated from their own equations."""

import numpy as np
import pytest

from learners.gnnmci import GNNMCI, gnnmci_forward
from learners.grey import GM11, GM1N, ago, background, gm0n_coefficients, gm11_fit, gm11_forecast, iago
from learners.grey_gmc import GMC1N, GMC1NPSO, gmc_ls_fit, gmc_simulate
from twin.errors import InputError

N = 40
T = np.arange(N)


def drivers(seed=0, n=N):
    """Two smooth temperature-rise series (°C), a heating curve and a slower wavy one."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    return np.column_stack([2.0 * (1 - np.exp(-t / 10)) + 0.05 * rng.standard_normal(n),
                            1.5 * (1 - np.exp(-t / 25)) + 0.3 * np.sin(t / 5)])


def test_ago_iago_roundtrip_and_background():
    x = np.array([1.0, 2.0, 4.0, 3.0])
    np.testing.assert_array_equal(ago(x), [1, 3, 7, 10])
    np.testing.assert_array_equal(iago(ago(x)), x)
    np.testing.assert_array_equal(background(ago(x)), [2.0, 5.0, 8.5])


def test_gm0n_recovers_its_own_equation():
    # Build y so that z_1^(1)(k) = sum_j theta_j x_j^(1)(k) holds exactly for k = 2..n.
    rng = np.random.default_rng(1)
    X = rng.uniform(0.5, 2.0, (30, 3))
    theta = np.array([1.5, -0.7, 2.0])
    z1 = ago(X)[1:] @ theta
    Y = np.empty(30)
    Y[0] = 0.8
    for k in range(1, 30):
        Y[k] = 2.0 * z1[k - 1] - Y[k - 1]  # z(k) = (Y(k-1) + Y(k)) / 2
    np.testing.assert_allclose(gm0n_coefficients(X, iago(Y)), theta, rtol=1e-9)


def test_gm11_exact_least_squares_on_geometric_series():
    # x(k) = c r^(k-1) satisfies x(k) + a z(k) = b exactly with a = 2(1-r)/(1+r), b = 2c/(1+r).
    c, r = 3.0, 1.08
    x = c * r ** np.arange(12)
    a, b = gm11_fit(x)
    assert a == pytest.approx(2 * (1 - r) / (1 + r), rel=1e-10)
    assert b == pytest.approx(2 * c / (1 + r), rel=1e-10)


def test_gm11_forecasts_its_whitened_solution():
    # Series from the whitened solution x1(k) = (x(1) - b/a) e^{-a(k-1)} + b/a, a = -0.05, b = 2.
    # LS estimates 2 tanh(a/2) instead of a (relative bias a^2/12 ~ 2e-4), so: tolerance 1e-3.
    a, b, first = -0.05, 2.0, 2.0
    k = np.arange(1, 21)
    x1 = (first - b / a) * np.exp(-a * (k - 1)) + b / a
    x0 = iago(x1)
    est_a, est_b = gm11_fit(x0[:15])
    assert est_a == pytest.approx(2 * np.tanh(a / 2), rel=1e-9)  # closed form of the LS estimate
    np.testing.assert_allclose(gm11_forecast(x0[:15], 5), x0[15:], rtol=1e-3)
    model = GM11().fit(np.zeros((15, 1)), x0[:15])
    np.testing.assert_allclose(model.forecast(5), x0[15:], rtol=1e-3)
    np.testing.assert_allclose(model.predict(np.zeros((20, 1))), x0, rtol=1e-3)


def gm1n_data(a, b, y0, X):
    """Response solving x_1^(0)(k) + a z_1^(1)(k) = sum_j b_j x_j^(1)(k) exactly."""
    drive = ago(X) @ b
    x1 = np.empty(len(X))
    x1[0] = y0
    for k in range(1, len(X)):
        x1[k] = ((1 - a / 2) * x1[k - 1] + drive[k]) / (1 + a / 2)
    return iago(x1)


def test_gm1n_recovers_coefficients_and_reproduces_data():
    X = drivers()
    y = gm1n_data(0.4, np.array([0.9, -0.3]), 0.1, X)
    model = GM1N(fit_method="equation").fit(X, y)
    assert model.a_ == pytest.approx(0.4, abs=1e-10)
    np.testing.assert_allclose(model.b_, [0.9, -0.3], atol=1e-10)
    np.testing.assert_allclose(model.predict(X), y, atol=1e-10)
    response = GM1N().fit(X, y)  # default: least squares of the simulated response
    assert response.a_ == pytest.approx(0.4, abs=1e-6)
    np.testing.assert_allclose(response.b_, [0.9, -0.3], atol=1e-6)
    np.testing.assert_allclose(response.predict(X), y, atol=1e-6)
    whitened = GM1N(response="whitened").fit(X, y).predict(X)
    assert whitened.shape == (N,) and whitened[0] == pytest.approx(0.1)


def gmc_difference_data(b1, b, u, y0, X):
    """Response solving the GMC least-squares equation exactly (trapezoidal drivers + u)."""
    return gmc_simulate(b1, b, u, ago(X), y0, response="difference")


def test_gmc1n_least_squares_recovers_coefficients():
    X = drivers()
    y = gmc_difference_data(0.3, np.array([0.8, -0.5]), 0.05, 0.2, X)
    b1, b, u = gmc_ls_fit(X, y)
    assert b1 == pytest.approx(0.3, abs=1e-10) and u == pytest.approx(0.05, abs=1e-10)
    np.testing.assert_allclose(b, [0.8, -0.5], atol=1e-10)
    model = GMC1N(response="difference", fit_method="equation").fit(X, y)
    np.testing.assert_allclose(model.predict(X), y, atol=1e-10)
    response = GMC1N(response="difference").fit(X, y)
    np.testing.assert_allclose(np.r_[response.b1_, response.b_, response.u_], [0.3, 0.8, -0.5, 0.05], atol=1e-6)
    np.testing.assert_allclose(response.predict(X), y, atol=1e-6)


def test_gmc1n_convolution_response_close_to_ls_equation():
    # Tien's convolution response differs from the LS equation by O(b1^2): 0.3^2/8 ~ 1 % here.
    X = drivers()
    y = gmc_simulate(0.3, np.array([0.8, -0.5]), 0.05, ago(X), 0.2)
    model = GMC1N().fit(X, y)
    np.testing.assert_allclose(model.b_, [0.8, -0.5], rtol=0.03)
    assert np.max(np.abs(model.predict(X) - y)) < 0.02 * np.max(np.abs(y))


def test_gmc1n_pso_reaches_least_squares_solution():
    # On data from the LS equation, PSO (constriction, 90 particles, 300 iterations) must land
    # within 0.01 of the LS coefficients (which are exact here).
    X = drivers()
    y = gmc_difference_data(0.3, np.array([0.8, -0.5]), 0.05, 0.2, X)
    ls = GMC1N(response="difference").fit(X, y)
    pso = GMC1NPSO(response="difference", variant="constriction", n_iterations=300, random_state=0).fit(X, y)
    np.testing.assert_allclose(np.r_[pso.b1_, pso.b_, pso.u_], np.r_[ls.b1_, ls.b_, ls.u_], atol=0.01)
    assert np.max(np.abs(pso.predict(X) - y)) < 0.01 * np.max(np.abs(y))


def test_gnnmci_network_identity_and_fit():
    X = np.column_stack([drivers(), np.linspace(0, 1, N) ** 2])
    w11, w2, w2u, y0 = 0.2, np.array([1.5, -0.8, 0.3]), 0.1, 0.5
    out = gnnmci_forward(w11, w2, w2u, ago(X), y0)
    # Layers A-D collapse to x1(1) e^{-w11 k} + sum_j w2j x_j^(1) + w2u (k >= 1); x1(1) at k = 0.
    np.testing.assert_allclose(out[1:], (y0 * np.exp(-w11 * T) + ago(X) @ w2 + w2u)[1:], atol=1e-12)
    assert out[0] == y0
    y = iago(out)
    model = GNNMCI(n_iterations=200, random_state=0).fit(X, y)
    np.testing.assert_allclose(model.w2_, w2, atol=0.01)
    assert np.max(np.abs(model.predict(X) - y)) < 1e-3 * np.max(np.abs(y))


@pytest.mark.parametrize("cls", [GM11, GM1N, GMC1N, GMC1NPSO, GNNMCI])
def test_too_few_rows_is_input_error(cls):
    with pytest.raises(InputError, match="rows"):
        cls().fit(np.ones((2, 1)), np.ones(2))


def test_wrong_width_at_predict():
    X = drivers()
    model = GM1N().fit(X, gm1n_data(0.4, np.array([0.9, -0.3]), 0.1, X))
    with pytest.raises(InputError):
        model.predict(X[:, :1])


def test_unfitted_and_bad_response():
    with pytest.raises(InputError, match="not fitted"):
        GM1N().predict(drivers())
    with pytest.raises(InputError, match="not fitted"):
        GM11().predict(np.zeros((3, 1)))
    X = drivers()
    with pytest.raises(InputError, match="response"):
        GM1N(response="nope").fit(X, X[:, 0])
    with pytest.raises(InputError, match="response"):
        GMC1N(response="nope").fit(X, X[:, 0])


def _lag(x, tau):
    from scipy.signal import lfilter

    return lfilter([1 / tau], [1, -(1 - 1 / tau)], x)


def long_record(n=1141, seed=0):
    """A seed-001-like record: 1141 samples of a 63 % heating / cooling run, three measured temperature
    rises (lags 40-400 samples, noisy, 1/16 degC quantised) and a drift that also depends on an
    unmeasured fast temperature (lag 15), so no grey model fits it exactly."""
    t = np.arange(n, dtype=float)
    p = (t < 0.63 * n).astype(float)
    T1, T2, T3 = 6 * _lag(p, 120), 3 * _lag(_lag(p, 200), 200), 9 * _lag(p, 40)
    y = -2.0 * T1 + 1.5 * T2 - 1.2 * T3 - 12.0 * _lag(p, 15)
    rng = np.random.default_rng(seed)
    X = np.round((np.column_stack([T1, T2, T3]) + 0.03 * rng.standard_normal((n, 3))) * 16) / 16
    return X, y


def test_long_record_equation_fit_diverges_and_is_refused():
    """The divergence of the study (1e14-1e26 um): the equation LS picks a < 0 on a long smooth record."""
    from learners.grey import gm1n_simulate

    X, y = long_record()
    z1 = background(ago(y))
    theta, *_ = np.linalg.lstsq(np.column_stack([-z1, ago(X)[1:]]), y[1:], rcond=None)
    assert theta[0] < -0.05  # unstable development coefficient
    with np.errstate(over="ignore", invalid="ignore"):
        raw = gm1n_simulate(theta[0], theta[1:], ago(X), y[0])
    assert not np.all(np.abs(raw) < 1e6)  # what the old estimator returned
    b1, *_ = gmc_ls_fit(X, y)
    assert b1 < 0 and np.exp(-b1 * (len(y) - 1)) > 1e20
    with pytest.raises(InputError, match="unstable"):
        GM1N(fit_method="equation").fit(X, y)
    with pytest.raises(InputError, match="unstable"):
        GMC1N(fit_method="equation").fit(X, y)


@pytest.mark.parametrize("model", [GM1N(), GM1N(response="whitened"), GMC1N(), GMC1N(response="difference")],
                         ids=["gm1n", "gm1n-whitened", "gmc1n", "gmc1n-difference"])
def test_long_record_response_fit_is_stable_and_close(model):
    X, y = long_record()
    model.fit(X, y)
    a = getattr(model, "a_", getattr(model, "b1_", None))
    assert a >= 0.0
    for Xp, yp in ((X, y), long_record(seed=1)):
        pred = model.predict(Xp)
        assert np.all(np.isfinite(pred))
        assert np.sqrt(np.mean((pred - yp) ** 2)) < 0.05 * np.ptp(yp)  # ~0.7 um of a 33 um range


def test_a_development_coefficient_pinned_at_its_search_range_is_reported():
    """The response fit searches a in [1e-6, a_max] per sample; a value at either end is pinned, not
    fitted, and ``at_bound_`` says which end ('' inside the range)."""
    from learners import make_learner
    from learners.grey import A_MIN, search_bound

    assert search_bound(A_MIN, 20.0).startswith("at the search range's lower end")
    assert search_bound(20.0, 20.0).startswith("at the search range's upper end")
    assert search_bound(0.05, 20.0) == ""
    t = np.arange(40.0)
    X = np.column_stack([1.0 + 0.1 * t, 2.0 + 0.05 * t])
    y = 3.0 * (1.0 - np.exp(-0.1 * t)) + 0.01 * t
    for name in ("gm1n", "gmc1n"):
        model = make_learner(name).fit(X, y)
        assert isinstance(model.at_bound_, str)


@pytest.mark.parametrize("alpha", [1e-5, 0.1])
def test_gm0n_ridge_is_the_normal_equations_with_lambda_alpha_trace_over_p(alpha):
    """GM(0,N) with a ridge term: theta = (B^T B + lambda I)^-1 B^T z, lambda = alpha trace(B^T B) / p,
    B rows [x_2^(1)(k) .. x_N^(1)(k)] and z(k) = (x_1^(1)(k-1) + x_1^(1)(k)) / 2 for k = 2..n (AGO by
    cumulative sums, written out here); alpha = 1e-5 is GreySelection's default. To round-off."""
    rng = np.random.default_rng(7)
    X = rng.uniform(0.5, 2.0, (25, 3))
    y = rng.uniform(-1.0, 3.0, 25)
    B = np.cumsum(X, axis=0)[1:]
    y1 = np.cumsum(y)
    z = 0.5 * (y1[:-1] + y1[1:])
    gram = B.T @ B
    lam = alpha * np.trace(gram) / 3
    expected = np.linalg.solve(gram + lam * np.eye(3), B.T @ z)
    np.testing.assert_allclose(gm0n_coefficients(X, y, alpha=alpha), expected, rtol=1e-12)
    assert not np.allclose(expected, np.linalg.lstsq(B, z, rcond=None)[0], rtol=1e-9, atol=0)  # the ridge acts


def test_gmc1n_convolution_response_is_tiens_sum():
    """Tien's GMC(1,N) response, summed term by term: f(k) = sum_j b_j x_j^(1)(k) + u on the AGO
    drivers, x_1^(1)(k) = x_1^(1)(1) e^{-b1 (k-1)} + sum_{tau=2..k} e^{-b1 (k - tau + 1/2)}
    (f(tau) + f(tau-1)) / 2 with x_1^(1)(1) = y0, then IAGO x_1^(0)(k) = x_1^(1)(k) - x_1^(1)(k-1).
    To round-off."""
    b1, b, u, y0 = 0.3, np.array([0.8, -0.5]), 0.05, 0.2
    X1 = np.cumsum(drivers(), axis=0)
    f = X1 @ b + u
    x1 = np.empty(N)
    for k in range(1, N + 1):                        # k, tau: 1-based sample numbers
        x1[k - 1] = y0 * np.exp(-b1 * (k - 1)) + sum(np.exp(-b1 * (k - tau + 0.5)) * (f[tau - 1] + f[tau - 2]) / 2
                                                     for tau in range(2, k + 1))
    expected = np.r_[x1[0], x1[1:] - x1[:-1]]
    np.testing.assert_allclose(gmc_simulate(b1, b, u, X1, y0), expected, rtol=1e-12)
