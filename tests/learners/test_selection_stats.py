"""Sensor selectors. Known answers: fuzzy-r2's maximal tree reproduces seed 003 Tables 3 and 5 from the
printed correlation matrix (Eq. 12) and Table 4; hier-corr / correlation pick the informative sensors
on synthetic data."""

import numpy as np
import pytest
import scipy.stats

from twin.errors import InputError

from learners.selection_stats import (AllSelector, CorrelationSelector, FuzzyR2Selector, HierCorrSelector,
                                      choose_level, maximal_spanning_tree, representatives, tree_partition)

# Seed 003 Eq. (12), L230: upper triangle of the 11 x 11 correlation matrix of T1..T11.
_UPPER = """1 0.91291 0.8972 0.88765 0.97532 0.95647 0.81976 0.908 0.97891 0.95868 0.86397
1 0.98677 0.98366 0.96459 0.94869 0.93909 0.9865 0.9602 0.96513 0.94943
1 0.98309 0.95065 0.93572 0.94915 0.98747 0.95176 0.96321 0.93318
1 0.94542 0.92853 0.96927 0.9921 0.9519 0.96418 0.94085
1 0.98288 0.88303 0.96299 0.98226 0.96855 0.91988
1 0.86006 0.94684 0.96524 0.94873 0.89664
1 0.96475 0.90592 0.93318 0.91032
1 0.96373 0.97348 0.94578
1 0.98947 0.90734
1 0.91689
1"""
# Table 4, L265-L274: r of T1..T11 with the slope k.
_R_K = [0.9725, 0.9660, 0.9538, 0.9160, 0.9814, 0.9673, 0.8536, 0.9382, 0.9667, 0.9440, 0.8889]
# Table 5, L276-L290: representative combinations for 1..11 clusters (1-based sensor numbers).
_TABLE5 = [[5], [5, 11], [5, 7, 11], [2, 5, 7, 11], [1, 2, 5, 7, 11], [1, 2, 5, 7, 9, 11],
           [1, 2, 5, 6, 7, 9, 11], [1, 2, 3, 5, 6, 7, 9, 11], [1, 2, 3, 5, 6, 7, 8, 9, 11],
           [1, 2, 3, 5, 6, 7, 8, 9, 10, 11], list(range(1, 12))]


def _seed003_matrix():
    R = np.zeros((11, 11))
    for i, line in enumerate(_UPPER.splitlines()):
        R[i, i:] = [float(v) for v in line.split()]
    return R + R.T - np.eye(11)


def test_maximal_tree_reproduces_seed_003_tables_3_and_5():
    edges = maximal_spanning_tree(_seed003_matrix())
    assert len(edges) == 10
    # Table 3 row [0.97348, 0.97891): {T1,T5,T6,T9,T10}, {T2,T3,T4,T8}, {T7}, {T11}
    four = [[i + 1 for i in g] for g in tree_partition(edges, 11, 4)]
    assert four == [[1, 5, 6, 9, 10], [2, 3, 4, 8], [7], [11]]
    for k, expected in enumerate(_TABLE5, start=1):
        reps = representatives(tree_partition(edges, 11, k), _R_K)
        assert [i + 1 for i in reps] == expected


def _synthetic(n=400, seed=0):
    """Three groups of sensors: group a (x0-x2), group b (x3-x4), unrelated c (x5-x6); y = a + b.

    The clean sensors x1 and x4 have |r| = 0.71 with y; their noisy neighbours 0.63; c about 0.
    """
    rng = np.random.default_rng(seed)
    a, b, c = rng.normal(size=(3, n))
    X = np.column_stack([a + 0.5 * rng.normal(size=n), a, a + 0.5 * rng.normal(size=n),
                         b + 0.5 * rng.normal(size=n), b, c, c + 0.1 * rng.normal(size=n)])
    y = a + b + 0.01 * rng.normal(size=n)
    return X, y


def test_correlation_picks_informative_sensors():
    # Known answer: the clean sensors x1 (group a) and x4 (group b) have the largest |r| with y.
    X, y = _synthetic()
    sel = CorrelationSelector(n_select=2).fit(X, y)
    assert sel.selected_ == [1, 4]
    assert sel.selected_names_ == ["x1", "x4"]
    assert np.array_equal(sel.transform(X), X[:, [1, 4]])


def test_hier_corr_picks_informative_sensor_per_group():
    # Known answer: three correlation groups {x0,x1,x2}, {x3,x4}, {x5,x6}; the best of each is kept.
    X, y = _synthetic()
    sel = HierCorrSelector(n_select=3).fit(X, y)
    assert sel.selected_[:2] == [1, 4] and sel.selected_[2] in (5, 6)
    assert len(set(sel.labels_[sel.selected_])) == 3
    assert sel.transform(X).shape == (len(y), 3)


