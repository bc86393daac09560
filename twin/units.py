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

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
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
    """
    if dimension not in _UNITS:
        raise KeyError(f"unknown dimension {dimension!r}")
    table = _UNITS[dimension]
    if isinstance(text, bool):
        raise UnitError(f"expected a quantity in {CANONICAL[dimension]}, got {text!r}")
    if isinstance(text, (int, float)):
        if dimension == "dimensionless":
            return _finite(float(text), text)
        raise UnitError(f"{text!r} has no unit; write it like '{text} {CANONICAL[dimension]}'")
    match = _PATTERN.match(str(text))
    if not match:
        raise UnitError(f"cannot read {text!r} as '<number> <unit>' (unit {CANONICAL[dimension]})")
    value, unit = float(match.group(1)), match.group(2)
    if unit not in table:
        other = [dim for dim, units in _UNITS.items() if unit in units]
        hint = f" ({unit!r} is a {other[0].replace('_', ' ')} unit)" if other else ""
        if not unit:
            raise UnitError(f"{text!r} has no unit; expected {_spellings(dimension)}")
        raise UnitError(f"{text!r} has the wrong unit{hint}; expected {_spellings(dimension)}")
    return _finite(value * table[unit], text)


def format_quantity(value: float, dimension: str) -> str:
    """Format an SI value with the canonical unit of ``dimension`` (``"8 W/m2K"``)."""
    unit = CANONICAL[dimension]
    return f"{value:.6g}" if dimension == "dimensionless" else f"{value:.6g} {unit}"


def _spellings(dimension: str) -> str:
    return ", ".join(repr(u) for u in _UNITS[dimension] if u)


def _finite(value: float, text) -> float:
    if not math.isfinite(value):
        raise UnitError(f"{text!r} is not a finite number")
    return value
