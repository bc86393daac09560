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


INSIDE = 1e-9   # [-] of a step: the left limit at its end (a step's inputs hold on [t_n, t_(n+1)))


def load_instants(times: np.ndarray, theta: float) -> np.ndarray:
    """The instants [s] at which step n -> n+1 of the uniform grid ``times`` reads its loads,
    t_n + theta dt, no later than t_(n+1) - INSIDE dt: the theta-scheme's f(t_n + theta dt) for a
    piecewise-constant input (a spindle step on [start, end), a feed drive's step average) is then
    the value the input holds during the step, also at theta = 1, where t_(n+1) itself is the next
    step's start. The moved instant changes a smooth input by its slope times 1e-9 dt."""
    times = np.asarray(times, float)
    if len(times) < 2:
        return times[:0]
    dt = times[1] - times[0]
    return times[:-1] + min(theta, 1.0 - INSIDE) * dt
