"""Signatures of candidate effects: how every observable responds to one effect's strength.

An *observable vector* stacks, over time, every temperature sensor [degC] (through the sensor's
first-order lag and bias, without noise) and every ISO 230-3 probe reading [um]. For a model
``spec`` and a candidate effect E with strength parameter p, the signature is

    g_E(p) = y(spec + E(p)) - y(spec),

computed by two twin runs on one prebuilt mesh (:class:`Engine` assembles the heat matrices and
the adjoint drift influence vectors once and re-runs only the time stepping). Loads enter the
heat equation linearly (ARCHITECTURE: loads = fixed pattern x time signal), so when E contributes
only heat sources whose powers scale with p, g_E(p) = (p / p_ref) g_E(p_ref) exactly: one run.
Otherwise (a conductance h changes the operator, a time constant changes a signal shape) g is
nonlinear in p and the fit runs Gauss-Newton with finite-difference sensitivities dg/dp.

Fitting: with residual r = measurement - model and channel weights w,

    p_hat = argmin_{lower <= p <= upper} || w * (r - g_E(p)) ||^2

(``scipy.optimize.lsq_linear`` for the linear case). Nuisance responses (the model's own uncertain
parameters, e.g. the thermal expansion of each material) are fitted freely with every candidate:
they are profiled out by projecting r, g and dg/dp onto the complement of their weighted span.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import lsq_linear

from twin.effects import EFFECTS, HeatSource, SurfaceHeatFlux
from twin.model import ModelSpec
from twin.observe import (ExpansionSensitivity, FiveProbeTestBar, RunContext, TemperatureSensors,
                           sensor_points)
from twin.physics.prepared import PreparedTwin
from twin.signals import lag_series

def strength_parameter(effect) -> str | None:
    """Name of the parameter the diagnosis fits for ``effect`` (its declared ``strength``), or None
    when the effect has nothing to fit."""
    return effect.strength or None


def reference_value(param) -> float:
    """Reference strength p_ref for a signature: the default, or 10 % of the widest bound if the
    default is zero (a zero-strength run has no signature)."""
    if param.default != 0:
        return float(param.default)
    return 0.1 * (param.upper if abs(param.upper) >= abs(param.lower) else param.lower)


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
        um = (lambda key: (raw[key] - raw[key][0]) * 1e6)
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


def is_linear_source(effect: str, spec: ModelSpec, mm, scenario, pname: str, pref: float) -> bool:
    """True if E contributes only heat sources whose powers at 2 p_ref are exactly twice those at
    p_ref on the scenario grid (then the response is linear in p with g(0) = 0)."""
    eff = EFFECTS[effect]
    base = eff.defaults()
    t = scenario.times()
    try:
        a = eff.loads(mm, scenario, {**base, pname: pref})
        b = eff.loads(mm, scenario, {**base, pname: 2 * pref})
    except Exception:  # noqa: BLE001 - an effect that cannot be evaluated is treated as nonlinear
        return False
    if not a or len(a) != len(b) or not all(isinstance(x, (HeatSource, SurfaceHeatFlux)) for x in a + b):
        return False
    return all(np.allclose(y.power(t), 2 * x.power(t), rtol=1e-9, atol=1e-12) for x, y in zip(a, b))


@dataclass
class Fit:
    """A fitted candidate: effect name(s), fitted SI values, response, weighted SSE after."""

    effects: tuple[str, ...]
    values: dict[str, dict[str, float]]     # effect -> {param: SI value}
    response: np.ndarray                     # (nt, nch) fitted g
    sse: float                               # weighted sum of squares after
    nparams: int
    linear: dict[str, bool] = field(default_factory=dict)
    signature: dict[str, np.ndarray] = field(default_factory=dict)  # effect -> g at p_ref (per unit p)


class SignatureFitter:
    """Fits candidate effects to a weighted residual ``r`` (nt, nch) with weights ``w`` (nch,)."""

    def __init__(self, engine: Engine, spec: ModelSpec, base_obs: np.ndarray, residual: np.ndarray,
                 weights: np.ndarray, gn_iterations: int = 6, nuisance: np.ndarray | None = None):
        self.engine, self.spec, self.base = engine, spec, base_obs
        self.r, self.w, self.gn_iterations = residual, weights, gn_iterations
        # nuisance responses (k, nt, nch), fitted freely alongside every candidate: profiled out
        # by projecting every weighted vector onto the complement of their span (Q orthonormal)
        self.Q = self.N = None
        if nuisance is not None and len(nuisance):
            cols = np.column_stack([(n * weights).ravel() for n in nuisance])
            self.N = cols
            q, rr = np.linalg.qr(cols)
            keep = np.abs(np.diag(rr)) > 1e-10 * max(np.abs(np.diag(rr)).max(), 1e-300)
            self.Q = q[:, keep] if keep.any() else None

    def project(self, x: np.ndarray) -> np.ndarray:
        """A weighted, flattened vector with its nuisance component removed."""
        return x if self.Q is None else x - self.Q @ (self.Q.T @ x)

    def weighted(self, x: np.ndarray) -> np.ndarray:
        return self.project((x * self.w).ravel())

    def residual_after(self, g: np.ndarray) -> np.ndarray:
        """r - g - (the nuisance fitted to r - g), native units, shape of r."""
        return self.weighted(self.r - g).reshape(self.r.shape) / np.where(self.w > 0, self.w, 1.0)

    def nuisance_coefficients(self, g: np.ndarray) -> np.ndarray:
        """Amplitudes of the nuisance responses fitted (weighted least squares) to r - g; empty
        without nuisance."""
        if self.N is None:
            return np.zeros(0)
        return np.linalg.lstsq(self.N, ((self.r - g) * self.w).ravel(), rcond=None)[0]

    def sse(self, g: np.ndarray) -> float:
        return float(np.sum(self.weighted(self.r - g) ** 2))

    def response(self, effect: str, pname: str, value: float) -> np.ndarray:
        return self.engine.observe(with_effect(self.spec, effect, {pname: value})) - self.base

    def fit_single(self, effect: str) -> Fit | None:
        """Bounded least-squares fit of ``effect``'s strength; None if it has nothing to fit."""
        eff = EFFECTS[effect]
        pname = strength_parameter(eff)
        if pname is None:
            return None
        par = eff.parameter(pname)
        pref = reference_value(par)
        g_ref = self.response(effect, pname, pref)
        linear = is_linear_source(effect, self.spec, self.engine.mm, self.engine.scenario, pname, pref)
        unit = g_ref / pref
        A = self.weighted(unit).reshape(-1, 1)
        b = self.weighted(self.r)
        lo, hi = par.lower, par.upper
        p = float(lsq_linear(A, b, bounds=([lo], [hi])).x[0]) if np.any(A) else pref
        if linear:
            g = unit * p
        else:
            p, g = self._gauss_newton(effect, pname, par, p if p != 0 else pref)
        return Fit((effect,), {effect: {pname: p}}, g, self.sse(g), 1, {effect: linear}, {effect: unit})

    def _gauss_newton(self, effect, pname, par, p0):
        """Bounded scalar Gauss-Newton: p <- clip(p + J.(r - g) / J.J), J = dg/dp by forward
        differences (step 2 % of |p|), keeping the best point seen."""
        p = float(np.clip(p0, par.lower, par.upper))
        g = self.response(effect, pname, p)
        best = (self.sse(g), p, g)
        span = par.upper - par.lower
        for _ in range(self.gn_iterations):
            dp = 0.02 * max(abs(p), 1e-3 * span)
            if p + dp > par.upper:
                dp = -dp
            J = (self.response(effect, pname, p + dp) - g) / dp
            Jw, rw = self.weighted(J), self.weighted(self.r - g)
            denom = float(np.sum(Jw * Jw))
            if denom == 0:
                break
            p_new = float(np.clip(p + np.sum(Jw * rw) / denom, par.lower, par.upper))
            g_new = self.response(effect, pname, p_new)
            s_new = self.sse(g_new)
            if s_new < best[0]:
                best = (s_new, p_new, g_new)
            if abs(p_new - p) <= 1e-3 * max(abs(p), 1e-6 * span):
                break
            p, g = p_new, g_new
        return best[1], best[2]

    def fit_pair(self, a: Fit, b: Fit) -> Fit:
        """Joint bounded fit of two candidates. Each member's response is linearised about its
        single fit, g_i(p) ~ (p / p_i) g_i(p_i) (exact for linear sources), and the two
        amplitudes are fitted together by ``lsq_linear`` within the members' bounds."""
        cols, lo, hi, names = [], [], [], []
        for f in (a, b):
            (eff, vals), = f.values.items()
            (pname, p), = vals.items()
            par = EFFECTS[eff].parameter(pname)
            if p == 0:
                p = reference_value(par)
                shape = f.signature[eff] * p
            else:
                shape = f.response
            cols.append(self.weighted(shape))
            lo.append(par.lower / p if p > 0 else par.upper / p)
            hi.append(par.upper / p if p > 0 else par.lower / p)
            names.append((eff, pname, p, shape))
        A = np.column_stack(cols)
        sol = lsq_linear(A, self.weighted(self.r), bounds=(lo, hi)).x
        g = sum(c * n[3] for c, n in zip(sol, names))
        values = {n[0]: {n[1]: float(c * n[2])} for c, n in zip(sol, names)}
        return Fit(a.effects + b.effects, values, g, self.sse(g), 2, {**a.linear, **b.linear},
                   {**a.signature, **b.signature})
