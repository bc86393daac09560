"""Run one simulation: machine + effects + scenario -> transient heat -> drift -> instruments.

Heat: :mod:`twin.physics.heat`. Drift: every displacement output (tool point relative to the
workpiece point in X, Y, Z; each ISO 230-3 probe relative to its fixture) is a linear functional
of the temperature rise, q(t) = W^T (T(t) - T_0), with W from one adjoint elastic solve per
output (:mod:`twin.physics.elastic`); the displacement field itself is never formed in a run.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field

import numpy as np

from twin.fem.mesh import MachineMesh
from twin.model import LoadSet, ModelSpec
from twin.physics.prepared import PreparedTwin, drift_functionals  # noqa: F401  (drift_functionals re-exported)

AXES = ("X", "Y", "Z")


@dataclass
class RunResult:
    """Everything a run computed, before instruments and packaging (SI units, degC)."""

    mm: MachineMesh
    scenario: object
    spec: ModelSpec
    loads: LoadSet
    times: np.ndarray
    theta: float
    sensor_true: np.ndarray        # (nt, nsensor) degC
    stored_heat: np.ndarray        # (nt,) J, 1^T M T
    surface_integral: np.ndarray   # (nt, ncv) int T dA per convection load [K m2]
    drift: np.ndarray              # (nt, 3) m, tool relative to workpiece
    probe: np.ndarray              # (nt, nprobe) m
    hottest_time: float
    hottest_field: np.ndarray      # (nheat,) degC on the temperature dofs (mm.heat_node maps them to nodes)
    sensors: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)

    def heat_flows(self):
        """Heat into the structure per load at the output instants [W]: sources P(t), and
        h (T_air A - int T dA) for convection loads. Returns (sources (nt, nsrc), conv (nt, ncv))."""
        h, air, s = self.loads.signals(self.times)
        return s, h * (air * self.loads.areas - self.surface_integral)

    def step_energy(self):
        """Energy accounting of the theta-scheme [J] over the whole run: (heat in by sources,
        heat in by convection (negative when lost), change of stored heat)."""
        dt = self.times[1] - self.times[0]
        h, air, s = self.loads.signals(self.times[:-1] + self.theta * dt)
        mid = self.theta * self.surface_integral[1:] + (1 - self.theta) * self.surface_integral[:-1]
        return (dt * s.sum(), dt * np.sum(h * (air * self.loads.areas - mid)),
                self.stored_heat[-1] - self.stored_heat[0])


def run(machine, scenario, spec: ModelSpec | None = None, resolution: str = "default", theta: float = 0.5,
        materials: dict | None = None, progress=None, mm: MachineMesh | None = None,
        sensors: list | None = None, prepared: PreparedTwin | None = None) -> RunResult:
    """Simulate ``scenario`` on ``machine`` with the effects of ``spec``.

    ``materials`` maps a material name to a replacement (e.g. perturbed properties);
    ``progress(done, total)`` is called after every step; ``sensors`` (a list of
    :class:`geometries.base.Point`) replaces the machine's temperature-sensor sites;
    ``prepared`` reuses a :class:`twin.physics.prepared.PreparedTwin` of the same machine and scenario.
    """
    spec = spec or ModelSpec()
    t0 = _time.perf_counter()
    twin = prepared or PreparedTwin(machine, scenario, mm, resolution, materials, sensors)
    prep = _time.perf_counter() - t0
    times = scenario.times()
    hottest = {"max": -np.inf, "time": 0.0, "field": None}

    def on_step(n, T):
        tmax = T.max()
        if tmax > hottest["max"]:
            hottest.update(max=tmax, time=times[n], field=T.copy())
        if progress is not None:
            progress(n, len(times) - 1)

    t1 = _time.perf_counter()
    loads, out = twin.run(spec, theta, on_step)
    timings = {"preparation": prep, "time_stepping": _time.perf_counter() - t1, "steps": len(times) - 1}
    if hottest["field"] is None:
        hottest["field"] = np.full(loads.mm.nheat, scenario.start_temperature)
    ns, ncv = len(twin.sensors), loads.system.r.shape[1]
    disp = out[:, ns + 1 + ncv:] - out[0, ns + 1 + ncv:]
    return RunResult(loads.mm, scenario, spec, loads, times, theta, out[:, :ns], out[:, ns], out[:, ns + 1:ns + 1 + ncv],
                     disp[:, :3], disp[:, 3:], hottest["time"], hottest["field"], twin.sensors, timings)
