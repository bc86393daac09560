"""Snapshots of the whole temperature field (not linear in T, so kept by a step hook)."""

from __future__ import annotations

import numpy as np

from twin.observe.base import Observer


class HottestField(Observer):
    """The field at the instant its maximum is highest: ``time`` [s] and ``field`` [degC] on the
    temperature dofs (``mm.heat_node`` maps them to mesh nodes); the start field until a step
    is hotter. For ``twin simulate --field`` and the demo's 3-D picture."""

    key = "hottest"
    time: float = 0.0
    field: np.ndarray | None = None

    def start(self, T0):
        self.time, self.field, self.max = 0.0, np.array(T0, dtype=float), float(np.max(T0))

    def on_step(self, n, time, T):
        peak = float(T.max())
        if peak > self.max:
            self.max, self.time, self.field = peak, float(time), T.copy()
