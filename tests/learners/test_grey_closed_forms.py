"""Grey-model formulas pinned by closed forms (mutation-testing follow-up)."""

import numpy as np
import pytest

from learners.grey import ago, check_growth, gm11_simulate
from learners.grey_gmc import gmc_retention, gmc_simulate
from twin.errors import InputError


def test_gm11_zero_development_coefficient_is_a_straight_line():
    """a -> 0 limit of the whitened response: x^(1)(k) = x(1) + b (k - 1), so after IAGO the raw
    series is x(1), b, b, b, ... (the first sample is the start value itself)."""
    first, b = 5.0, 2.0
    np.testing.assert_allclose(gm11_simulate(0.0, b, first, 5), [5.0, 2.0, 2.0, 2.0, 2.0], rtol=0, atol=1e-12)
    # continuity with the general formula (x(1) - b/a) e^{-a(k-1)} + b/a as a -> 0
    np.testing.assert_allclose(gm11_simulate(1e-9, b, first, 5), gm11_simulate(0.0, b, first, 5), atol=1e-6)


@pytest.mark.parametrize("n", [4, 11, 31])
def test_growth_over_n_samples_is_retention_to_the_n_minus_1(n):
    """A response over samples 1..n grows by retention^(n-1) (n - 1 steps); refused only above 1e3."""
    kw = dict(model="GM(1,N)", coef_name="a", coef=-0.1, fit_method="equation")
    edge = 1e3 ** (1.0 / (n - 1))
    check_growth(edge * (1 - 1e-6), n, **kw)          # growth just under 1e3: accepted
    with pytest.raises(InputError):
        check_growth(edge * (1 + 1e-6), n, **kw)      # just over: refused


@pytest.mark.parametrize("b1", [0.3, 0.05, -0.2])
@pytest.mark.parametrize("response", ["convolution", "difference"])
def test_gmc_retention_is_the_homogeneous_response_ratio(b1, response):
    """With b = 0, u = 0 the GMC(1,N) AGO response obeys x^(1)(k) = R x^(1)(k-1), R = e^{-b1}
    (convolution) or (1 - b1/2)/(1 + b1/2) (difference); gmc_retention must return that R."""
    x1 = ago(gmc_simulate(b1, [0.0], 0.0, np.zeros((6, 1)), 2.0, response))
    expected = np.exp(-b1) if response == "convolution" else (1 - 0.5 * b1) / (1 + 0.5 * b1)
    assert gmc_retention(b1, response) == pytest.approx(expected, rel=1e-14)
    np.testing.assert_allclose(x1[1:] / x1[:-1], expected, rtol=1e-12)


def test_gm1n_whitened_response_written_out():
    """GM(1,N)'s whitened response with the drive S(k) = sum_j b_j x_j^(1)(k) taken at each k:
    x^(1)(k) = (y0 - S(k) / a) e^(-a (k - 1)) + S(k) / a, then the inverse AGO."""
    from learners.grey import gm1n_simulate
    rng = np.random.default_rng(3)
    X = rng.uniform(0.0, 1.0, (12, 2))
    a, b, y0 = 0.3, np.array([0.8, -0.5]), 0.2
    drive = np.cumsum(X, axis=0) @ b
    x1 = (y0 - drive / a) * np.exp(-a * np.arange(12)) + drive / a
    np.testing.assert_allclose(gm1n_simulate(a, b, np.cumsum(X, axis=0), y0, "whitened"),
                               np.r_[x1[0], np.diff(x1)], rtol=1e-12, atol=1e-14)
