"""Metrics pinned by hand-computed values on signed residuals and negative errors (mutation follow-up)."""

import numpy as np
import pytest

from learners import metrics


def test_abs_residual_percentile_uses_absolute_residuals():
    """q-th percentile of |Z - P|: residuals (-10, 1, 2, 3, 4) -> |.| = (1, 2, 3, 4, 10), median 3,
    90th percentile (linear) 4 + 0.6 * 6 = 7.6, 100th = max |Z - P| = 10."""
    Z = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    P = Z - np.array([-10.0, 1.0, 2.0, 3.0, 4.0])
    assert metrics.abs_residual_percentile(Z, P, 50) == pytest.approx(3.0, abs=1e-12)
    assert metrics.abs_residual_percentile(Z, P, 90) == pytest.approx(7.6, abs=1e-12)
    assert metrics.abs_residual_percentile(Z, P, 100) == metrics.max_abs_residual(Z, P) == 10.0


def test_improvement_uses_the_largest_absolute_error():
    """100 (1 - max|Z-P| / max|Z|) with a negative drift: max|Z| = 64, max|Z-P| = 4 -> 93.75 %."""
    Z = np.array([-64.0, -30.0, 10.0])
    P = Z + np.array([4.0, -2.0, 1.0])
    assert metrics.improvement(Z, P) == pytest.approx(93.75, abs=1e-12)
