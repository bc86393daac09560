"""The one place where unit strings are parsed.

Every quantity that crosses a boundary (TOML scenario, ``--set`` on the command line, a CSV
mapping) is a string with an explicit unit, e.g. ``"8000 rpm"``, ``"2 h"``, ``"20 degC"``,
``"2.5 K"``, ``"8 W/m2K"``. :func:`parse_quantity` converts it to the SI value of a named
*dimension*; a missing or wrong unit raises :class:`UnitError`.

SI conventions inside the package: s, m, W, K (temperature *differences*), degC (absolute
temperatures, offset-free so that conduction and convection stay linear), rpm for spindle speed
(machine-tool users think in rpm; it is converted where an effect needs rad/s).
"""

from __future__ import annotations

import math
import re

from twin.errors import describe

# dimension -> {unit spelling -> factor to the SI unit}; the first spelling is canonical.
_UNITS: dict[str, dict[str, float]] = {
    "time": {"s": 1.0, "sec": 1.0, "min": 60.0, "h": 3600.0, "hr": 3600.0, "d": 86400.0, "ms": 1e-3},
    "speed": {"rpm": 1.0, "1/min": 1.0, "krpm": 1000.0},
    "temperature": {"degC": 1.0, "°C": 1.0, "C": 1.0},
    "temperature_difference": {"K": 1.0, "mK": 1e-3},
    "power": {"W": 1.0, "kW": 1e3, "mW": 1e-3},
    "heat_transfer_coefficient": {"W/m2K": 1.0, "W/(m2 K)": 1.0, "W/(m^2 K)": 1.0, "W/m^2/K": 1.0,
                                   "W/m2/K": 1.0, "W/(m2*K)": 1.0, "W/m^2K": 1.0},
    "conductance": {"W/K": 1.0},
    "heat_flux": {"W/m2": 1.0, "W/m^2": 1.0},
    "length": {"m": 1.0, "mm": 1e-3, "um": 1e-6, "cm": 1e-2},
    "velocity": {"m/s": 1.0, "mm/s": 1e-3, "mm/min": 1e-3 / 60.0, "m/min": 1.0 / 60.0},
    "acceleration": {"m/s2": 1.0, "m/s^2": 1.0, "mm/s2": 1e-3, "mm/s^2": 1e-3},
    "temperature_gradient": {"K/m": 1.0, "K/mm": 1e3},
    "strain": {"m/m": 1.0, "um/m": 1e-6, "ppm": 1e-6},
    "thermal_strain": {"1/K": 1.0, "um/m/K": 1e-6, "ppm/K": 1e-6},
    "inverse_length": {"1/m": 1.0, "/m": 1.0, "1/mm": 1e3},
    "angle": {"deg": math.pi / 180.0, "rad": 1.0, "mrad": 1e-3},
    "dimensionless": {"1": 1.0, "": 1.0, "%": 0.01},
}

CANONICAL = {dim: next(iter(units)) for dim, units in _UNITS.items()}
# the unit a hint suggests where users do not write the SI one (positions on a machine in mm)
HINT_UNIT = {"length": "mm", "velocity": "mm/s", "acceleration": "mm/s2", "strain": "um/m",
             "thermal_strain": "um/m/K"}
_EXAMPLES = {"time": "10 s", "speed": "6000 rpm", "temperature": "20 degC", "temperature_difference": "2 K",
             "power": "50 W", "heat_transfer_coefficient": "8 W/m2K", "conductance": "1 W/K",
             "heat_flux": "100 W/m2", "length": "150 mm", "velocity": "20 mm/s", "acceleration": "100 mm/s2",
             "strain": "50 um/m", "thermal_strain": "11.5 um/m/K", "angle": "10 deg", "dimensionless": "0.5"}

_NUMBER = r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?"   # ASCII digits: a "٩٠٠٠ rpm" is no number
_PATTERN = re.compile(rf"^\s*({_NUMBER})\s*(.*?)\s*$")


class UnitError(ValueError):
    """A quantity string that is malformed or carries the wrong unit for its dimension."""


def dimensions() -> list[str]:
    """Names of the dimensions :func:`parse_quantity` accepts."""
    return list(_UNITS)


