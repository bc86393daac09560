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


def test_membership_exponent_for_m_other_than_two():
    """Eq. (1) with m != 2: mu_i is proportional to d_i^(-2/(m-1)).

    Point 1, centres 0 and 4 (d = 1, 3): m = 3 gives weights 1/d -> [3/4, 1/4]; m = 1.5 gives
    d^-4 -> [81/82, 1/82]. (At m = 2, 2/(m-1) = 2(m-1), so only m != 2 tells the exponent apart.)
    """
    np.testing.assert_allclose(fcm_memberships([[1.0]], [[0.0], [4.0]], m=3.0), [[0.75, 0.25]], rtol=0, atol=1e-15)
    np.testing.assert_allclose(fcm_memberships([[1.0]], [[0.0], [4.0]], m=1.5), [[81 / 82, 1 / 82]],
                               rtol=0, atol=1e-15)


@pytest.mark.parametrize("m", [2.0, 3.0])
def test_converged_centres_are_membership_weighted_means(m):
    """Eq. (3) at the fixed point: c_i = sum_j u_ij^m x_j / sum_j u_ij^m with the returned memberships."""
    x, _ = blobs(seed=4)
    res = fuzzy_cmeans(x, 3, m=m, tol=1e-14, max_iter=1000, random_state=0)
    assert res.n_iter < 1000
    assert np.linalg.norm(res.centers[:, None, :] - TRUE_CENTRES[None], axis=2).min(axis=1).max() < 0.2
    u = res.membership
    weighted = np.array([(u[:, i] ** m) @ x / (u[:, i] ** m).sum() for i in range(3)])
    np.testing.assert_allclose(res.centers, weighted, rtol=0, atol=1e-6)
