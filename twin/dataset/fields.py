"""The readers of a dataset spec's fields (its tables through
:class:`twin.io.table_reader.TableReader`): a quantity with its unit (:func:`quantity`) and a quantity's distribution
(:class:`Dist`, :func:`distribution`). Errors are :class:`twin.errors.InputError` naming the spec
file and the field."""

from __future__ import annotations

import math
from dataclasses import dataclass
from statistics import NormalDist

from twin.errors import InputError, describe
from twin.units import UnitError, format_quantity, parse_quantity

DISTRIBUTIONS = ("fixed", "grid", "uniform", "log_uniform", "normal")
MAX_CASES = 100_000
MIN_NORMAL_MASS = 1e-6   # a normal with less of its probability within the bounds is refused
_SQRT2 = math.sqrt(2.0)
_UNIT = NormalDist()


@dataclass(frozen=True)
class Dist:
    """A quantity's distribution, values in SI: ``fixed (v,)``, ``grid (v1, v2, ...)``,
    ``uniform (lo, hi)``, ``log_uniform (lo, hi)``, ``normal (mean, sd)`` truncated to
    ``[lower, upper]`` (drawn exactly, see :func:`truncated_normal`)."""

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
            return truncated_normal(v[0], v[1], self.lower, self.upper, float(rng.uniform()))
        raise ValueError(f"a {self.kind} is not drawn")

    @property
    def low(self) -> float:
        return min(self.values) if self.kind != "normal" else self.lower

    @property
    def high(self) -> float:
        return max(self.values) if self.kind != "normal" else self.upper


def _phi(z: float) -> float:
    """The standard normal CDF, accurate (relatively) far into the lower tail."""
    return 0.5 * math.erfc(-z / _SQRT2)


def _standard(mean: float, sd: float, lower: float, upper: float) -> tuple[float, float, float, float]:
    """``(a, b, sign, mass)``: the bounds standardised and, when both lie above the mean,
    mirrored (``sign`` -1) so that ``a < 0`` or the whole interval is in the lower tail, where
    the CDF is accurate; ``mass`` is the probability of the normal within the bounds."""
    a, b, sign = (lower - mean) / sd, (upper - mean) / sd, 1.0
    if a >= 0.0:
        a, b, sign = -b, -a, -1.0
    if b <= 0.0:
        mass = _phi(b) - _phi(a)
    else:   # a < 0 < b: a sum of two positive halves, accurate even for a tiny interval
        mass = 0.5 * (math.erf(b / _SQRT2) + math.erf(-a / _SQRT2))
    return a, b, sign, mass


def normal_mass(mean: float, sd: float, lower: float, upper: float) -> float:
    """The probability of the normal ``(mean, sd)`` within ``[lower, upper]``."""
    return _standard(mean, sd, lower, upper)[3]


def truncated_normal(mean: float, sd: float, lower: float, upper: float, u: float) -> float:
    """The normal ``(mean, sd)`` truncated to ``[lower, upper]`` at the uniform ``u`` in [0, 1):
    its inverse CDF, exactly (no redrawing, so one uniform per draw whatever the bounds); the
    upper half through the upper tail, so both tails keep their precision."""
    a, b, sign, mass = _standard(mean, sd, lower, upper)
    v = u if sign > 0 else 1.0 - u   # mirrored bounds: the mirrored quantile, so x grows with u
    p = _phi(a) + v * mass
    if p <= 0.5:
        z = a if p <= 0.0 and a > -math.inf else _UNIT.inv_cdf(min(max(p, 5e-324), 0.5))
    else:   # 1 - p, written without cancellation
        q = _phi(-b) + (1.0 - v) * mass
        z = b if q <= 0.0 and b < math.inf else -_UNIT.inv_cdf(min(max(q, 5e-324), 0.5))
    return min(max(mean + sign * sd * z, lower), upper)


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
    normal's mean) within ``[lower, upper]`` (``what`` says whose bounds they are), and at least
    :data:`MIN_NORMAL_MASS` of a normal's probability within them."""
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
        form = {"fixed": 'one value, e.g. { fixed = "40 W" }', "uniform": "[lo, hi]", "log_uniform": "[lo, hi]",
                "normal": "[mean, sd]"}[kind]
        raise InputError(source, field, f"a {kind} takes {form}, got {len(raw)} value{'s' * (len(raw) != 1)}")
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
    bounds = what or f"[{_fmt(lower, dimension)} .. {_fmt(upper, dimension)}]".replace("inf", "∞")
    for raw_v, v in zip(raw, checked):
        if not lower <= v <= upper:
            raise InputError(source, field, f"{raw_v} is outside the bounds {bounds}")
    if kind == "normal" and (mass := normal_mass(values[0], values[1], lower, upper)) < MIN_NORMAL_MASS:
        raise InputError(source, field, f"only {mass:.2g} of the normal's probability lies within the bounds "
                                        f"{bounds} (at least {MIN_NORMAL_MASS:g} is needed): the standard deviation "
                                        f"{raw[1]} dwarfs the bounds; give a smaller one, or a [lo, hi] range for "
                                        "an even spread")
    return Dist(kind, values, dimension, lower, upper)


def _fmt(v: float, dimension: str) -> str:
    """A bound with its unit (times in hours), infinite bounds as 'inf'."""
    if not math.isfinite(v):
        return f"{v:g}"
    if dimension == "time":
        return f"{v / 3600:.6g} h"
    return format_quantity(v, dimension)
