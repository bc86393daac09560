"""ANFIS (thesis seed 000 Sec. 3.11, seed 001). Known answer: both rule generators fit the smooth
nonlinear law y = sin(x1) cos(x2) on a 21 x 21 grid over [0, pi]^2 (std of y = 0.43) to a training
RMSE below 0.005 (grid, 3 MFs per input = 9 rules) and 0.01 (FCM, 9 rules)."""

import re

import numpy as np
import pytest

from learners.anfis import ANFISFCM, ANFISGrid
from twin.errors import InputError


def _grid_law():
    g = np.linspace(0.0, np.pi, 21)
    x1, x2 = np.meshgrid(g, g)
    X = np.column_stack([x1.ravel(), x2.ravel()])
    return X, np.sin(X[:, 0]) * np.cos(X[:, 1])


def _rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def test_anfis_grid_fits_sin_cos():
    X, y = _grid_law()
    m = ANFISGrid(n_mfs=3, epochs=30).fit(X, y)
    assert m.n_rules_ == 9
    assert _rmse(m.predict(X), y) < 0.005
    assert m.loss_curve_.min() == pytest.approx(_rmse(m.predict(X), y), rel=1e-6)  # best epoch kept


def test_anfis_fcm_fits_sin_cos_and_training_helps():
    X, y = _grid_law()
    m0 = ANFISFCM(n_rules=9, epochs=0, random_state=0).fit(X, y)
    m = ANFISFCM(n_rules=9, epochs=100, random_state=0).fit(X, y)
    assert m.n_rules_ == 9
    assert _rmse(m.predict(X), y) < 0.01
    assert _rmse(m.predict(X), y) < 0.5 * _rmse(m0.predict(X), y)   # the backward pass moves premises usefully
    assert np.array_equal(ANFISFCM(n_rules=9, epochs=100, random_state=0).fit(X, y).predict(X), m.predict(X))


def test_rules_text_is_readable_and_in_raw_units():
    rng = np.random.default_rng(0)
    X = np.column_stack([20 + 5 * rng.random(200), 30 + 2 * rng.random(200)])
    y = 2.0 * X[:, 0] - 3.0 * X[:, 1] + 7.0        # linear law: every rule's consequent is this plane
    m = ANFISFCM(n_rules=2, epochs=5, random_state=0).fit(X, y)
    text = m.rules_text(["T1", "T2"])
    lines = text.splitlines()
    assert len(lines) == 2
    assert re.match(r"Rule 1: IF T1 is near [-\d.e+]+ \(sigma [\d.e+-]+\) AND T2 is near .* THEN y = .*T1 .*T2 [+-] [\d.]+", lines[0])
    assert np.allclose(m.rule_coefs_, [[2.0, -3.0]] * 2, atol=1e-4)
    assert np.allclose(m.rule_intercepts_, 7.0, atol=1e-2)
    assert np.all((m.rule_centers_[:, 0] > 19) & (m.rule_centers_[:, 0] < 26))
    assert "x1" in m.rules_text()


def test_grid_refuses_rule_explosion():
    X = np.random.default_rng(0).random((50, 8))
    with pytest.raises(InputError):
        ANFISGrid(n_mfs=3).fit(X, X.sum(axis=1))


def test_premise_gradient_matches_finite_differences():
    """Jang's backward pass: the analytic premise gradient (consequents fixed) equals central differences."""
    from learners.anfis import _consequents, _normalise, _output, _premise_gradient, _premise_terms

    rng = np.random.default_rng(3)
    Z, t = rng.standard_normal((80, 2)), rng.standard_normal(80)
    C, S = rng.standard_normal((3, 2)), 0.5 + rng.random((3, 2))
    P = _consequents(Z, _normalise(_premise_terms(Z, C, S)), t)

    def mse(C_, S_):
        out, _ = _output(Z, _normalise(_premise_terms(Z, C_, S_)), P)
        return float(np.mean((out - t) ** 2))

    wbar = _normalise(_premise_terms(Z, C, S))
    out, F = _output(Z, wbar, P)
    gC, gS = _premise_gradient(Z, t, wbar, F, out, C, S)
    h = 1e-6
    for g, which in ((gC, 0), (gS, 1)):
        num = np.zeros_like(g)
        for idx in np.ndindex(g.shape):
            d = np.zeros_like(g)
            d[idx] = h
            args_p = (C + d, S) if which == 0 else (C, S + d)
            args_m = (C - d, S) if which == 0 else (C, S - d)
            num[idx] = (mse(*args_p) - mse(*args_m)) / (2 * h)
        np.testing.assert_allclose(g, num, rtol=1e-5, atol=1e-9)


