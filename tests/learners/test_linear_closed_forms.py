"""PCR component count pinned at the exact threshold (mutation-testing follow-up)."""

import numpy as np

from learners.linear import PCR


def test_pcr_keeps_components_until_the_fraction_is_exceeded_not_reached():
    """Two centred, orthogonal, equal-variance inputs: R = I, lambda = (1, 1), cumulative explained
    fraction (0.5, 1.0). n_components = 0.5 asks for a fraction that *exceeds* 0.5 (seed 003: > 85 %),
    so both components are kept; 0.49 keeps one."""
    X = np.array([[1.0, 1.0], [1.0, -1.0], [-1.0, 1.0], [-1.0, -1.0]])
    y = np.array([1.0, 2.0, 0.5, 3.0])
    m = PCR(n_components=0.5).fit(X, y)
    np.testing.assert_allclose(m.explained_variance_, [1.0, 1.0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.cumsum(m.explained_variance_ratio_), [0.5, 1.0], rtol=0, atol=1e-15)
    assert m.n_components_ == 2
    assert PCR(n_components=0.49).fit(X, y).n_components_ == 1
