"""Fuzzy c-means objective pinned by its definition (mutation-testing follow-up)."""

import numpy as np
import pytest

from learners.fcm import fcm_memberships, fuzzy_cmeans


@pytest.mark.parametrize("m", [2.0, 2.5, 1.5])
def test_objective_is_membership_to_the_m_times_squared_distance(m):
    """J = sum_i sum_j mu_ij^m d_ij^2 (Eq. 2), evaluated at the returned centres and memberships."""
    rng = np.random.default_rng(4)
    data = np.vstack([rng.normal(c, 0.4, (15, 2)) for c in ([0, 0], [3, 1], [1, 4])])
    res = fuzzy_cmeans(data, 3, m=m, random_state=0)
    d2 = ((data[:, None, :] - res.centers[None, :, :]) ** 2).sum(axis=2)
    np.testing.assert_allclose(res.membership, fcm_memberships(data, res.centers, m), rtol=1e-12)
    assert res.objective == pytest.approx(float((res.membership ** m * d2).sum()), rel=1e-12)
