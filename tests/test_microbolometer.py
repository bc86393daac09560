"""The microbolometer's sensor chain against closed forms: the ADC's range and half-count
rounding, the temporal and fixed-pattern noise against their declared deviations (chi-square
bands), and the offset drift as an exact Ornstein-Uhlenbeck process (:mod:`twin.observe.microbolometer`)."""

from __future__ import annotations

import numpy as np
import pytest

from twin.observe.microbolometer import Microbolometer
from twin.observe.radiometry import RadianceTable

BAND = (7.5e-6, 13e-6)   # m: the camera's long-wave band, as tests/test_camera.py


def _chain(sensor, shape=(1, 1), times=(0.0,), seed=0):
    from twin.observe.microbolometer import SensorChain

    return SensorChain(sensor, RadianceTable(BAND), shape, np.asarray(times, float), np.random.default_rng(seed))


QUIET = dict(netd=0.0, fixed_pattern=0.0, row_fixed=0.0, column_fixed=0.0, row_temporal=0.0, column_temporal=0.0,
             frame_temporal=0.0, offset=0.0, drift=0.0)


def test_adc_maps_the_range_ends_to_the_end_counts_and_rounds_to_half_a_count():
    """The ADC c = round(c_0 + G W), G = (2^bits - 1) / (L(T_hi) - L(T_lo)), c_0 = -G L(T_lo):
    blackbodies at the ends of the range (-40, +120 degC) give 0 and 2^14 - 1 exactly; inside,
    radiance_of(c) = (c - c_0) / G is within half a count step 1 / (2 G) of W (and the error
    reaches it: the bound is tight), counts of radiance_of(c) are c again (the inverse on its
    grid), radiances beyond the range clip to the end counts. noiseless() zeroes every noise and
    offset term and keeps the ADC, so its counts do not depend on the seed."""
    table = RadianceTable(BAND)
    sensor = Microbolometer().noiseless()
    assert all(getattr(sensor, k) == 0.0 for k in QUIET)
    assert (sensor.bits, sensor.range, sensor.reference_temperature) == (14, (-40.0, 120.0), 30.0)
    n = 20000
    chain = _chain(sensor, (1, n), np.arange(5) * 10.0)   # a chain takes frames in order: five here
    lo, hi = table.radiance(np.array([-40.0, 120.0]))
    ends = np.array([lo, hi, lo - 1.0, hi + 1.0]).reshape(4, 1, 1).repeat(n, axis=2)
    assert np.array_equal(chain.counts(ends)[:, 0], np.array([0, 16383, 0, 16383])[:, None].repeat(n, axis=1))
    w = np.random.default_rng(1).uniform(lo, hi, n)
    c = chain.counts(w.reshape(1, 1, n))
    err = chain.radiance_of(c[0, 0]) - w
    half = 0.5 / chain.gain
    assert np.abs(err).max() <= half * (1 + 1e-9) and np.abs(err).max() > 0.99 * half
    grid = np.arange(0, 16384, dtype=np.uint16)
    back = _chain(sensor, (1, len(grid))).counts(chain.radiance_of(grid).reshape(1, 1, -1))
    assert np.array_equal(back[0, 0], grid)
    assert np.array_equal(_chain(sensor, (1, n), seed=7).counts(w.reshape(1, 1, n)), c)


def test_temporal_and_fixed_pattern_noise_have_their_declared_deviations():
    """A uniform scene at T_ref = 30 degC, one noise term at a time, its deviation sigma [K]
    entering as sigma dL/dT(T_ref) (module docstring): the counts' variance is (G L'(T_ref) sigma)^2
    + 1/12 (Sheppard: the rounding adds a uniform error of 1/12 count^2 when sigma spans many
    counts; 0.15 % of the NETD's 54 count^2). Temporal (NETD 0.08 K): 64 x 64 pixels x 64 frames,
    N = 262144, the sample variance (N - 1) s^2 / sigma^2 ~ chi2(N - 1) has relative standard error
    sqrt(2 / N) = 0.28 %; held to 4 standard errors (1.1 %). The mean is c_0 + G L(T_ref) within
    4 sigma / sqrt(N). Fixed pattern (0.03 K): the same in every frame; 256 x 256 pixels,
    standard error 0.55 %, held to 2.2 %."""
    table = RadianceTable(BAND)
    L30 = table.radiance(30.0)
    n_fr, side = 64, 64
    chain = _chain(Microbolometer(**{**QUIET, "netd": 0.08}), (side, side), np.arange(n_fr) * 10.0, seed=11)
    c = chain.counts(np.full((n_fr, side, side), L30)).astype(float)
    sigma_c = chain.gain * chain.kelvin * 0.08
    N = c.size
    assert c.var(ddof=1) == pytest.approx(sigma_c ** 2 + 1 / 12, rel=4 * np.sqrt(2 / N))
    assert c.mean() == pytest.approx(chain.zero + chain.gain * L30, abs=4 * sigma_c / np.sqrt(N))
    side = 256
    chain = _chain(Microbolometer(**{**QUIET, "fixed_pattern": 0.03}), (side, side), (0.0, 10.0), seed=12)
    c = chain.counts(np.full((2, side, side), L30)).astype(float)
    assert np.array_equal(c[0], c[1])
    sigma_c = chain.gain * chain.kelvin * 0.03
    assert c[0].var(ddof=1) == pytest.approx(sigma_c ** 2 + 1 / 12, rel=4 * np.sqrt(2 / side ** 2))


