"""Sensor-set search with the truth (validate.studies.placement_search): exhaustive search equals
scoring all C(p, k) sets one by one with lstsq; greedy forward selection is no better."""

from itertools import combinations

import numpy as np
import pytest

from validate.studies.placement_search import exhaustive_best, greedy_oracle, lstsq_test_rmse


def test_exhaustive_search_finds_the_best_of_all_sets():
    """Against every C(9, 3) = 84 set scored one by one with lstsq; the greedy set is no better."""
    rng = np.random.default_rng(3)
    base = rng.normal(size=(200, 3))
    X = np.column_stack([base, base @ rng.normal(size=(3, 6)) + 0.3 * rng.normal(size=(200, 6))])
    y = X[:, 0] - 2 * X[:, 4] + 0.5 * X[:, 7] + 0.2 * rng.normal(size=200)
    Xtr, ytr, Xte, yte = X[:120], y[:120], X[120:], y[120:]
    brute = min((lstsq_test_rmse(Xtr[:, list(c)], ytr, Xte[:, list(c)], yte), list(c))
                for c in combinations(range(9), 3))
    cols, rmse, n = exhaustive_best(Xtr, ytr, Xte, yte, range(9), 3, chunk=10, recheck=5)
    assert n == 84 and cols == brute[1] and rmse == pytest.approx(brute[0], rel=1e-12)
    greedy = greedy_oracle(Xtr, ytr, Xte, yte, list(range(9)), 3)
    assert lstsq_test_rmse(Xtr[:, greedy], ytr, Xte[:, greedy], yte) >= rmse - 1e-12
    with pytest.raises(ValueError, match="exceeds"):
        exhaustive_best(Xtr, ytr, Xte, yte, range(9), 3, max_sets=10)
