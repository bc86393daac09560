"""Effects: physical mechanisms registered by name, each returning loads.

An effect declares its parameters (name, dimension/unit, default, bounds, doc) and, for a meshed
machine and a scenario, returns loads that are a *fixed spatial pattern times a time signal*:

* :class:`HeatSource`: total power P(t) [W] spread uniformly over a set of cells;
* :class:`SurfaceHeatFlux`: total power P(t) [W] spread over a set of facets (uniformly, or in
  proportion to per-facet weights);
* :class:`Convection`: -k dT/dn = h(t) (T - T_air(t)) on a set of facets, h [W/(m2 K)], T_air [degC];
* :class:`ContactConductance`: q = h_c(t) (T_a - T_b) across interior facets between two parts,
  whose temperature field is split there (the joint stays bonded mechanically), h_c [W/(m2 K)].

Signals are functions of time arrays [s]. This structure makes every observable's response to
each effect exactly computable (loads enter the heat equation linearly) and lets the solver
assemble every pattern once.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from twin.signals import lag_series
from twin.units import CANONICAL, format_quantity

Signal = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Parameter:
    """One effect parameter; ``default``, ``lower``, ``upper`` are SI values of ``dimension``."""

    name: str
    dimension: str
    default: float
    lower: float
    upper: float
    doc: str

    @property
    def unit(self) -> str:
        return CANONICAL[self.dimension]

    def describe(self, value: float | None = None) -> str:
        v = self.default if value is None else value
        return (f"{self.name} = {format_quantity(v, self.dimension)} "
                f"[{format_quantity(self.lower, self.dimension)} .. {format_quantity(self.upper, self.dimension)}]: {self.doc}")


@dataclass(frozen=True)
class Uncertain:
    """A parameter whose value is uncertain on a real machine: its plausible range [lower, upper]
    (SI values of the parameter's dimension) and why. The diagnosis fits it like a missing effect
    when the effect is in the model (:mod:`validate.candidates`). ``linear``: every observable is
    affine in this parameter (a heat source's power); False for film coefficients, conductances
    and anything that changes the operator or a signal's shape (fitted by Gauss-Newton)."""

    name: str
    lower: float
    upper: float
    why: str
    linear: bool = False


@dataclass(frozen=True)
class HeatSource:
    label: str
    cells: np.ndarray
    power: Signal


@dataclass(frozen=True)
class SurfaceHeatFlux:
    """Total power P(t) [W] over ``facets``: uniform flux, or with ``weights`` (one per facet, of
    either sign, sum_g A_g w_g != 0) a flux proportional to them, q_f = P w_f / sum_g A_g w_g [W/m2]
    (the room's height-linear fluxes weigh by z_f - z_ref, :func:`twin.effects.room.linear_in_height`)."""

    label: str
    facets: np.ndarray
    power: Signal
    weights: np.ndarray | None = None


@dataclass(frozen=True)
class Convection:
    label: str
    facets: np.ndarray
    h: Signal
    air: Signal


@dataclass(frozen=True)
class ContactConductance:
    """Finite thermal contact across interior ``facets``; ``parts`` is the side that gets its own
    interface temperatures (see :meth:`twin.fem.mesh.MachineMesh.split_heat`)."""

    label: str
    facets: np.ndarray
    parts: tuple[str, ...]
    h: Signal


class Effect:
    """Base class: subclasses set ``name``, ``summary``, ``reference``, ``parameters``, the
    ``roles`` of the machine contract they place loads on (:data:`geometries.regions.ROLES`), their
    ``strength`` parameter and whether the response is ``linear`` in it (true for heat sources
    and fluxes whose power scales with it; a film coefficient or conductance changes the operator,
    so its response is not), and implement :meth:`loads`. The class docstring carries the
    equation."""

    name: str = ""
    summary: str = ""
    reference: str = ""
    parameters: tuple[Parameter, ...] = ()
    roles: tuple[str, ...] = ()
    strength: str = ""      # the parameter that sets how strong the effect is (what a diagnosis fits)
    linear: bool = False    # is every observable's response linear in the strength (heat sources only)?
    uncertain: tuple[Uncertain, ...] = ()   # parameters a real machine may have otherwise, with plausible ranges

    def missing_roles(self, machine) -> list[str]:
        """The roles this effect needs that ``machine`` does not declare."""
        return [r for r in self.roles if r not in machine.roles]

    def applies_to(self, machine) -> bool:
        """True if ``machine`` declares every role this effect needs."""
        return not self.missing_roles(machine)

    def parameter(self, name: str) -> Parameter:
        for p in self.parameters:
            if p.name == name:
                return p
        raise KeyError(name)

    def defaults(self) -> dict[str, float]:
        return {p.name: p.default for p in self.parameters}

    def uncertainty(self, name: str) -> Uncertain | None:
        """The declared :class:`Uncertain` range of parameter ``name`` (None if it is not declared)."""
        return next((u for u in self.uncertain if u.name == name), None)

    def check_params(self, params: dict[str, float], source: str) -> None:
        """:class:`InputError` naming ``source`` where ``params`` (SI, each within its bounds) are
        impossible together (a door open longer than its repeat interval would never close);
        effects whose parameters are independent keep this default, which accepts them all."""

    def refusal(self, scenario, params: dict[str, float]) -> tuple[str, str] | None:
        """(parameter, why) where this effect, switched on at ``params``, cannot run ``scenario``
        (a door draft whose first opening is after the run's end would do nothing: a user who
        switched it on expects it to act); None where it can. Checked by a run
        (:func:`twin.model.check_refusals`, unless it runs idle effects), by a diagnosis against its
        records, and by a dataset for every planned case before it builds any (:mod:`twin.dataset.plan`)."""
        return None

    def acts(self, scenario, params: dict | None = None) -> bool:
        """False only where this effect, at ``params`` (default: its defaults), certainly puts no
        load into a run of ``scenario`` (the door stream without a door event, a door draft
        opening after the run's end): the diagnosis then offers neither it nor its parameters as
        candidates, whose responses would be zero."""
        return True

    def loads(self, mm, scenario, params: dict[str, float]) -> list:
        raise NotImplementedError

    def air_change(self, z: np.ndarray, t: np.ndarray, scenario, params: dict[str, float]) -> np.ndarray | None:
        """(n_t, n_z) [K] what this effect adds to the room air T_air(t) at heights ``z`` [m] and
        times ``t`` [s] in the model's air (what a sensor in the air reads,
        :func:`twin.observe.temperature.air_temperature`); None for an effect that leaves the air
        as the room's (every effect but the stratifications)."""
        return None


EFFECTS: dict[str, Effect] = {}


def register_effect(cls: type[Effect]) -> type[Effect]:
    """Class decorator: register one instance of ``cls`` under ``cls.name``."""
    if cls.name in EFFECTS:
        raise RuntimeError(f"effect {cls.name!r} registered twice")
    check_declarations(cls)
    EFFECTS[cls.name] = cls()
    return cls


def check_declarations(cls) -> None:
    """RuntimeError if ``cls``'s strength or an uncertain range does not fit its parameters: the
    strength must be a parameter; each :class:`Uncertain` must name a parameter, lie within its
    bounds and contain its default."""
    params = {p.name: p for p in cls.parameters}
    if cls.strength and cls.strength not in params:
        raise RuntimeError(f"effect {cls.name!r}: strength {cls.strength!r} is not one of its parameters")
    for u in cls.uncertain:
        p = params.get(u.name)
        if p is None:
            raise RuntimeError(f"effect {cls.name!r}: uncertain {u.name!r} is not one of its parameters")
        if not (p.lower <= u.lower <= p.default <= u.upper <= p.upper):
            raise RuntimeError(f"effect {cls.name!r}: uncertain range of {u.name!r} [{u.lower:g}, {u.upper:g}] must "
                               f"contain the default {p.default:g} and lie within [{p.lower:g}, {p.upper:g}]")


def constant(value: float) -> Signal:
    """The signal that is ``value`` at every time."""
    value = float(value)
    return lambda t: np.full(np.shape(t), value)


def power_law(n: np.ndarray, reference_speed: float, exponent: float) -> np.ndarray:
    """(|n| / n_ref)^exponent for speeds n [rpm], 0 where n = 0 (at rest, whatever the exponent)."""
    n = np.abs(np.asarray(n, dtype=float))
    return np.power(n / reference_speed, exponent, where=n > 0, out=np.zeros_like(n))


def speed_power_law(scenario, reference_speed: float, exponent: float, scale: float) -> Signal:
    """Signal scale * (n(t) / n_ref)^exponent for spindle speed n(t) [rpm] (0 when stopped)."""

    def signal(t: np.ndarray) -> np.ndarray:
        return scale * power_law(scenario.spindle_speed(t), reference_speed, exponent)

    return signal


def first_order_lag(signal: Signal, tau: float, t_end: float, step: float = 60.0) -> Signal:
    """Signal y with tau dy/dt = x(t) - y, y(0) = x(0), tau [s] (see :func:`twin.signals.lag_series`),
    integrated once on a grid of ``step`` seconds up to ``t_end`` and interpolated linearly."""
    grid = np.arange(0.0, t_end + 2 * step, step)
    y = lag_series(signal(grid), step, tau)
    return lambda t: np.interp(t, grid, y)