def test_checking_data_keeps_the_epoch_of_least_checking_error():
    """validation_fraction holds out blocks of consecutive rows and keeps the best checking epoch (MATLAB anfis)."""
    from learners.anfis import _checking_rows

    mask = _checking_rows(100, 0.2, 10)
    assert mask.sum() == 20 and np.array_equal(np.flatnonzero(mask)[:10], np.arange(40, 50))
    X, y = _grid_law()
    y = y + 0.05 * np.random.default_rng(0).standard_normal(y.size)
    m = ANFISFCM(n_rules=9, epochs=40, validation_fraction=0.2, validation_block=21, random_state=0).fit(X, y)
    assert m.checking_curve_.shape == m.loss_curve_.shape
    assert m.best_epoch_ == int(np.argmin(m.checking_curve_))
    off = ANFISFCM(n_rules=9, epochs=40, random_state=0).fit(X, y)
    assert off.checking_curve_ is None and off.best_epoch_ == int(np.argmin(off.loss_curve_))
    with pytest.raises(ValueError):
        ANFISFCM(validation_fraction=0.9).fit(X, y)


def test_checking_blocks_shrink_on_short_records():
    from learners.anfis import _checking_rows

    mask = _checking_rows(51, 0.2, 30)  # 51 rows: blocks of 5, two checking blocks
    assert mask.sum() == 10 and np.array_equal(np.flatnonzero(mask), np.r_[20:25, 45:50])


def test_grid_neighbouring_mfs_cross_at_one_half():
    """Grid MFs: centres evenly spaced over the training range, sigma = spacing / (2 sqrt(2 ln 2)), so
    at the midpoint of two neighbouring centres exp(-(spacing/2)^2 / (2 sigma^2)) = 1/2 (epochs = 0: untrained)."""
    rng = np.random.default_rng(0)
    X = np.column_stack([20.0 + 5.0 * rng.random(20), 30.0 + 2.0 * rng.random(20)])
    m = ANFISGrid(n_mfs=3, epochs=0).fit(X, X[:, 0] - X[:, 1])
    for j in range(2):
        centres = np.unique(m.rule_centers_[:, j])
        np.testing.assert_allclose(centres, np.linspace(X[:, j].min(), X[:, j].max(), 3), rtol=0, atol=1e-12)
        sigma = m.rule_sigmas_[:, j]
        np.testing.assert_allclose(sigma, sigma[0], rtol=1e-15)
        half = (centres[1] - centres[0]) / 2.0
        assert np.exp(-half ** 2 / (2.0 * sigma[0] ** 2)) == pytest.approx(0.5, abs=1e-12)


def test_fcm_rule_widths_are_membership_weighted_spreads():
    """FCM rules (epochs = 0): sigma_rj = max(sqrt(sum_n u_nr^m (z_nj - c_rj)^2 / sum_n u_nr^m), 0.05) and
    c_rj = FCM centre, from fuzzy c-means on the z-scored (ddof 1) inputs and output."""
    from learners.fcm import fuzzy_cmeans

    rng = np.random.default_rng(1)
    X = np.column_stack([20.0 + 5.0 * rng.random(40), 30.0 + 2.0 * rng.random(40)])
    y = np.sin(X[:, 0]) + 0.1 * X[:, 1]
    fcm_m = 2.5
    m = ANFISFCM(n_rules=3, epochs=0, fcm_m=fcm_m, random_state=0).fit(X, y)
    Z = (X - X.mean(axis=0)) / X.std(axis=0, ddof=1)
    t = (y - y.mean()) / y.std(ddof=1)
    res = fuzzy_cmeans(np.column_stack([Z, t]), 3, m=fcm_m, random_state=0)
    um = res.membership ** fcm_m
    for j in range(2):
        c = res.centers[:, j]
        spread = np.sqrt(((Z[:, j, None] - c) ** 2 * um).sum(axis=0) / um.sum(axis=0))
        np.testing.assert_allclose(m.mf_centers_[j], c, rtol=0, atol=1e-12)
        np.testing.assert_allclose(m.mf_sigmas_[j], np.maximum(spread, 0.05), rtol=1e-12)


def test_anfis_trains_on_the_rows_outside_the_checking_blocks():
    """The checking split: loss_curve_ is the RMSE on the training rows and checking_curve_ on the
    checking rows (_checking_rows: blocks of 21 rows, 20 %); at best_epoch_, the kept model's, so
    both equal the returned model's RMSE on those rows (swapping the two sets trains on 20 %)."""
    from learners.anfis import _checking_rows
    g = np.linspace(0.0, np.pi, 21)
    x1, x2 = np.meshgrid(g, g)
    X = np.column_stack([x1.ravel(), x2.ravel()])
    y = np.sin(X[:, 0]) * np.cos(X[:, 1]) + 0.05 * np.random.default_rng(0).standard_normal(441)
    m = ANFISFCM(n_rules=9, epochs=10, validation_fraction=0.2, validation_block=21, random_state=0).fit(X, y)
    check = _checking_rows(len(y), 0.2, 21)
    assert 0 < check.sum() < len(y) / 2

    def rmse(rows):
        return np.sqrt(np.mean((m.predict(X[rows]) - y[rows]) ** 2))

    assert m.loss_curve_[m.best_epoch_] == pytest.approx(rmse(~check), rel=1e-9)
    assert m.checking_curve_[m.best_epoch_] == pytest.approx(rmse(check), rel=1e-9)
