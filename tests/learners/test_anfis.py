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