def parse_quantity(text: str | int | float, dimension: str) -> float:
    """Parse ``"<number> <unit>"`` into the SI value of ``dimension``.

    A bare number is accepted only for ``dimensionless`` quantities. Examples::

        parse_quantity("2 h", "time") == 7200.0
        parse_quantity("8 W/m2K", "heat_transfer_coefficient") == 8.0

    Errors describe the value in the user's terms (a TOML date, the boolean true), say when the
    number is the problem (not finite, not a decimal number such as ``0x3c`` or ``6_0``) rather
    than the unit, and hint a unit that is plausible for the dimension (``'150 mm'``)."""
    if dimension not in _UNITS:
        raise KeyError(f"unknown dimension {dimension!r}")
    table = _UNITS[dimension]
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise UnitError(f"got {describe(text)}; expected a quantity with a unit such as {example(dimension)!r}")
    if isinstance(text, (int, float)):
        if not math.isfinite(text):
            raise UnitError(f"{text} is not a finite number")
        if dimension == "dimensionless":
            return float(text)
        raise UnitError(f"{text} has no unit; write it like '{text} {HINT_UNIT.get(dimension, CANONICAL[dimension])}'"
                        f" (units: {_spellings(dimension)})")
    if not str(text).strip():
        raise UnitError(f"is empty; write it like {example(dimension)!r}")
    number, _, rest = str(text).strip().partition(" ")
    if (rest.strip() and rest.strip() in table) or not _PATTERN.match(str(text)):   # "0x3c s", "nan degC", "x s"
        if not re.fullmatch(_NUMBER, number):
            nan = re.match(r"[-+]?(nan|infinity|inf)", number, re.IGNORECASE)    # "nan", "inf s", "nanW"
            finite = not (nan and (nan.end() == len(number) or number[nan.end():] in table))
            what = f"{text!r}: {number!r}" if rest.strip() else repr(text)
            what += " is not a finite number" if not finite else " is not a decimal number"
            raise UnitError(f"{what}; write it like {example(dimension)!r}")
    match = _PATTERN.match(str(text))
    if not match:
        raise UnitError(f"cannot read {text!r} as '<number> <unit>' (unit {CANONICAL[dimension]})")
    value, unit = float(match.group(1)), match.group(2)
    if unit not in table:
        other = [dim for dim, units in _UNITS.items() if unit in units]
        hint = f" ({unit!r} is a {other[0].replace('_', ' ')} unit)" if other else ""
        if not unit:
            raise UnitError(f"{text!r} has no unit; expected {_spellings(dimension)}")
        for known in sorted((u for u in table if u and unit.endswith(u)), key=len, reverse=True):
            middle = unit[:-len(known)]   # "6_0W": "_0", "0x3cW": "x3c" between the number and a known unit
            if middle and not middle.isalpha() and not re.search(r"\s", middle):   # not a prefix like "MW"'s "M"
                raise UnitError(f"{text!r}: {match.group(1) + middle!r} is not a decimal number; write it like "
                                f"{example(dimension)!r}")
        raise UnitError(f"{text!r} has the wrong unit{hint}; expected {_spellings(dimension)}")
    return _finite(value * table[unit], text)


def example(dimension: str) -> str:
    """A quantity of ``dimension`` as a user would write it (``'10 s'``, ``'150 mm'``)."""
    return _EXAMPLES.get(dimension, f"1 {HINT_UNIT.get(dimension, CANONICAL[dimension])}").strip()


def format_quantity(value: float, dimension: str) -> str:
    """Format an SI value with the canonical unit of ``dimension`` (``"8 W/m2K"``)."""
    unit = CANONICAL[dimension]
    return f"{value:.6g}" if dimension == "dimensionless" else f"{value:.6g} {unit}"


def clean(value: float | None, digits: int = 12) -> float | None:
    """``value`` with the round-off of unit conversions cut away (``digits`` significant digits):
    for numbers written to files and attributes, so that 24 deg reads 24.0, not
    24.000000000000004, and 1.549 m not 1.5490000000000002. None (a setting left to its
    default) stays None."""
    return None if value is None else float(f"{float(value):.{digits}g}")


def unit_scale(unit: str, dimension: str) -> float:
    """The SI value of one ``unit`` (a unit alone, as a CSV header or a column mapping gives it) of
    ``dimension``: ``unit_scale("min", "time")`` is 60.0. :class:`UnitError` naming the unit as
    written, and its kind where it is another dimension's."""
    u = str(unit).strip()
    table = _UNITS[dimension]
    if u and u in table:
        return table[u]
    other = [dim for dim, units in _UNITS.items() if u and u in units]
    kind = f" ({u!r} is a {other[0].replace('_', ' ')} unit)" if other else ""
    raise UnitError(f"{u!r} is not a unit of {dimension.replace('_', ' ')}{kind}; expected {_spellings(dimension)}")


def _spellings(dimension: str) -> str:
    return ", ".join(repr(u) for u in _UNITS[dimension] if u)


def _finite(value: float, text) -> float:
    if not math.isfinite(value):
        raise UnitError(f"{text!r} is not a finite number")
    return value
