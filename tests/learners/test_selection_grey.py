"""Grey + FCM sensor selection: known scores by hand and the right sensors on synthetic data."""

import numpy as np
import pytest

from learners.selection_grey import (GM0NFCMSelector, GRAFCMSelector, deng_grade, fcm_representatives,
                                     similitude_degree)
from twin.errors import InputError


def eight_sensors(seed, noise=0.02, n=60):
    """8 temperature series (°C): the error (µm) is 4 ΔT0 + 1.5 ΔT1; sensors 2-5 are other smooth
    heating/wavy curves, 6 and 7 duplicate 2 and 3; every reading has independent noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    s0 = 5 * (1 - np.exp(-t / 15))
    s1 = 3 * (1 - np.exp(-t / 40)) + 0.5 * np.sin(t / 6)
    others = [2 * (1 - np.exp(-t / 4)), 3 * np.sin(t / 20) ** 2, 0.05 * t, 2 * (1 - np.exp(-t / 80)) + 0.3 * np.cos(t / 4)]
    X = np.column_stack([s0, s1] + others + others[:2]) + 20.0 + rng.normal(0, noise, (n, 8))
    return X, 4 * s0 + 1.5 * s1


@pytest.mark.parametrize("seed", range(5))
def test_gm0n_fcm_picks_the_influential_sensors(seed):
    X, y = eight_sensors(seed)
    two = GM0NFCMSelector(n_select=2).fit(X, y)
    assert two.selected_.tolist() == [0, 1]
    assert two.selected_names_ == ["x0", "x1"]
    np.testing.assert_array_equal(two.transform(X), X[:, [0, 1]])
    three = GM0NFCMSelector(n_select=3).fit(X, y)
    assert {0, 1} <= set(three.selected_.tolist()) and len(three.selected_) == 3
    assert np.argmax(three.scores_) == 0


def test_similitude_degree_by_hand():
    # reference zero-initial image (0, 1, 3), sensor (0, 2, 2): |(1-2) + 0.5 (3-2)| = 0.5 -> 1/1.5
    ref = np.array([5.0, 6.0, 8.0])
    X = np.array([[1.0, 7.0], [3.0, 8.0], [3.0, 10.0]])  # second column is the reference shifted
    np.testing.assert_allclose(similitude_degree(ref, X), [1 / 1.5, 1.0])


def test_deng_grade_by_hand():
    # normalised ref (0, .5, 1); sensor A (0, 1, 1) -> Delta (0, .5, 0); sensor B = ref -> 0.
    # Delta_min = 0, Delta_max = 0.5, rho = 0.5: xi = 0.25 / (Delta + 0.25) -> A: (1, 1/3, 1)
    ref = np.array([0.0, 1.0, 2.0])
    X = np.array([[0.0, 10.0], [4.0, 11.0], [4.0, 12.0]])
    np.testing.assert_allclose(deng_grade(ref, X), [(1 + 1 / 3 + 1) / 3, 1.0])


def test_gra_fcm_keeps_the_most_similar_sensor_per_group():
    rng = np.random.default_rng(0)
    t = np.arange(50.0)
    y = 10 * (1 - np.exp(-t / 12))
    X = np.column_stack([y + 20, 0.9 * y + 20, 0.2 * y + 20, 0.1 * y + 20, rng.normal(20, 0.05, 50)])
    for measure in ("similitude", "deng"):
        sel = GRAFCMSelector(n_select=2, measure=measure).fit(X, y)
        assert 0 in sel.selected_ and len(sel.selected_) == 2
        assert np.argmax(sel.scores_) == 0


def test_representatives_fill_up_and_column_names():
    # all scores equal: FCM cannot form 3 groups; the best (first) three are kept
    sel, labels = fcm_representatives(np.ones(5), 3)
    assert sel.tolist() == [0, 1, 2] and (labels == -1).all()

    class Table(np.ndarray):
        pass

    X, y = eight_sensors(0)
    tab = X.view(Table)
    tab.columns = [f"T{j + 1:02d}" for j in range(8)]
    assert GM0NFCMSelector(n_select=2).fit(tab, y).selected_names_ == ["T01", "T02"]
    with pytest.raises(InputError, match="n_select"):   # more sensors than there are: refused, never cut down
        GM0NFCMSelector(n_select=20).fit(X, y)


def test_similitude_degree_four_samples_by_hand():
    """Liu's similitude degree (module docstring, thesis Eq. (4.1)) with zero-initial images
    x^0(k) = x(k) - x(1): |s_0 - s_m| = |sum_{k=2..n-1} (x_0^0(k) - x_m^0(k)) + 0.5 (x_0^0(n) - x_m^0(n))|,
    eps = 1 / (1 + |s_0 - s_m|). ref (5, 6, 8, 9) -> (0, 1, 3, 4); sensor (1, 3, 3, 6) -> (0, 2, 2, 5);
    differences (0, -1, 1, -1): inner sum k = 2..3 is -1 + 1 = 0, end term 0.5 (-1) = -0.5,
    so eps = 1 / 1.5 = 2/3 (the last sample counted in full as well would give 1 / 2.5 = 0.4)."""
    ref = np.array([5.0, 6.0, 8.0, 9.0])
    sensor = np.array([1.0, 3.0, 3.0, 6.0])
    z0, zm = ref - ref[0], sensor - sensor[0]
    diff = z0 - zm
    s = diff[1] + diff[2] + 0.5 * diff[3]
    assert s == -0.5
    np.testing.assert_allclose(similitude_degree(ref, sensor[:, None]), [1.0 / (1.0 + abs(s))], rtol=1e-14)
    np.testing.assert_allclose(similitude_degree(ref, sensor[:, None]), [2.0 / 3.0], rtol=1e-14)


def test_deng_grade_with_a_nonzero_delta_min():
    """Deng's grade with Delta_min > 0 (the hand case above has Delta_min = 0, where the term
    vanishes): ref (0, 1, 2) -> (0, .5, 1), sensor (2, 0, 1) -> (1, 0, .5), Delta = (1, .5, .5),
    Delta_min .5, Delta_max 1, rho .5: xi = (Delta_min + rho Delta_max) / (Delta + rho Delta_max) =
    (2/3, 1, 1), grade 8/9."""
    np.testing.assert_allclose(deng_grade([0.0, 1.0, 2.0], np.array([[2.0], [0.0], [1.0]])), [8 / 9], rtol=1e-14)
