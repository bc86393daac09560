"""The sensor chain of an uncooled microbolometer camera: noise, offset drift and 14-bit counts.

The detector's signal is linear in the radiance W reaching it [W/(m2 sr)]; the ADC maps it to
counts c = round(c_0 + G W), clipped to [0, 2^bits - 1], with G and c_0 chosen so that blackbodies
at the ends of the camera's range (S65: -40 and +120 degC) give counts 0 and 2^bits - 1.

Noise, in the standard 3-D noise components (t: frame, v: row, h: column; D'Agostino & Webb 1991,
"Three-dimensional analysis framework and measurement methodology for imaging system noise",
Proc. SPIE 1488), each given as a temperature-equivalent standard deviation at the reference
temperature (NETD is specified "0.08 K at 30 degC") and added to the signal as
sigma dL/dT(T_ref):

* temporal, per pixel and frame (sigma_tvh): the NETD;
* fixed pattern, per pixel (sigma_vh), and fixed row and column banding (sigma_v, sigma_h): drawn
  once per run (the residual of the camera's non-uniformity correction);
* temporal row and column banding (sigma_tv, sigma_th) and frame flicker (sigma_t): new each frame;
* a slowly drifting offset common to all pixels: an initial offset N(0, sigma_0) plus an
  Ornstein-Uhlenbeck drift of standard deviation sigma_d and time constant tau (exact update
  x_k+1 = a x_k + sqrt(1 - a^2) sigma_d xi, a = exp(-dt / tau)), the sum clipped to the accuracy
  spec (+-2 K: "usually in the order of +-2 degC", seed 001 L116).

The banding and drift defaults are plausible values for an uncooled camera, not measured on an
S65; the NETD and the accuracy are the seed's. All draws come from one seeded generator in a
fixed order (fixed patterns, offset series, then frame by frame), so frames are bit-identical for
the same seed and independent of how the frames are processed in blocks. The per-frame noise is
drawn in single precision (it is 1e-3 of a count at most; twice as fast).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np


@dataclass(frozen=True)
class Microbolometer:
    """Sensor-chain parameters: temperature-equivalent standard deviations [K] at
    ``reference_temperature`` [degC], the offset drift (``drift_time`` [s]), the accuracy bound [K]
    and the ADC (``bits``, ``range`` [degC] of blackbodies at the lowest and highest count)."""

    netd: float = 0.08
    reference_temperature: float = 30.0
    fixed_pattern: float = 0.03
    row_fixed: float = 0.02
    column_fixed: float = 0.02
    row_temporal: float = 0.01
    column_temporal: float = 0.01
    frame_temporal: float = 0.0
    offset: float = 0.5
    drift: float = 0.3
    drift_time: float = 1800.0
    accuracy: float = 2.0
    bits: int = 14
    range: tuple[float, float] = (-40.0, 120.0)

    def noiseless(self) -> "Microbolometer":
        """The same ADC with every noise and offset term zero (for checks against closed forms)."""
        zero = {k: 0.0 for k in ("netd", "fixed_pattern", "row_fixed", "column_fixed", "row_temporal",
                                  "column_temporal", "frame_temporal", "offset", "drift")}
        return Microbolometer(**{**asdict(self), **zero})

    def as_dict(self) -> dict:
        """The parameters with their units in their names (a result's ``camera`` attribute)."""
        units = {"netd": "K", "reference_temperature": "degC", "fixed_pattern": "K", "row_fixed": "K",
                 "column_fixed": "K", "row_temporal": "K", "column_temporal": "K", "frame_temporal": "K",
                 "offset": "K", "drift": "K", "drift_time": "s", "accuracy": "K", "range": "degC"}
        return {f"{k}_{units[k]}" if k in units else k: list(v) if isinstance(v, tuple) else v
                for k, v in asdict(self).items()}


class SensorChain:
    """One run of one camera: the ADC of ``params`` on radiance ``table``, the fixed patterns and
    the offset series for frames ``shape`` = (H, W) at instants ``frame_times`` [s], drawn from
    ``rng``; :meth:`counts` then turns signal blocks into counts, frame by frame, in order."""

    def __init__(self, params: Microbolometer, table, shape: tuple[int, int], frame_times: np.ndarray,
                 rng: np.random.Generator):
        self.p, self.shape, self.rng = params, shape, rng
        lo, hi = table.radiance(np.array(params.range))
        self.top = 2 ** params.bits - 1
        self.gain = self.top / (hi - lo)          # counts per W/(m2 sr)
        self.zero = -lo * self.gain               # c_0
        self.kelvin = table.slope(params.reference_temperature)  # W/(m2 sr) per K at T_ref
        H, W = shape
        p = params
        self.fixed = (p.fixed_pattern * rng.standard_normal((H, W)) + p.row_fixed * rng.standard_normal((H, 1))
                      + p.column_fixed * rng.standard_normal((1, W)))
        self.offset = self._offset_series(np.asarray(frame_times, dtype=float))
        self.next = 0

    def _offset_series(self, t: np.ndarray) -> np.ndarray:
        p = self.p
        n = len(t)
        x = np.empty(n)
        start = p.offset * self.rng.standard_normal()
        xi = self.rng.standard_normal(n)
        drift = p.drift * xi[0] if n else 0.0
        for k in range(n):
            if k:
                a = np.exp(-(t[k] - t[k - 1]) / p.drift_time) if p.drift_time > 0 else 0.0
                drift = a * drift + np.sqrt(1 - a * a) * p.drift * xi[k]
            x[k] = drift
        return np.clip(start + x, -p.accuracy, p.accuracy)

    def counts(self, signal: np.ndarray) -> np.ndarray:
        """uint16 counts (n, H, W) of the next n frames' radiance ``signal`` (n, H, W)."""
        p, (H, W) = self.p, self.shape
        n = len(signal)
        k = slice(self.next, self.next + n)
        self.next += n
        noise_k = np.empty((n, H, W), dtype=np.float32)
        normal = self.rng.standard_normal
        for i in range(n):
            frame = normal((H, W), dtype=np.float32) * np.float32(p.netd)
            frame += (p.row_temporal * normal((H, 1)) + p.column_temporal * normal((1, W))
                      + p.frame_temporal * normal()).astype(np.float32)
            noise_k[i] = frame
        noise_k += (self.fixed[None] + self.offset[k][:, None, None]).astype(np.float32)
        c = np.rint(self.zero + self.gain * (signal + self.kelvin * noise_k))
        return np.clip(c, 0, self.top).astype(np.uint16)

    def radiance_of(self, counts: np.ndarray) -> np.ndarray:
        """The radiance [W/(m2 sr)] the camera infers from ``counts`` (inverse of its ADC)."""
        return (np.asarray(counts, dtype=float) - self.zero) / self.gain