def test_fuzzy_r2_level_choice_gives_seed_003_five_sensors():
    # Seed 003 Table 6 R^2 for 1..6 sensors; Sig. 0.008 for 5 (Table 7), 0.058 for 6 (Table 8);
    # levels 1-4 are significant (Sig. not printed; R^2 >= 0.963 with n = 8). Expected: 5.
    r2 = [0.963, 0.963, 0.971, 0.989, 0.997, 0.999]
    p = [1e-5, 1e-4, 1e-3, 1e-3, 0.008, 0.058]
    assert choose_level(r2, p, n_samples=8) == 5


def test_fuzzy_r2_auto_level_is_significant_and_contains_informative_sensors():
    X, y = _synthetic(300)
    sel = FuzzyR2Selector().fit(X, y)
    assert {1, 4} <= set(sel.selected_)
    assert sel.p_values_[sel.n_selected_ - 1] < 0.05
    fixed = FuzzyR2Selector(n_select=3).fit(X, y)     # one sensor per correlation group
    assert fixed.selected_[:2] == [1, 4] and fixed.selected_[2] in (5, 6)


def test_names_from_columns_and_all_selector():
    pd = pytest.importorskip("pandas")
    X, y = _synthetic(300)
    df = pd.DataFrame(X, columns=[f"T{i + 1}" for i in range(X.shape[1])])
    sel = CorrelationSelector(n_select=2).fit(df, y)
    assert sel.selected_names_ == ["T2", "T5"]
    assert list(sel.transform(df).columns) == ["T2", "T5"]
    a = AllSelector().fit(X, y)
    assert a.selected_ == list(range(X.shape[1])) and a.transform(X).shape == X.shape


def test_bad_count_and_constant_column():
    X, y = _synthetic(50)
    with pytest.raises(ValueError):
        CorrelationSelector(n_select=0).fit(X, y)
    Xc = np.column_stack([np.ones(len(y)), X])
    for selector in (CorrelationSelector(n_select=3), HierCorrSelector(n_select=3), FuzzyR2Selector(n_select=3)):
        with pytest.raises(InputError, match="column 0 is constant"):   # as twin learn refuses it: never picked
            selector.fit(Xc, y)


def test_regression_f_test_of_one_predictor_is_the_slope_t_test():
    """Eq. (8) with p = 1: F = (SSR/1) / (SSE/(n-2)) = t^2 of the slope, so its p-value equals
    scipy.stats.linregress(x, y).pvalue and R^2 = r^2."""
    from learners.selection_stats import _regression_test

    rng = np.random.default_rng(4)
    x = rng.normal(size=12)
    y = 0.8 * x + rng.normal(size=12)
    ref = scipy.stats.linregress(x, y)
    r2, _, p_value = _regression_test(x[:, None], y)
    assert 1e-3 < ref.pvalue < 0.5
    assert p_value == pytest.approx(ref.pvalue, rel=1e-12)
    assert r2 == pytest.approx(ref.rvalue ** 2, rel=1e-12)


def test_choose_level_uses_the_bic_ln_n_penalty_not_aic():
    """BIC = n ln(1 - R^2) + (k + 1) ln n, n = 1000, both levels significant (p = 1e-5):
    level 1: 1000 ln 0.1 + 2 ln 1000 = -2288.77; level 2: 1000 ln 0.0995 + 3 ln 1000 = -2286.87,
    so level 1. An AIC-like penalty 2 (k + 1) would give -2298.59 vs -2301.61 and pick level 2."""
    assert choose_level([0.9, 0.9005], [1e-5, 1e-5], n_samples=1000) == 1


def test_hier_corr_distance_is_one_minus_abs_r_so_anticorrelated_columns_share_a_group():
    """d_ij = 1 - |r_ij|: column 1 = -a + 0.05 noise has r ~ -1 with column 0 = a, so d ~ 0 and the
    two share a cluster; b (independent) is the other cluster (d ~ 1). y = a + b: the chosen sensors
    are one of {0, 1} plus column 2. With d = 1 - r, columns 0 and 1 would be ~2 apart (different groups)."""
    rng = np.random.default_rng(7)
    a, b, noise = rng.normal(size=(3, 300))
    X = np.column_stack([a, -a + 0.05 * noise, b])
    sel = HierCorrSelector(n_select=2).fit(X, a + b)
    assert sel.labels_[0] == sel.labels_[1]
    assert sel.labels_[2] != sel.labels_[0]
    assert 2 in sel.selected_ and len(sel.selected_) == 2
