"""Fuzzy c-means separates well-separated blobs; memberships are a fuzzy partition."""

import numpy as np
import pytest

from learners.fcm import fcm_memberships, fuzzy_cmeans
from twin.errors import InputError

TRUE_CENTRES = np.array([[0.0, 0.0], [6.0, 6.0], [0.0, 7.0]])


def blobs(seed=0, n=40, sigma=0.3):
    rng = np.random.default_rng(seed)
    x = np.vstack([rng.normal(c, sigma, (n, 2)) for c in TRUE_CENTRES])
    labels = np.repeat(np.arange(3), n)
    return x, labels


def test_separates_blobs():
    x, labels = blobs()
    res = fuzzy_cmeans(x, 3, random_state=0)
    np.testing.assert_allclose(res.membership.sum(axis=1), 1.0, atol=1e-12)
    assert res.membership.shape == (120, 3) and res.centers.shape == (3, 2)
    # each true centre is matched by one found centre within 0.2 (blob std 0.3, 40 points)
    dist = np.linalg.norm(res.centers[:, None, :] - TRUE_CENTRES[None], axis=2)
    assert sorted(dist.argmin(axis=1).tolist()) == [0, 1, 2]
    assert dist.min(axis=1).max() < 0.2
    # hard labels agree with the truth up to a permutation
    hard = res.membership.argmax(axis=1)
    for k in range(3):
        assert len(set(hard[labels == k])) == 1
    assert len(set(hard)) == 3
    assert res.n_iter >= 1 and res.objective > 0


def test_deterministic_and_input_untouched():
    x, _ = blobs(1)
    x_copy = x.copy()
    a = fuzzy_cmeans(x, 3, random_state=5)
    b = fuzzy_cmeans(x, 3, random_state=5)
    np.testing.assert_array_equal(a.centers, b.centers)
    np.testing.assert_array_equal(a.membership, b.membership)
    np.testing.assert_array_equal(x, x_copy)


def test_one_dimensional_input_and_single_cluster():
    v = np.array([0.0, 0.1, 0.2, 5.0, 5.1, 5.2])
    res = fuzzy_cmeans(v, 2, random_state=0)
    np.testing.assert_allclose(np.sort(res.centers.ravel()), [0.1, 5.1], atol=0.05)
    one = fuzzy_cmeans(v, 1)
    np.testing.assert_allclose(one.membership, 1.0)
    np.testing.assert_allclose(one.centers, [[v.mean()]])  # c = 1: the centre is the mean


def test_membership_formula_by_hand():
    # m = 2: mu_1 = 1 / (1 + d1^2/d2^2); point 1 from centre 0 and 3 from centre 4 -> 9/10, 1/10
    u = fcm_memberships([[1.0]], [[0.0], [4.0]], m=2.0)
    np.testing.assert_allclose(u, [[0.9, 0.1]])
    # a point on a centre belongs to it fully
    np.testing.assert_allclose(fcm_memberships([[4.0]], [[0.0], [4.0]]), [[0.0, 1.0]])


def test_too_few_rows():
    with pytest.raises(InputError):
        fuzzy_cmeans(np.zeros((5, 2)), 2)
    with pytest.raises(ValueError):
        fuzzy_cmeans(np.arange(6.0), 2, m=1.0)
