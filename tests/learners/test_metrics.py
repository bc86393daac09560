"""Metrics against hand-computed values."""

import math

import numpy as np
import pytest

from learners import metrics

Z = np.array([1.0, 2.0, 3.0, 4.0])  # measured thermal error
P = np.array([1.0, 3.0, 3.0, 2.0])  # prediction; residuals Z-P = 0, -1, 0, 2


def test_hand_values():
    # RMSE = sqrt((0 + 1 + 0 + 4) / 4) = sqrt(1.25)
    assert metrics.rmse(Z, P) == pytest.approx(math.sqrt(1.25))
    # NSE = 1 - 5 / sum((Z - 2.5)^2) = 1 - 5/5 = 0
    assert metrics.nse(Z, P) == pytest.approx(0.0)
    # R: dz = (-1.5,-.5,.5,1.5), dp = (-1.25,.75,.75,-.25); sum dz dp = 1.5; |dz|^2 = 5; |dp|^2 = 2.75
    assert metrics.correlation(Z, P) == pytest.approx(1.5 / math.sqrt(5 * 2.75))
    assert metrics.max_abs_residual(Z, P) == 2.0
    # improvement = 100 * (1 - 2/4) = 50 %
    assert metrics.improvement(Z, P) == pytest.approx(50.0)
    # MRE = 100/4 * (0 + 1/2 + 0 + 2/4) = 25 %
    assert metrics.mean_relative_error(Z, P) == pytest.approx(25.0)


def test_thesis_improvement_check():
    # thesis: +-4 um residual against a 64 um error gives 93.75 % ("up to 94 %")
    z = np.array([0.0, 32.0, 64.0])
    p = z + np.array([0.0, 4.0, -4.0])
    assert metrics.improvement(z, p) == pytest.approx(93.75)


def test_perfect_prediction_and_score_all_keys():
    s = metrics.score_all(Z, Z)
    assert set(s) == {"rmse", "nse", "r", "max_abs_residual", "improvement_pct", "mre_pct"}
    assert s["rmse"] == 0 and s["nse"] == 1 and s["r"] == pytest.approx(1) and s["improvement_pct"] == 100
    assert s["mre_pct"] == 0


def test_mre_skips_zero_drift_and_degenerate_cases():
    # Z = 0 sample is left out: only |3-2|/2 counts -> 50 %
    assert metrics.mean_relative_error([0.0, 2.0], [1.0, 3.0]) == pytest.approx(50.0)
    assert math.isnan(metrics.nse([1.0, 1.0], [1.0, 2.0]))
    assert math.isnan(metrics.correlation([1.0, 2.0], [3.0, 3.0]))
    with pytest.raises(ValueError):
        metrics.rmse([1.0, 2.0], [1.0])


def test_score_all_maps_each_key_to_its_metric():
    """score_all on Z = (1, 2, 3, 4), P = (1, 3, 3, 2), each key by hand: residuals (0, 1, 0, -2),
    RMSE sqrt(5/4); NSE 1 - 5 / 5 = 0; r = cov / (sd sd) = 1.5 / sqrt(5 x 2.75); max |residual| 2;
    improvement 100 (1 - max|e| / max|Z|) = 50 %; MRE mean of |e| / |Z| = (0 + 1/2 + 0 + 2/4) / 4 =
    25 % (a perfect prediction, the test above, cannot tell a key given the wrong metric, since
    NSE = r = 1 there)."""
    Z, P = np.array([1.0, 2.0, 3.0, 4.0]), np.array([1.0, 3.0, 3.0, 2.0])
    s = metrics.score_all(Z, P)
    assert s["nse"] == pytest.approx(0.0, abs=1e-12)
    assert s["r"] == pytest.approx(1.5 / math.sqrt(5 * 2.75), rel=1e-12)
    assert s["rmse"] == pytest.approx(math.sqrt(1.25), rel=1e-12) and s["max_abs_residual"] == 2.0
    assert s["improvement_pct"] == pytest.approx(50.0, rel=1e-12)
    assert s["mre_pct"] == pytest.approx(25.0, rel=1e-12)
