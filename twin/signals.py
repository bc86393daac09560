"""Small time-signal tools shared by effects and instruments."""

from __future__ import annotations

import numpy as np


def lag_series(x: np.ndarray, step: float, tau: float) -> np.ndarray:
    """First-order lag of samples x (axis 0 = time, spacing ``step`` [s]), tau [s], y(0) = x(0).

    tau dy/dt = x - y, exact for x linear between samples:
    y_i = a y_(i-1) + (1 - a) x_(i-1) + b (x_i - x_(i-1)), a = exp(-step/tau), b = 1 - tau (1 - a)/step.
    """
    x = np.asarray(x, dtype=float)
    if tau <= 0:
        return x.copy()
    a = np.exp(-step / tau)
    b = 1.0 - tau * (1.0 - a) / step
    y = np.empty_like(x)
    y[0] = x[0]
    for i in range(1, len(x)):
        y[i] = a * y[i - 1] + (1.0 - a) * x[i - 1] + b * (x[i] - x[i - 1])
    return y
