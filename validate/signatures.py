"""Signatures of candidates: how every observable responds to a change of the model.

An *observable vector* stacks, over time, every channel a machine's instruments give
(:mod:`validate.channels`): the temperature sensors [degC] (through the sensor's first-order lag
and bias, without noise), the ISO 230-3 probes [um], the laser triangulation sensors [um] and the
FBG strain gauges [um/m], each gauge both compensated (``strain``) and raw (``strain_raw``), and,
when the scenario runs a laser interferometer, its positioning error at every target [um] at every
instant (``positioning``; a measurement has it at the runs only):

    eps_raw = eps + k_T dT_g,   eps_comp = eps_raw - k_T (lag(T_s) - lag(T_s)(0)),

eps the mean mechanical-plus-thermal strain along the fibre, T_g the grating's mean temperature,
T_s the compensating sensor (:mod:`twin.observe.strain`), without noise or quantisation. For a
model ``spec`` and a candidate c at value p (:mod:`validate.candidates`) the signature is

    g_c(p) = y(spec with c = p) - y(spec),

computed by twin runs on one prebuilt mesh (:class:`Engine` assembles the heat matrices and the
adjoint drift influence vectors once and re-runs only the time stepping). Loads enter the heat
equation linearly (ARCHITECTURE: loads = fixed pattern x time signal), so when c only scales heat
sources, g_c(p) = (p - p_0) u_c exactly: one run. Otherwise (a conductance changes the operator,
a time constant changes a signal's shape) g is nonlinear in p and :mod:`validate.fit` runs
Gauss-Newton on it.
"""

from __future__ import annotations

import copy

import numpy as np

from twin.effects import EFFECTS
from twin.model import ModelSpec
from twin.observe import (ExpansionSensitivity, FiveProbeTestBar, LaserTriangulation, RunContext, StrainGauges,
                          TemperatureSensors, sensor_points)
from twin.observe.interferometer import PositioningTrace, check_interferometer
from twin.physics.prepared import PreparedTwin
from twin.physics.prepared_args import check_beside_prepared, coarse_unless_given
from validate.channels import target_label
from twin.signals import lag_series

DISPLACEMENT_GROUPS = ("probe", "laser", "positioning", "strain", "strain_raw")   # groups that respond to the expansion


