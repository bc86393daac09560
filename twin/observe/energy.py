"""The heat balance of a run: heat flow per effect and the first law over the whole run.

Rows: the stored heat E = 1^T M T [J] and, per convection load k, the surface integral
I_k = r_k^T T = int T dA [K m2]. Heat into the structure per load: sources P_j(t) [W]; convection
h_k(t) (T_air,k(t) A_k - I_k) [W] (negative when heat is lost); contacts exchange heat inside the
structure and carry none. The theta-scheme conserves energy exactly (:mod:`twin.physics.heat`):

    E_N - E_0 = dt sum_n [ sum_j s_j(t_n+theta) + sum_k h_k(t_n+theta) (T_air,k A_k - I_k^(n+theta)) ],
    I^(n+theta) = theta I^(n+1) + (1 - theta) I^n,

so the relative closure |sources + convection - stored| / max(|terms|) measures only the
round-off and the linear solver's tolerance.
"""

from __future__ import annotations

import numpy as np

from twin.observe.base import Observer, variable
from twin.signals import load_instants


class HeatBalance(Observer):
    """Variable ``heat_power(time, effect)`` [W]: heat flow into the structure per effect; attributes
    ``energy_sources_J``, ``energy_convection_J``, ``energy_stored_J``, ``energy_closure``."""

    key = "energy"
    raw_unit = "J (row 0: stored heat), K m2 (the others: int T dA of each convection load)"
    layout_cached = False

    def rows(self, twin, loads):
        ones_M = np.asarray(loads.heat.M.sum(axis=0)).ravel()
        return np.vstack([ones_M[None, :], loads.system.r.T])

    @staticmethod
    def flows(raw: np.ndarray, ctx) -> tuple[np.ndarray, np.ndarray]:
        """Heat into the structure at the output instants [W]: (sources (n_t, n_src), convection
        (n_t, n_cv))."""
        h, air, s = ctx.loads.signals(ctx.times)
        return s, h * (air * ctx.loads.areas - raw[:, 1:])

    @staticmethod
    def energy(raw: np.ndarray, ctx) -> tuple[float, float, float]:
        """(heat in by sources, heat in by convection (negative: lost), change of stored heat) [J]
        over the run, with the theta-scheme's own quadrature (exact balance)."""
        t, theta = ctx.times, ctx.theta
        if len(t) < 2:
            return 0.0, 0.0, 0.0
        dt = t[1] - t[0]
        h, air, s = ctx.loads.signals(load_instants(t, theta))
        integral = raw[:, 1:]
        mid = theta * integral[1:] + (1 - theta) * integral[:-1]
        return (float(dt * s.sum()), float(dt * np.sum(h * (air * ctx.loads.areas - mid))),
                float(raw[-1, 0] - raw[0, 0]))

    def data(self, raw, ctx):
        src, conv = self.flows(raw, ctx)
        effects = list(ctx.spec.effects)
        power = np.zeros((len(ctx.times), len(effects)))
        for j, e in enumerate(ctx.loads.source_effect):
            power[:, effects.index(e)] += src[:, j]
        for j, e in enumerate(ctx.loads.convection_effect):
            power[:, effects.index(e)] += conv[:, j]
        return ({"heat_power": variable(("time", "effect"), power, "W", "heat flow into the structure per effect")},
                {"effect": ("effect", effects, {"long_name": "physical effect"})})

    def attrs(self, raw, ctx) -> dict:
        sources, convection, stored = self.energy(raw, ctx)
        scale = max(abs(sources), abs(convection), abs(stored), 1e-300)
        return {"energy_sources_J": sources, "energy_convection_J": convection, "energy_stored_J": stored,
                "energy_closure": abs(sources + convection - stored) / scale}
