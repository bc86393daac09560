"""Instrument models: what a sensor records given the true signal.

Temperature sensor (DS18S20-like digital sensor, seed 000 L3845-3869): first-order lag tau,
bias, Gaussian noise, quantisation q = 0.0625 K:  y = q round((lag(T) + bias + noise) / q).
Eddy-current probe (seed 000 L3878-3906): 0.1 um resolution, small Gaussian noise.
Laser triangulation sensor (seed 000 L3911-3933, Machine C): as a probe, coarser and noisier
(large-standoff heads: 0.1 um resolution, 0.2 um noise; plausible, the seed gives none).
FBG strain gauge (seed 000 L3939-3976): temperature cross-sensitivity 8.64 um/m/K in the raw
reading; interrogator resolution about 1 pm of a 1550 nm grating, i.e. 0.8 um/m, noise 0.5 um/m.
Noise comes from a seeded generator; the noise-free truth is always kept beside the reading.
"""

from __future__ import annotations

import numpy as np

from twin.effects.base import Parameter
from twin.signals import lag_series

INSTRUMENTS: dict[str, tuple[Parameter, ...]] = {
    "temperature_sensor": (
        Parameter("quantisation", "temperature_difference", 0.0625, 0.0, 1.0, "reading resolution (DS18S20: 0.0625 K)"),
        Parameter("noise", "temperature_difference", 0.05, 0.0, 1.0, "noise standard deviation (+/-0.1 K at 2 sigma)"),
        Parameter("lag", "time", 5.0, 0.0, 600.0, "first-order time constant of sensor and mounting"),
        Parameter("bias", "temperature_difference", 0.0, -5.0, 5.0, "constant offset of every sensor"),
    ),
    "probe": (
        Parameter("resolution", "length", 0.1e-6, 0.0, 10e-6, "reading resolution (eddy-current NCDT: 0.1 um)"),
        Parameter("noise", "length", 0.05e-6, 0.0, 10e-6, "noise standard deviation"),
    ),
    "laser_triangulation": (
        Parameter("resolution", "length", 0.1e-6, 0.0, 10e-6, "reading resolution"),
        Parameter("noise", "length", 0.2e-6, 0.0, 10e-6, "noise standard deviation"),
    ),
    "fbg": (
        Parameter("cross_sensitivity", "thermal_strain", 8.64e-6, 0.0, 50e-6,
                  "apparent strain per kelvin of the grating (seed 000: 8.64 um/m/K)"),
        Parameter("quantisation", "strain", 0.8e-6, 0.0, 100e-6, "reading resolution (1 pm at 1550 nm)"),
        Parameter("noise", "strain", 0.5e-6, 0.0, 100e-6, "noise standard deviation"),
    ),
}


def quantise(x: np.ndarray, q: float) -> np.ndarray:
    """Round to the nearest multiple of q (no-op for q = 0): n q with n = round(x / q). Where q is
    1/m for a whole m (0.1 um, 0.01 K, and 0.1 um reached as 0.1e-6 m x 1e6), the step is taken as
    n / m, the double nearest the decimal reading (n q gives 0.30000000000000004 for 3 x 0.1)."""
    if not q > 0:
        return np.asarray(x, dtype=float)
    n = np.round(np.asarray(x, dtype=float) / q)
    m = round(1.0 / q)
    return n / m if m >= 1 and abs(1.0 / q - m) <= 1e-9 * m else n * q


def temperature_reading(true: np.ndarray, dt: float, p: dict, rng: np.random.Generator) -> np.ndarray:
    """Sensor readings [degC] of true temperatures (ntime, nsensor) [degC] sampled every dt [s]."""
    lagged = lag_series(true, dt, p["lag"])
    return quantise(lagged + p["bias"] + p["noise"] * rng.standard_normal(true.shape), p["quantisation"])


def probe_reading(true_um: np.ndarray, p: dict, rng: np.random.Generator) -> np.ndarray:
    """Probe readings [um] of true displacements (ntime, nprobe) [um]."""
    noise_um, res_um = p["noise"] * 1e6, p["resolution"] * 1e6
    return quantise(true_um + noise_um * rng.standard_normal(true_um.shape), res_um)