class Engine:
    """A twin prepared once (:class:`twin.physics.prepared.PreparedTwin`, or ``prepared``) for
    many runs of one scenario, observed at the temperature sensors, the probes, the laser
    triangulation sensors and the FBG gauges the machine has; :meth:`observe` then costs one
    transient integration. Equivalent to :func:`twin.simulate.run` (tested) restricted to these
    instruments. ``names``: the channel name of every output column.
    """

    def __init__(self, machine, scenario, resolution: str | None = None, mm=None, materials: dict | None = None,
                 sensors: list | None = None, prepared: PreparedTwin | None = None):
        self.machine, self.scenario = machine, scenario
        if prepared is not None:
            check_beside_prepared(prepared, "validate.signatures.Engine", mm, resolution, materials)
        self.twin = prepared or PreparedTwin(machine, mm, coarse_unless_given(mm, resolution), materials)
        self.mm = self.twin.mm
        self.temperature = TemperatureSensors(sensors if sensors is not None else sensor_points(machine))
        self.sensors = self.temperature.points
        self.nsensor = len(self.sensors)
        self.probes = FiveProbeTestBar() if machine.probes else None
        self.probe_names = [p.name for p in machine.probes]
        self.lasers = LaserTriangulation() if machine.lasers else None
        self.laser_names = [p.name for p in machine.lasers]
        config = getattr(scenario, "interferometer", None)
        if config is not None:                      # as a simulation checks it: a clean error, not a KeyError
            check_interferometer(config, scenario, machine)
        self.positioning = PositioningTrace(config, machine) if config is not None else None
        self.target_names = ([target_label(t * 1e3) for t in self.positioning.targets]
                             if self.positioning is not None else [])
        self.strain = StrainGauges(machine.strain_gauges) if machine.strain_gauges else None
        self.gauge_names = [g.name for g in machine.strain_gauges]
        self.readers = [o for o in (self.probes, self.lasers, self.positioning) if o is not None]
        self.displacements = self.readers + ([self.strain] if self.strain is not None else [])
        self.names = ([f"temperature:{p.name}" for p in self.sensors] + [f"probe:{n}" for n in self.probe_names]
                      + [f"laser:{n}" for n in self.laser_names] + [f"positioning:{n}" for n in self.target_names]
                      + [f"strain:{n}" for n in self.gauge_names]
                      + [f"strain_raw:{n}" for n in self.gauge_names])
        self.groups = [n.split(":", 1)[0] for n in self.names]
        self.times = scenario.times()
        self.runs = 0
        self._last = None   # (spec, materials, outputs) of the last run: records sharing this engine reuse it

    def observers(self, materials: tuple[str, ...] = ()) -> list:
        """The observers of one run: temperatures, the displacement-like instruments, and each
        material's expansion sensitivity of every displacement-like instrument."""
        return ([self.temperature] + self.displacements
                + [ExpansionSensitivity(m, o) for m in materials for o in self.displacements])

    def readings(self, raw: dict, spec: ModelSpec, dt: float, lag: bool = True, bias: bool = True) -> np.ndarray:
        """(n_t, n_columns) in the order of :attr:`names` from one run's (or one response's) raw
        observer outputs ``raw`` on a grid of step ``dt`` [s]: temperatures [degC] (through the
        sensor lag when ``lag``, plus its bias when ``bias``), probe and laser readings [um] and
        strains [um/m] (module docstring; the compensating sensor lagged when ``lag``), positioning
        errors [um], changes from the first instant for all but the temperatures."""
        p = spec.params["temperature_sensor"]
        delay = (lambda x: lag_series(x, dt, p["lag"])) if lag else (lambda x: x)
        temps = delay(raw["temperature"]) + (p["bias"] if bias else 0.0)
        cols = [temps]
        cols += [(raw[o.key] - raw[o.key][0]) * 1e6 for o in self.readers]
        if self.strain is not None:
            k = len(self.gauge_names)
            s = raw[self.strain.key] - raw[self.strain.key][0]
            kt = spec.params["fbg"]["cross_sensitivity"] * 1e6
            apparent = s[:, :k] * 1e6 + kt * s[:, k:2 * k]
            sensor = delay(s[:, 2 * k:])
            cols += [apparent - kt * (sensor - sensor[0]), apparent]
        return np.hstack(cols) if cols else np.zeros((len(temps), 0))

    def expansion_columns(self, raw: dict, materials: tuple[str, ...]) -> np.ndarray:
        """(nmat, n_t, n_columns): each material's expansion response (zero on temperatures; um on
        probes and lasers, um/m on both strain readings: the grating's cross-sensitivity does not
        depend on alpha)."""
        out = np.zeros((len(materials), len(self.times), len(self.names)))
        for k, m in enumerate(materials):
            start = self.nsensor
            for o in self.displacements:
                key = ExpansionSensitivity(m, o).key
                um = (raw[key] - raw[key][0]) * 1e6
                copies = 2 if o is self.strain else 1
                for _ in range(copies):
                    out[k, :, start:start + um.shape[1]] = um
                    start += um.shape[1]
        return out

    def _run(self, spec: ModelSpec, materials: tuple[str, ...] = (), instrument: bool = True):
        """The observables (nt, n_columns) and the responses (nmat, nt, n_columns) to a unit
        relative change of each material's expansion coefficient, from one run."""
        # one model is fitted to every record: an effect acting in another record does nothing here
        loads, raw = self.twin.run(self.scenario, spec, self.observers(materials), idle_effects=True)
        self.runs += 1
        ctx = RunContext(self.times, self.scenario, spec, self.machine, loads, np.random.default_rng(0))
        posed = {o.key: o.readings(raw[o.key], ctx) for o in self.readers}
        posed.update({ExpansionSensitivity(m, o).key: o.readings(raw[ExpansionSensitivity(m, o).key], ctx)
                      for m in materials for o in self.readers})
        raw = dict(raw, temperature=self.temperature.true_values(raw["temperature"], ctx), **posed)   # at the pose
        out = self.readings(raw, spec, self.scenario.sample_interval, lag=instrument, bias=instrument)
        return out, self.expansion_columns(raw, materials)

    def true_outputs(self, spec: ModelSpec) -> np.ndarray:
        """(nt, n_columns): true sensor temperatures [degC], probe and laser readings [um],
        strains [um/m] (compensated by the sensor's true temperature), no instrument model."""
        return self._run(spec, instrument=False)[0]

    def observe(self, spec: ModelSpec) -> np.ndarray:
        """Like :meth:`true_outputs` with the temperature-sensor lag and bias applied (no noise)."""
        return self.observe_with_expansion(spec, [])[0]

    def observe_with_expansion(self, spec: ModelSpec, materials: list[str]) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`observe` and, from the same run, the response of every observable to a unit
        relative change of each material's expansion coefficient, d y / d(alpha_m / alpha_m0)
        (nmat, nt, n_columns) (:class:`twin.observe.ExpansionSensitivity`): zero on the
        temperatures, readings in um (um/m) on the displacement-like channels. Drift and strain
        are linear in each alpha for the run's temperatures, so y + sum_m c_m response_m is the
        run with every alpha_m scaled by (1 + c_m), exactly. The same ``spec`` and materials as the
        last call return its arrays without a new run (records that share this engine)."""
        key = (copy.deepcopy(spec), tuple(materials))
        if self._last is not None and self._last[0] == key:
            return self._last[1]
        out = self._run(spec, tuple(materials))
        self._last = (key, out)
        return out


def with_effect(spec: ModelSpec, effect: str, values: dict[str, float]) -> ModelSpec:
    """A copy of ``spec`` with ``effect`` switched on and its parameters ``values`` (SI) set."""
    params = {g: dict(v) for g, v in spec.params.items()}
    params[effect] = {**EFFECTS[effect].defaults(), **values}
    return ModelSpec(tuple(spec.effects) + (effect,), params)
