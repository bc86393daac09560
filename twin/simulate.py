"""Run one simulation: machine + effects + scenario -> transient heat -> drift -> instruments.

Heat: :mod:`twin.transient`. Drift: every displacement output (tool point relative to the
workpiece point in X, Y, Z; each ISO 230-3 probe relative to its fixture) is a linear functional
of the temperature rise, q(t) = W^T (T(t) - T_0), with W from one adjoint elastic solve per
output (:mod:`twin.elastic`); the displacement field itself is never formed in a run.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from twin.assembly import assemble_heat
from twin.elastic import ElasticSolver
from twin.mesh import MachineMesh
from twin.model import LoadSet, ModelSpec, build_loads
from twin.points import displacement_functional, interpolation_matrix
from twin.transient import integrate

AXES = ("X", "Y", "Z")
_UNIT = np.eye(3)


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
    hottest_field: np.ndarray
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


def drift_functionals(mm: MachineMesh) -> sp.csr_matrix:
    """Rows: tool-minus-workpiece displacement X, Y, Z, then each probe's reading [m per m]."""
    machine = mm.machine
    pts = {name: interpolation_matrix(mm, [machine.point(name).xyz], [name])
           for name in {machine.tool_point, machine.workpiece_point}
           | {p.target for p in machine.probes} | {p.fixture for p in machine.probes}}
    rows = [displacement_functional(pts[machine.tool_point], _UNIT[d])
            - displacement_functional(pts[machine.workpiece_point], _UNIT[d]) for d in range(3)]
    rows += [displacement_functional(pts[p.target], p.direction) - displacement_functional(pts[p.fixture], p.direction)
             for p in machine.probes]
    return sp.vstack(rows).tocsr()


def run(machine, scenario, spec: ModelSpec | None = None, resolution: str = "default", theta: float = 0.5,
        materials: dict | None = None, progress=None, mm: MachineMesh | None = None,
        sensors: list | None = None) -> RunResult:
    """Simulate ``scenario`` on ``machine`` with the effects of ``spec``.

    ``materials`` maps a material name to a replacement (e.g. perturbed properties);
    ``progress(done, total)`` is called after every step; ``sensors`` (a list of
    :class:`geometries.base.Point`) replaces the machine's temperature-sensor sites.
    """
    spec = spec or ModelSpec()
    timings = {}
    t0 = _time.perf_counter()
    mm = mm or machine.mesh(resolution)
    mats = {p.name: materials[p.material.name] for p in machine.parts if materials and p.material.name in materials}
    heat = assemble_heat(mm, mats)
    loads = build_loads(mm, scenario, spec, heat)
    timings["heat_assembly"] = _time.perf_counter() - t0

    t1 = _time.perf_counter()
    elastic = ElasticSolver.build(mm, mats)
    timings["elastic_factorisation"] = _time.perf_counter() - t1
    W = elastic.influence(drift_functionals(mm))  # (nnodes, 3 + nprobe)

    sensors = sensors if sensors is not None else [machine.point(name) for name in machine.sensor_sites]
    S = interpolation_matrix(mm, [p.xyz for p in sensors], [p.name for p in sensors]).toarray()
    ones_M = np.asarray(heat.M.sum(axis=0)).ravel()
    outputs = np.vstack([S, ones_M[None, :], loads.system.r.T, W.T])

    times = scenario.times()
    dt = scenario.sample_interval
    h, air, s = loads.signals(times[:-1] + theta * dt)
    T0 = np.full(mm.nnodes, scenario.start_temperature)
    hottest = {"max": -np.inf, "time": 0.0, "field": T0}

    def on_step(n, T):
        tmax = T.max()
        if tmax > hottest["max"]:
            hottest.update(max=tmax, time=times[n], field=T.copy())
        if progress is not None:
            progress(n, len(times) - 1)

    t2 = _time.perf_counter()
    out = integrate(loads.system, T0, dt, len(times) - 1, h, air, s, sp.csr_matrix(outputs), theta, on_step)
    timings["time_stepping"] = _time.perf_counter() - t2
    timings["steps"] = len(times) - 1
    ns, ncv = len(sensors), loads.system.r.shape[1]
    disp = out[:, ns + 1 + ncv:] - out[0, ns + 1 + ncv:]
    return RunResult(mm, scenario, spec, loads, times, theta, out[:, :ns], out[:, ns], out[:, ns + 1:ns + 1 + ncv],
                     disp[:, :3], disp[:, 3:], hottest["time"], hottest["field"], sensors, timings)
