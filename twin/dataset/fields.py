"""The readers of a dataset spec's fields (its tables through
:class:`twin.io.table_reader.TableReader`): a quantity with its unit (:func:`quantity`) and a quantity's distribution
(:class:`Dist`, :func:`distribution`). Errors are :class:`twin.errors.InputError` naming the spec
file and the field."""

from __future__ import annotations

import math
from dataclasses import dataclass

from twin.errors import InputError, describe
from twin.units import UnitError, format_quantity, parse_quantity

DISTRIBUTIONS = ("fixed", "grid", "uniform", "log_uniform", "normal")
MAX_CASES = 100_000


@dataclass(frozen=True)
class Dist:
    """A quantity's distribution, values in SI: ``fixed (v,)``, ``grid (v1, v2, ...)``,
    ``uniform (lo, hi)``, ``log_uniform (lo, hi)``, ``normal (mean, sd)`` truncated to
    ``[lower, upper]``."""

    kind: str
    values: tuple[float, ...]
    dimension: str
    lower: float = -math.inf
    upper: float = math.inf

    def sample(self, rng) -> float:
        """One draw from the numpy Generator ``rng`` (a grid is expanded by the plan, not drawn)."""
        v = self.values
        if self.kind == "fixed":
            return v[0]
        if self.kind == "uniform":
            return float(rng.uniform(v[0], v[1]))
        if self.kind == "log_uniform":
            return float(math.exp(rng.uniform(math.log(v[0]), math.log(v[1]))))
        if self.kind == "normal":
            for _ in range(10_000):
                x = float(rng.normal(v[0], v[1]))
                if self.lower <= x <= self.upper:
                    return x
            raise ValueError("normal draws fall outside the bounds")   # prevented by the spec check
        raise ValueError(f"a {self.kind} is not drawn")

    @property
    def low(self) -> float:
        return min(self.values) if self.kind != "normal" else self.lower

    @property
    def high(self) -> float:
        return max(self.values) if self.kind != "normal" else self.upper


def quantity(value, dimension: str, source: str, field: str) -> float:
    """``value`` ("2 h", "20 degC") as the SI value of ``dimension``; errors name ``field``."""
    try:
        return parse_quantity(value, dimension)
    except UnitError as err:
        raise InputError(source, field, str(err)) from None


def distribution(value, dimension: str, source: str, field: str, lower: float = -math.inf,
                 upper: float = math.inf, grid: bool = False, what: str = "") -> Dist:
    """A quantity, a ``[lo, hi]`` range (uniform) or a one-key table naming a distribution;
    checked: ranges not empty or reversed, log-uniform positive, sd positive, every value (and a
    normal's mean) within ``[lower, upper]`` (``what`` says whose bounds they are)."""
    if isinstance(value, list):
        kind, raw = "uniform", value
    elif isinstance(value, dict):
        if len(value) != 1 or next(iter(value)) not in DISTRIBUTIONS:
            raise InputError(source, field, f"expected one of {', '.join(DISTRIBUTIONS)} (one key), got "
                                            f"{', '.join(map(str, value)) or 'an empty table'}")
        kind, raw = next(iter(value.items()))
        field = f"{field}.{kind}"
    else:
        kind, raw = "fixed", [value]
    if kind == "grid" and not grid:
        raise InputError(source, field, "a grid is allowed for [parameters] only; use a range or a distribution")
    if kind == "fixed" and not isinstance(raw, list):
        raw = [raw]
    if not isinstance(raw, list):
        raise InputError(source, field, f"expected a list of quantities, got {describe(raw)}")
    need = {"fixed": 1, "uniform": 2, "log_uniform": 2, "normal": 2}.get(kind)
    if need is not None and len(raw) != need:
        raise InputError(source, field, f"a {kind} takes {need} value(s) ([lo, hi] or [mean, sd]), got {len(raw)}")
    if kind == "grid" and not raw:
        raise InputError(source, field, "a grid needs at least one value")
    dims = [dimension] * len(raw)
    if kind == "normal" and dimension == "temperature":
        dims[1] = "temperature_difference"   # the spread of a temperature is a difference
    values = tuple(quantity(v, d, source, f"{field}[{i}]" if len(raw) > 1 else field)
                   for i, (v, d) in enumerate(zip(raw, dims)))
    if kind in ("uniform", "log_uniform") and not values[0] < values[1]:
        raise InputError(source, field, f"empty or reversed range [{raw[0]}, {raw[1]}]; write [lo, hi] with lo < hi")
    if kind == "log_uniform" and values[0] <= 0:
        raise InputError(source, field, f"a log-uniform range must be positive, got {raw[0]}")
    if kind == "normal" and values[1] <= 0:
        raise InputError(source, field, f"the standard deviation must be positive, got {raw[1]}")
    if kind == "grid" and len(set(values)) != len(values):
        raise InputError(source, field, "a grid value is given twice")
    checked = values[:1] if kind == "normal" else values
    for raw_v, v in zip(raw, checked):
        if not lower <= v <= upper:
            bounds = f"[{_fmt(lower, dimension)} .. {_fmt(upper, dimension)}]".replace("inf", "∞")
            raise InputError(source, field, f"{raw_v} is outside the bounds {what or bounds}")
    return Dist(kind, values, dimension, lower, upper)


def _fmt(v: float, dimension: str) -> str:
    """A bound with its unit (times in hours), infinite bounds as 'inf'."""
    if not math.isfinite(v):
        return f"{v:g}"
    if dimension == "time":
        return f"{v / 3600:.6g} h"
    return format_quantity(v, dimension)
