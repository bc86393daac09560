"""How a fitted candidate reads (:class:`validate.search.Fit`): its values with their units, the
statement "p is 195 W, not 150 W", the range each member was fitted in, and the members at a bound
of it (within :data:`validate.fit.BOUND_TOL` of the range's width, as the expansion nuisance)."""

from __future__ import annotations

from twin.units import format_quantity
from validate.fit import BOUND_TOL, at_bounds
from validate.search import Fit


def at_bound(f: Fit) -> list[str]:
    """The members (``effect.parameter``) of a fit whose value sits at a bound of its range."""
    at = at_bounds(f.values, [c.lower for c in f.candidates], [c.upper for c in f.candidates])
    return [f"{c.effect}.{c.parameter}" for c, a in zip(f.candidates, at) if a]


def format_bounds(f: Fit) -> dict[str, dict[str, list[str]]]:
    """{effect: {parameter: ["lower unit", "upper unit"]}}: the range each member was fitted in."""
    out: dict[str, dict[str, list[str]]] = {}
    for c in f.candidates:
        out.setdefault(c.effect, {})[c.parameter] = [format_quantity(float(f"{b:.4g}"), c.dimension)
                                                     for b in (c.lower, c.upper)]
    return out


def bound_text(f: Fit) -> str:
    """'floor.conductance at its bound 200 W/m2K (range 2 W/m2K to 200 W/m2K)' for each member at a bound,
    '; '-joined; a missing effect at the value where it adds nothing says so ('' when none)."""
    out = []
    names = set(at_bound(f))
    for c, v in zip(f.candidates, f.values):
        if f"{c.effect}.{c.parameter}" not in names:
            continue
        q = lambda x: format_quantity(float(f"{x:.3g}"), c.dimension)
        nothing = (", where it adds nothing" if not c.in_model and abs(v - c.zero) <= BOUND_TOL * (c.upper - c.lower)
                   else "")
        out.append(f"{c.effect}.{c.parameter} at its bound {q(v)} (range {q(c.lower)} to {q(c.upper)}{nothing})")
    return "; ".join(out)


def statement(f: Fit) -> str:
    """'spindle_bearings.front_power is 195 W, not 150 W' (and ' and ' between pair members)."""
    return " and ".join(c.text(v) for c, v in zip(f.candidates, f.values))


def format_values(f: Fit, model: bool = False) -> dict[str, dict[str, str]]:
    """{effect: {parameter: "value unit"}} of a fit; with ``model``, the model's values of the members
    the model has (a parameter candidate's p_0)."""
    out: dict[str, dict[str, str]] = {}
    for c, v in zip(f.candidates, f.values):
        if model and not c.in_model:
            continue
        out.setdefault(c.effect, {})[c.parameter] = format_quantity(c.zero if model else v, c.dimension)
    return out
