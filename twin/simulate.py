"""Run one simulation: machine + effects + scenario -> transient heat -> observers.

Heat: :mod:`twin.physics.heat`. Drift: every displacement output (tool point relative to the
workpiece point in X, Y, Z; each ISO 230-3 probe relative to its fixture) is a linear functional
of the temperature rise, q(t) = W^T (T(t) - T_0), with W from one adjoint elastic solve per
observer (:mod:`twin.physics.prepared`); the displacement field itself is never formed in a run.
What is recorded is a list of observers (:func:`twin.observe.standard_observers` by default).
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field

import numpy as np

from twin.fem.mesh import MachineMesh
from twin.model import ModelSpec, default_spec
from twin.observe import HeatBalance, RunContext, TemperatureSensors, standard_observers
from twin.physics.loads import LoadSet
from twin.physics.prepared import PreparedTwin, check_prepared
from twin.physics.prepared_args import check_beside_prepared

SOURCE = "twin.simulate.run"


@dataclass
class RunResult:
    """Everything a run computed, before instruments and packaging: the raw readings of each
    observer (SI units, degC) and what produced them."""

    machine: object
    mm: MachineMesh
    scenario: object
    spec: ModelSpec
    loads: LoadSet
    times: np.ndarray
    theta: float
    observers: list
    readings: dict
    timings: dict = field(default_factory=dict)
    solver_info: dict = field(default_factory=dict)   # what solved it and each output's error

    def observer(self, key: str):
        """The run's observer with ``key`` (KeyError when the run had none)."""
        for o in self.observers:
            if o.key == key:
                return o
        raise KeyError(f"the run has no observer {key!r}")

    def context(self, seed: int = 0) -> RunContext:
        """What observers need to package their readings, with a generator seeded by ``seed``."""
        return RunContext(self.times, self.scenario, self.spec, self.machine, self.loads,
                          np.random.default_rng(seed), self.theta)

    @property
    def sensors(self) -> list:
        return self.observer("temperature").points

    @property
    def sensor_true(self) -> np.ndarray:
        """(n_t, n_sensor) true sensor temperatures [degC] (air sites read the model's air)."""
        obs: TemperatureSensors = self.observer("temperature")
        return obs.true_values(self.readings["temperature"], self.context())

    def _change_at_pose(self, key: str) -> np.ndarray:
        """A displacement observer's readings [m] at the pose of each instant (its raw rows with
        the moving axes' carry applied, :meth:`DisplacementObserver.readings`), as changes from
        the first instant."""
        at_pose = self.observer(key).readings(self.readings[key], self.context())
        return at_pose - at_pose[0]

    @property
    def drift(self) -> np.ndarray:
        """(n_t, 3) tool-point drift X, Y, Z [m], tool relative to the workpiece, at the pose."""
        return self._change_at_pose("drift")

    @property
    def probe(self) -> np.ndarray:
        """(n_t, n_probe) true probe readings [m], at the pose."""
        return self._change_at_pose("probes")

    @property
    def stored_heat(self) -> np.ndarray:
        """(n_t,) stored heat 1^T M T [J]."""
        return self.readings["energy"][:, 0]

    @property
    def hottest_time(self) -> float:
        return self.observer("hottest").time

    @property
    def hottest_field(self) -> np.ndarray:
        """(n_heat,) [degC] on the temperature dofs (``mm.heat_node`` maps them to nodes)."""
        return self.observer("hottest").field

    def heat_flows(self):
        """Heat into the structure per load at the output instants [W]: (sources (n_t, n_src),
        convection (n_t, n_cv)), see :class:`twin.observe.HeatBalance`."""
        return HeatBalance.flows(self.readings["energy"], self.context())

    def step_energy(self):
        """(heat in by sources, heat in by convection (negative when lost), change of stored
        heat) [J] over the run (:meth:`twin.observe.HeatBalance.energy`)."""
        return HeatBalance.energy(self.readings["energy"], self.context())


def run(machine, scenario, spec: ModelSpec | None = None, resolution: str | None = None, theta: float = 0.5,
        materials: dict | None = None, progress=None, mm: MachineMesh | None = None,
        sensors: list | None = None, prepared: PreparedTwin | None = None, observers: list | None = None,
        solver=None, idle_effects: bool = False) -> RunResult:
    """Simulate ``scenario`` on ``machine`` with the effects of ``spec`` (default: the machine's).

    ``materials`` maps a material name to a replacement (e.g. perturbed properties);
    ``progress(done, total)`` is called after every step; ``sensors`` (a list of
    :class:`geometries.base.Point`) replaces the machine's temperature-sensor sites; ``observers``
    replaces the whole standard set; ``prepared`` reuses a :class:`PreparedTwin` of the machine;
    ``solver`` (:class:`twin.physics.options.SolverOptions` or a name) chooses the solvers of a
    new one (default: by size). ``idle_effects``: an effect that cannot act in this run runs,
    doing nothing, instead of being refused (:meth:`PreparedTwin.run`). Beside ``prepared``, ``mm``, ``resolution``, ``materials`` and
    ``solver`` are left out or equal to its own (anything else is refused, never ignored);
    ``resolution`` with ``mm`` names the mesh's own resolution.
    """
    spec = spec or default_spec(machine)
    observers = observers if observers is not None else standard_observers(machine, sensors)
    t0 = _time.perf_counter()
    if prepared is not None:
        check_prepared(prepared, machine, SOURCE)
        check_beside_prepared(prepared, SOURCE, mm, resolution, materials, solver)
    twin = prepared or PreparedTwin(machine, mm, resolution, materials, solver)
    twin.adjoints(observers)   # factorise and solve the adjoints now, so that "preparation" holds them
    prep = _time.perf_counter() - t0
    times = scenario.times()

    t1 = _time.perf_counter()
    loads, readings = twin.run(scenario, spec, observers, theta, progress=progress, idle_effects=idle_effects)
    timings = {"preparation": prep, "time_stepping": _time.perf_counter() - t1, "steps": len(times) - 1}
    return RunResult(machine, loads.mm, scenario, spec, loads, times, theta, observers, readings, timings,
                     dict(twin.run_info))
