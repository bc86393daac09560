"""Signatures of candidates: how every observable responds to a change of the model.

An *observable vector* stacks, over time, every temperature sensor [degC] (through the sensor's
first-order lag and bias, without noise) and every ISO 230-3 probe reading [um]. For a model
``spec`` and a candidate c at value p (:mod:`validate.candidates`) the signature is

    g_c(p) = y(spec with c = p) - y(spec),

computed by twin runs on one prebuilt mesh (:class:`Engine` assembles the heat matrices and the
adjoint drift influence vectors once and re-runs only the time stepping). Loads enter the heat
equation linearly (ARCHITECTURE: loads = fixed pattern x time signal), so when c only scales heat
sources, g_c(p) = (p - p_0) u_c exactly: one run. Otherwise (a conductance changes the operator,
a time constant changes a signal's shape) g is nonlinear in p and :mod:`validate.fit` runs
Gauss-Newton on it.
"""

from __future__ import annotations

import numpy as np

from twin.effects import EFFECTS
from twin.model import ModelSpec
from twin.observe import (ExpansionSensitivity, FiveProbeTestBar, RunContext, TemperatureSensors,
                           sensor_points)
from twin.physics.prepared import PreparedTwin
from twin.signals import lag_series


class Engine:
    """A twin prepared once (:class:`twin.physics.prepared.PreparedTwin`, or ``prepared``) for
    many runs of one scenario, observed at the temperature sensors and the probes; :meth:`observe`
    then costs one transient integration. Equivalent to :func:`twin.simulate.run` (tested)
    restricted to sensors and probes.
    """

    def __init__(self, machine, scenario, resolution: str = "coarse", mm=None, materials: dict | None = None,
                 sensors: list | None = None, prepared: PreparedTwin | None = None):
        self.machine, self.scenario = machine, scenario
        self.twin = prepared or PreparedTwin(machine, mm, resolution, materials)
        self.mm = self.twin.mm
        self.temperature = TemperatureSensors(sensors if sensors is not None else sensor_points(machine))
        self.sensors = self.temperature.points
        self.nsensor = len(self.sensors)
        self.probes = FiveProbeTestBar() if machine.probes else None
        self.probe_names = [p.name for p in machine.probes]
        self.times = scenario.times()
        self.runs = 0

    def _run(self, spec: ModelSpec, materials: tuple[str, ...] = ()) -> tuple[np.ndarray, np.ndarray]:
        """The true observables (nt, nsensor + nprobe) (sensor temperatures [degC], probe readings
        [um]) and the responses (nmat, nt, nsensor + nprobe) to a unit relative change of each
        material's expansion coefficient (zero on temperatures), from one run."""
        observers = [self.temperature] + ([self.probes] if self.probes else [])
        observers += [ExpansionSensitivity(m, self.probes) for m in materials if self.probes]
        loads, raw = self.twin.run(self.scenario, spec, observers)
        self.runs += 1
        ctx = RunContext(self.times, self.scenario, spec, self.machine, loads, np.random.default_rng(0))
        temps = self.temperature.true_values(raw["temperature"], ctx)
        um = (lambda key: self.probes.change_um(self.probes.readings(raw[key], ctx)))   # at the pose
        probes = um("probes") if self.probes else np.zeros((len(self.times), 0))
        responses = np.zeros((len(materials), len(self.times), self.nsensor + probes.shape[1]))
        for k, o in enumerate(observers[2:] if self.probes else []):
            responses[k, :, self.nsensor:] = um(o.key)
        return np.hstack([temps, probes]), responses

    def true_outputs(self, spec: ModelSpec) -> np.ndarray:
        """(nt, nsensor + nprobe): true sensor temperatures [degC], then probe readings [um]."""
        return self._run(spec)[0]

    def observe(self, spec: ModelSpec) -> np.ndarray:
        """Like :meth:`true_outputs` with the temperature-sensor lag and bias applied (no noise)."""
        return self.observe_with_expansion(spec, [])[0]

    def observe_with_expansion(self, spec: ModelSpec, materials: list[str]) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`observe` and, from the same run, the response of every observable to a unit
        relative change of each material's expansion coefficient, d y / d(alpha_m / alpha_m0)
        (nmat, nt, nsensor + nprobe) (:class:`twin.observe.ExpansionSensitivity`): zero on the
        temperatures, probe readings in um on the probes. Drift is linear in each alpha for the
        run's temperatures, so y + sum_m c_m response_m is the run with every alpha_m scaled by
        (1 + c_m), exactly."""
        out, responses = self._run(spec, tuple(materials))
        p = spec.params["temperature_sensor"]
        out[:, :self.nsensor] = lag_series(out[:, :self.nsensor], self.scenario.sample_interval, p["lag"]) + p["bias"]
        return out, responses


def with_effect(spec: ModelSpec, effect: str, values: dict[str, float]) -> ModelSpec:
    """A copy of ``spec`` with ``effect`` switched on and its parameters ``values`` (SI) set."""
    params = {g: dict(v) for g, v in spec.params.items()}
    params[effect] = {**EFFECTS[effect].defaults(), **values}
    return ModelSpec(tuple(spec.effects) + (effect,), params)
