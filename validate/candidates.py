"""What a diagnosis may name: missing effects, wrong parameters of the model's own effects, and
the user's custom effects.

A :class:`Candidate` is one scalar the diagnosis fits: an effect's parameter p in [lower, upper]
(SI) and the model it changes:

* ``effect``: a library effect the model lacks, switched on at strength p (its ``strength``
  parameter within the parameter's bounds); the response is zero at p = 0 for a heat source;
* ``parameter``: an uncertain parameter of an effect the model has (``Effect.uncertain``: a
  bearing power, a film coefficient, a floor conductance ...), moved from its model value p_0
  within its plausible range; the response is zero at p = p_0;
* ``custom``: a user's effect from ``--effects-file`` (:mod:`twin.effects.custom`), as a missing
  effect when the model lacks it, as a parameter when the user switched it on.

The response of the observables is g(p) = y(model with p) - y(model); :attr:`Candidate.zero` is
the p where g vanishes, :attr:`Candidate.reference` a p != zero where a linear candidate's unit
response (g(p) / (p - zero)) is taken.

A missing contact conductance G (the test bar's seat) adds nothing at G = infinity, not at 0: its
``zero`` is the upper bound and it is :attr:`Candidate.reciprocal`: the resistance R = 1/G adds in
series, so g is nearly linear in 1/G - 1/G_zero and the fit's linearised start is taken in it
(:mod:`validate.search`). Linearised in G from G_zero = 1000 W/K, a 5 W/K seat would need 3.4x
the 20 W/K response where the secant gives 1.02x (the C-frame's duty cycle on the coarse mesh;
linear in 1/G: 4.1x): the start hit the 0.1 W/K bound and the candidate ranked 14th.
"""

from __future__ import annotations

from dataclasses import dataclass

from twin.effects import EFFECTS
from twin.model import ModelSpec, applicable_effects, uncertain_range
from twin.units import format_quantity


@dataclass(frozen=True)
class Candidate:
    """One fittable scalar: ``effect``'s parameter ``parameter`` in [lower, upper] (SI)."""

    name: str          # "electrical_cabinet", "spindle_bearings.front_power", a custom effect's name
    kind: str          # "effect" | "parameter" | "custom"
    effect: str
    parameter: str
    lower: float
    upper: float
    zero: float        # value at which the response vanishes (0 for a missing source, p_0 for a parameter)
    reference: float   # a value != zero for the unit response of a linear candidate, and the GN start
    linear: bool
    in_model: bool     # True: the model has the effect (a parameter); False: the candidate adds it
    reciprocal: bool = False   # g vanishes at the upper bound (G -> infinity): linearise in 1/p

    @property
    def dimension(self) -> str:
        return EFFECTS[self.effect].parameter(self.parameter).dimension

    def spec(self, base: ModelSpec, value: float) -> ModelSpec:
        """``base`` with this candidate at ``value`` (SI)."""
        params = {g: dict(v) for g, v in base.params.items()}
        effects = tuple(base.effects)
        if not self.in_model and self.effect not in effects:
            params[self.effect] = EFFECTS[self.effect].defaults()
            effects += (self.effect,)
        params[self.effect][self.parameter] = float(value)
        return ModelSpec(effects, params)

    def text(self, value: float) -> str:
        """``"spindle_bearings.front_power is 195 W, not 150 W"`` or ``"electrical_cabinet.power = 120 W"``."""
        v = format_quantity(float(f"{value:.3g}"), self.dimension)
        if self.in_model:
            return f"{self.effect}.{self.parameter} is {v}, not {format_quantity(self.zero, self.dimension)}"
        return f"{self.effect}.{self.parameter} = {v}"


def reference_value(param) -> float:
    """Reference strength for a missing effect's signature: the default, or 10 % of the widest
    bound if the default is zero (a zero-strength run has no signature)."""
    if param.default != 0:
        return float(param.default)
    return 0.1 * (param.upper if abs(param.upper) >= abs(param.lower) else param.lower)


def missing_effect(name: str) -> Candidate | None:
    """The candidate adding effect ``name`` at its fitted strength (None without a strength)."""
    eff = EFFECTS[name]
    if not eff.strength:
        return None
    par = eff.parameter(eff.strength)
    kind = "custom" if getattr(eff, "custom", False) else "effect"
    zero = 0.0 if eff.linear else _zero_of(par)
    return Candidate(name, kind, name, par.name, par.lower, par.upper, zero, reference_value(par), eff.linear, False,
                     reciprocal=not eff.linear and zero == par.upper > 0)


def _zero_of(par) -> float:
    """Where a nonlinear missing effect's response vanishes, as far as the fit needs it: 0 (a
    film coefficient or jacket conductance of zero adds nothing); for parameters whose zero is not
    'nothing' (a contact conductance: perfect contact is infinite) the upper bound, and the
    candidate is fitted in the reciprocal (module docstring)."""
    return 0.0 if par.lower <= 0.0 else par.upper


def wrong_parameters(spec: ModelSpec, machine=None) -> list[Candidate]:
    """Every declared uncertain parameter of the effects in ``spec``, moved within its plausible
    range on ``machine`` (:func:`twin.model.uncertain_range`: scaled where the machine sets its
    own default) from the model's value."""
    out = []
    for name in spec.effects:
        eff = EFFECTS[name]
        kind = "custom" if getattr(eff, "custom", False) else "parameter"
        for u in eff.uncertain:
            p0 = float(spec.params[name][u.name])
            lo, hi = uncertain_range(machine, name, u)
            lo, hi = min(lo, p0), max(hi, p0)
            ref = p0 + 0.5 * (hi - p0) if hi > p0 else p0 - 0.5 * (p0 - lo)
            out.append(Candidate(f"{name}.{u.name}", kind, name, u.name, lo, hi, p0, ref, u.linear, True))
    return out


def candidate_pool(machine, spec: ModelSpec, effects: list[str] | None = None, parameters: bool = True,
                   custom: tuple[str, ...] = (), scenarios: tuple = ()) -> list[Candidate]:
    """The candidates of a diagnosis: every applicable library effect missing from ``spec`` and the
    ``custom`` effects this diagnosis was given (an effects file's; a custom effect left
    registered by an earlier call in the process is no candidate: it once "explained" a test's
    outside source), or exactly ``effects``; then (``parameters``) every uncertain parameter of
    the model's effects; with ``scenarios`` (the measurements'), of those (not of the ``effects``
    named) none whose effect acts in none of them (:meth:`twin.effects.base.Effect.acts`: a door
    stream without a door event)."""
    from twin.effects.custom import CUSTOM

    names = effects if effects is not None else [e for e in applicable_effects(machine)
                                                 if e not in spec.effects and (e not in CUSTOM or e in custom)]
    def acting(cands):      # at the model's parameters (a missing effect: its defaults)
        return [c for c in cands if not scenarios
                or any(EFFECTS[c.effect].acts(sc, spec.params.get(c.effect)) for sc in scenarios)]

    out = [c for c in (missing_effect(n) for n in names) if c is not None]
    return (out if effects is not None else acting(out)) + (acting(wrong_parameters(spec, machine)) if parameters else [])
