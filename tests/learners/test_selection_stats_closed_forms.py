"""Regression F-test of fuzzy-r2 pinned by its closed form (mutation-testing follow-up)."""

import numpy as np
import pytest
import scipy.stats

from learners.selection_stats import FuzzyR2Selector


def test_level_p_values_are_the_regression_f_test():
    """Per level with p sensors: R^2 = 1 - SSE/SST, F = (R^2 / p) / ((1 - R^2) / (n - p - 1)),
    p-value = P[F(p, n-p-1) > F] (seed 003 Eqs. 7-8). Level 1 also equals the slope t-test of
    scipy.stats.linregress (F = t^2)."""
    rng = np.random.default_rng(7)
    n = 20
    X = rng.normal(size=(n, 3))
    y = 0.3 * X[:, 0] + 0.25 * X[:, 1] + rng.normal(size=n)
    sel = FuzzyR2Selector(n_select=2).fit(X, y)
    for level, cols in enumerate(sel.combinations_, start=1):
        p = len(cols)
        A = np.column_stack([np.ones(n), X[:, cols]])
        res = y - A @ np.linalg.lstsq(A, y, rcond=None)[0]
        r2 = 1 - (res @ res) / np.sum((y - y.mean()) ** 2)
        f = (r2 / p) / ((1 - r2) / (n - p - 1))
        assert sel.r2_[level - 1] == pytest.approx(r2, rel=1e-12)
        assert sel.p_values_[level - 1] == pytest.approx(scipy.stats.f.sf(f, p, n - p - 1), rel=1e-9)
    assert sel.p_values_[0] == pytest.approx(scipy.stats.linregress(X[:, sel.combinations_[0][0]], y).pvalue,
                                             rel=1e-9)
    assert 1e-3 < sel.p_values_[1] < 0.9       # moderate: a wrong F would move it visibly