def test_offset_drift_is_an_ornstein_uhlenbeck_process_common_to_all_pixels():
    """The drift's exact update x_k+1 = a x_k + sqrt(1 - a^2) sigma_d xi, a = exp(-dt / tau),
    started from N(0, sigma_d^2): stationary variance sigma_d^2 at every frame and lag-one
    correlation exp(-dt_k / tau) for each step, whatever its length. Frames alternate dt = 600 s
    and 3600 s (tau = 1800 s: a = 0.717 and 0.135; explicit Euler, 1 - dt / tau, would give 0.667
    and -1), 40000 frames: the correlation of each step kind (20000 pairs) has standard error
    sqrt((1 - a^2) / 20000) <= 0.007, held to 4 of them; the variance's relative standard error is
    sqrt(2 (1 + 2 sum rho_k^2) / n) = 0.9 % (sum rho_k^2 = 0.28), held to 3.5 %. The offset is read
    back through counts (every pixel the same; count step 0.011 K against sigma_d = 0.3 K). With a
    large initial offset the sum is clipped to the accuracy bound +-2 K."""
    table = RadianceTable(BAND)
    L30 = table.radiance(30.0)
    n, tau, sd = 40000, 1800.0, 0.3
    dt = np.where(np.arange(n - 1) % 2, 3600.0, 600.0)
    t = np.concatenate([[0.0], np.cumsum(dt)])
    sensor = Microbolometer(**{**QUIET, "drift": sd, "drift_time": tau, "accuracy": 100.0})
    chain = _chain(sensor, (2, 3), t, seed=5)
    c = chain.counts(np.full((n, 2, 3), L30))
    assert np.all(c == c[:, :1, :1])   # common to all pixels
    x = (chain.radiance_of(c[:, 0, 0]) - L30) / chain.kelvin   # [K]
    assert np.mean(x ** 2) == pytest.approx(sd ** 2, rel=0.035)
    for step in (600.0, 3600.0):
        k = np.flatnonzero(dt == step)
        a = np.exp(-step / tau)
        r = np.sum(x[k] * x[k + 1]) / np.sqrt(np.sum(x[k] ** 2) * np.sum(x[k + 1] ** 2))
        assert r == pytest.approx(a, abs=4 * np.sqrt((1 - a * a) / len(k)))
    clipped = _chain(Microbolometer(**{**QUIET, "offset": 50.0, "drift": 0.3}), (1, 1), np.arange(50) * 60.0, seed=2)
    x = (clipped.radiance_of(clipped.counts(np.full((50, 1, 1), L30))[:, 0, 0]) - L30) / clipped.kelvin
    assert np.all(np.abs(np.abs(x) - 2.0) <= 0.5 / (clipped.gain * clipped.kelvin) + 1e-6)


@pytest.mark.parametrize("term", ["row_fixed", "column_fixed", "row_temporal", "column_temporal"])
def test_row_and_column_banding_is_one_offset_a_line(term):
    """Banding (3-D noise sigma_v, sigma_h fixed; sigma_tv, sigma_th temporal), one term at a
    time at 0.02 K on a uniform scene at T_ref: every pixel of a row (or column) gets the same
    offset, so each line of counts is constant (exactly: white noise would not be), and the
    lines' counts have the variance (G L'(T_ref) sigma)^2 + 1/12 (Sheppard). 20000 lines x 2
    frames: a fixed term repeats in the second frame and its variance over 20000 lines has
    relative standard error sqrt(2 / 20000) = 1 %, held to 4 %; a temporal one is drawn anew each
    frame (40000 independent lines, held to 2.8 %) and the two frames' lines are uncorrelated
    within 4 / sqrt(20000)."""
    table = RadianceTable(BAND)
    L30 = table.radiance(30.0)
    lines, across = 20000, 3
    shape = (lines, across) if term.startswith("row") else (across, lines)
    chain = _chain(Microbolometer(**{**QUIET, term: 0.02}), shape, (0.0, 10.0), seed=21)
    c = chain.counts(np.full((2, *shape), L30)).astype(float)
    if term.startswith("column"):
        c = c.transpose(0, 2, 1)                   # lines first
    assert np.all(c == c[:, :, :1])                # one offset a line
    line = c[:, :, 0]
    sigma_c = chain.gain * chain.kelvin * 0.02
    if term.endswith("fixed"):
        assert np.array_equal(line[0], line[1])
        assert line[0].var(ddof=1) == pytest.approx(sigma_c ** 2 + 1 / 12, rel=4 * np.sqrt(2 / lines))
    else:
        assert line.var(ddof=1) == pytest.approx(sigma_c ** 2 + 1 / 12, rel=4 * np.sqrt(2 / line.size))
        assert abs(np.corrcoef(line[0], line[1])[0, 1]) < 4 / np.sqrt(lines)
