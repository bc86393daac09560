"""The instruments' declared noise and resolution against their statistics
(:mod:`twin.observe.instruments`): a reading y = q round((x + b + sigma xi) / q) of true values x
spread over many steps q has the error y - x with mean b and variance sigma^2 + q^2 / 12 exactly
(the rounding error of a value spread uniformly modulo q is uniform on [-q/2, q/2] and
independent of the noise). N = 200 000 readings: the sample variance has a relative standard
error of at most sqrt(2 / N) = 0.32 % (a uniform part has less kurtosis than a Gaussian), held to
4 of them; the mean to 4 sigma_e / sqrt(N)."""

from __future__ import annotations

import numpy as np
import pytest

from twin.model import ModelSpec
from twin.observe import RunContext, StrainGauges
from twin.observe.instruments import INSTRUMENTS, probe_reading, quantise, temperature_reading

N = 200_000


def _defaults(name: str) -> dict:
    return {p.name: p.default for p in INSTRUMENTS[name]}


def _check(error: np.ndarray, sigma: float, q: float, bias: float = 0.0) -> None:
    var = sigma ** 2 + q ** 2 / 12
    assert error.var(ddof=1) == pytest.approx(var, rel=4 * np.sqrt(2 / error.size))
    assert error.mean() == pytest.approx(bias, abs=4 * np.sqrt(var / error.size))


def _spread(scale: float, seed: int) -> np.ndarray:
    """True values spread uniformly over 1000 steps of ``scale`` (N, 1)."""
    return np.random.default_rng(seed).uniform(0.0, 1000.0 * scale, (N, 1))


def test_temperature_sensor_reads_with_its_noise_resolution_and_bias():
    """DS18S20-like sensor at its defaults: sigma 0.05 K, q 0.0625 K (lag 0 here: the samples are
    independent), and with a bias of 0.3 K the error's mean is the bias."""
    p = {**_defaults("temperature_sensor"), "lag": 0.0}
    x = 20.0 + _spread(p["quantisation"], 1)
    _check(temperature_reading(x, 60.0, p, np.random.default_rng(2)) - x, p["noise"], p["quantisation"])
    _check(temperature_reading(x, 60.0, {**p, "bias": 0.3}, np.random.default_rng(3)) - x, p["noise"],
           p["quantisation"], 0.3)


@pytest.mark.parametrize("instrument", ["probe", "laser_triangulation"])
def test_probe_and_laser_read_with_their_noise_and_resolution(instrument):
    """Eddy-current probe (0.05 um, 0.1 um resolution) and laser triangulation (0.2 um, 0.1 um)
    at their defaults, readings in um."""
    p = _defaults(instrument)
    x = _spread(p["resolution"] * 1e6, 4)
    _check(probe_reading(x, p, np.random.default_rng(5)) - x, p["noise"] * 1e6, p["resolution"] * 1e6)


def test_fbg_reads_with_its_noise_and_interrogator_resolution():
    """The FBG observer's raw reading minus the true strain (no temperature change: no
    cross-sensitivity) at the defaults: sigma 0.5 um/m, q 0.8 um/m (1 pm at 1550 nm)."""
    from tests.test_strain_laser import _bar
    from geometries.base import StrainGauge

    machine = _bar([StrainGauge("g", (0.5, 0.05, 0.099), (1.0, 0.0, 0.0), 0.05, "bar")])
    obs = StrainGauges(machine.strain_gauges)
    p = _defaults("fbg")
    true = np.vstack([[0.0], _spread(p["quantisation"], 6)]) * 1e-6        # m/m, the first row the baseline
    raw = np.hstack([true, np.zeros((len(true), 2))])                     # grating and sensor unchanged
    quiet = {"temperature_sensor": {**_defaults("temperature_sensor"), "noise": 0.0, "quantisation": 0.0, "lag": 0.0}}
    ctx = RunContext(np.arange(len(true)) * 60.0, type("S", (), {"sample_interval": 60.0})(),
                     ModelSpec((), quiet), machine, None, np.random.default_rng(7))
    data, _ = obs.data(raw, ctx)
    error = (data["strain_raw"][1] - data["strain_true"][1])[1:, 0]
    _check(error, p["noise"] * 1e6, p["quantisation"] * 1e6)


@pytest.mark.parametrize("q, m", [(0.1, 10), (0.1e-6 * 1e6, 10), (0.01, 100), (0.05, 20), (1 / 16, 16)])
def test_a_quantised_reading_is_the_double_nearest_its_decimal_step(q, m):
    """A reading n q with q = 1/m is written n / m, the double nearest the decimal: 0.3, not
    0.30000000000000004 (3 x 0.1), nor 0.09999999999999999 (0.1 um reached as 0.1e-6 m x 1e6);
    every reading within q/2 of the value it rounds (to round-off)."""
    x = np.random.default_rng(3).uniform(-50.0, 50.0, 10_000)
    y = quantise(x, q)
    n = np.round(x / q)
    np.testing.assert_array_equal(y, n / m)
    assert np.abs(y - x).max() <= q / 2 * (1 + 1e-9)
    assert [repr(v) for v in quantise(np.array([0.3, 0.7]), 0.1).tolist()] == ["0.3", "0.7"]


def test_a_step_that_is_no_unit_fraction_rounds_to_its_multiples():
    """q = 0.3 (no whole 1/q): the reading is n q exactly as computed; q = 0 passes the value."""
    x = np.array([0.44, -1.0, 2.0])
    np.testing.assert_array_equal(quantise(x, 0.3), np.round(x / 0.3) * 0.3)
    np.testing.assert_array_equal(quantise(x, 0.0), x)
