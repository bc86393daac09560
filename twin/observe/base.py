"""Observers: what an instrument would record, as objects.

An observer is linear in the temperature field wherever the physics allows it: it gives the
prepared twin a matrix of *rows* R (k, n_heat) once per temperature layout, the twin stacks the
rows of every observer of a run into one output operator and records R @ T at every output
instant (``raw``, shape (n_t, k)), and the observer turns its own raw block into named data
variables, applying its instrument model (lag, noise, quantisation, bias) with a seeded
generator while keeping the noise-free truth. Nobody but the twin knows where one observer's
rows sit among the others'.

Displacement observers (tool-point drift, probes, strain gauges) are linear functionals of the
displacement, q = G u = G K^-1 C (T - T_ref): their rows are (C^T lam)^T with one adjoint solve
K lam = G^T per observer, computed once by the prepared twin (:mod:`twin.physics.prepared`).

Observers that are not linear in T (a snapshot of the hottest field) use :meth:`Observer.on_step`.

An observer that records only some instants (a camera taking a frame every N output steps) says
which in :meth:`Observer.sample_steps`; the twin then keeps its rows apart, records R @ T only at
those steps (in ``raw_dtype``) and hands it a raw block with one row per sample. Its rows may be a
scipy sparse matrix (a camera's pixel operator has ~8 entries per row), which the twin never
densifies.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class RunContext:
    """What an observer may use to package its readings: the run's output instants ``times``
    [s], the scenario, the model spec (instrument parameters live in ``spec.params``), the
    machine, the loads of the run and a seeded random generator for the instrument noise."""

    times: np.ndarray
    scenario: object
    spec: object
    machine: object
    loads: object
    rng: np.random.Generator
    theta: float = 0.5
    extra: dict = field(default_factory=dict)


class Observer:
    """Base class. Subclasses set ``key`` (unique in a run) and implement :meth:`rows` (or
    :meth:`on_step`) and :meth:`data`.

    ``layout_cached``: the rows depend only on the temperature layout (and the twin's elastic
    solution), so the twin builds them once per layout; False when they depend on the run's loads.
    """

    key: str = ""
    raw_unit: str = ""       # SI unit of the raw readings R @ T (a solver's per-output errors are in it)
    layout_cached: bool = True
    raw_dtype = np.float64  # dtype of the raw block of a sampled observer (see sample_steps)

    def cache_key(self) -> tuple:
        """Identity of the rows for the twin's cache: observers with equal keys share rows."""
        return (type(self).__name__, self.key)

    def rows(self, twin, loads) -> np.ndarray | None:
        """(k, n_heat) rows (dense or scipy sparse) on the temperature dofs of ``loads.mm``; None
        for step-hook observers."""
        return None

    def check(self, scenario, machine) -> None:
        """Raise :class:`twin.errors.InputError` unless this observer can read ``scenario`` on
        ``machine`` (an instrument with its own instants checks them against the run's grid);
        the twin calls it before a run."""

    def sample_steps(self, times: np.ndarray) -> np.ndarray | None:
        """Indices into the run's output instants ``times`` [s] at which this observer records;
        None (the default) records every instant in the twin's stacked output operator."""
        return None

    def start(self, T0: np.ndarray) -> None:
        """Called before the first step with the start field (step-hook observers reset here)."""

    def on_step(self, n: int, time: float, T: np.ndarray) -> None:
        """Called after every time step with the new field (observers that are not linear in T)."""

    def data(self, raw: np.ndarray, ctx: RunContext) -> tuple[dict, dict]:
        """(data variables, coordinates) for the result Dataset from this observer's ``raw``
        readings (n_t, k); each variable is ``(dims, values, {"units": ..., "long_name": ...})``."""
        return {}, {}

    def attrs(self, raw: np.ndarray, ctx: RunContext) -> dict:
        """Result attributes this observer contributes (e.g. the energy balance)."""
        return {}


def variable(dims, values, units: str, long_name: str) -> tuple:
    """One Dataset variable with CF ``units`` and ``long_name``."""
    return (dims, np.asarray(values), {"units": units, "long_name": long_name})


def error_units(observers) -> dict[str, str]:
    """{observer key: unit of its raw readings}: the units of a run's per-output solver errors."""
    return {o.key: o.raw_unit for o in observers}
