"""LS-SVM (seed 004 Eqs. 4-6). Known answer: the fit equals a direct dense solve of its KKT system."""

import numpy as np

from learners.lssvm import LSSVM


def _data(n=40, seed=0):
    rng = np.random.default_rng(seed)
    X = 23.0 + 10.0 * rng.random((n, 2))
    y = 30.0 * np.sin(X[:, 0] / 5.0) - 1.7 * X[:, 1] + rng.normal(scale=0.3, size=n)
    return X, y


def test_lssvm_equals_direct_dense_kkt_solve():
    # Known answer: [[0, 1^T], [1, Omega + I/gamma]] [b; a] = [0; y] solved with numpy directly.
    X, y = _data()
    gamma, sigma = 56.2, np.sqrt(71.4)
    m = LSSVM(gamma=gamma, sigma=sigma).fit(X, y)
    n = len(y)
    omega = np.array([[np.exp(-np.sum((X[i] - X[j]) ** 2) / (2 * sigma ** 2)) for j in range(n)] for i in range(n)])
    A = np.zeros((n + 1, n + 1))
    A[0, 1:] = 1.0
    A[1:, 0] = 1.0
    A[1:, 1:] = omega + np.eye(n) / gamma
    sol = np.linalg.solve(A, np.concatenate([[0.0], y]))
    assert np.isclose(m.intercept_, sol[0], rtol=1e-9, atol=1e-9)
    assert np.allclose(m.dual_coef_, sol[1:], rtol=1e-8, atol=1e-9)
    assert abs(m.dual_coef_.sum()) < 1e-8 * np.abs(m.dual_coef_).sum()  # first KKT row: sum a_i = 0
    Xt = _data(5, seed=3)[0]
    k = np.exp(-((Xt[:, None, :] - X[None, :, :]) ** 2).sum(axis=2) / (2 * sigma ** 2))
    assert np.allclose(m.predict(Xt), k @ sol[1:] + sol[0])


def test_large_gamma_interpolates_training_data():
    X, y = _data()
    m = LSSVM(gamma=1e8, sigma=2.0).fit(X, y)
    assert np.max(np.abs(m.predict(X) - y)) < 1e-3


def test_thinning_keeps_max_samples():
    X, y = _data(100)
    m = LSSVM(max_samples=30).fit(X, y)
    assert m.n_support_ == 30
    assert m.predict(X).shape == (100,)
