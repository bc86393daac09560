"""Instants at which an instrument reads (interferometer runs, probing routines): parsed from a
scenario's list of times, the first the 0 s baseline, and checked against its time grid."""

from __future__ import annotations

import numpy as np

from twin.errors import InputError
from twin.units import UnitError, parse_quantity


def baseline_instants(values, source: str, key: str, first: str) -> tuple[float, ...]:
    """Instants [s] of the list ``values`` (strings with a time unit): increasing, the first 0 s
    (``first`` names what it is, for the error); InputError naming ``key`` otherwise."""
    try:
        t = [parse_quantity(v, "time") for v in (values if isinstance(values, list) else [])]
    except UnitError as err:
        raise InputError(source, key, str(err)) from None
    return check_instants(t, source, key, first)


def check_instants(times, source: str, key: str, first: str) -> tuple[float, ...]:
    """``times`` [s]: one or more finite numbers, increasing, the first 0 s (``first`` names what
    it is); the instants as floats, or an InputError naming ``key`` (a negative or late first
    instant left its readings' slots unfilled)."""
    if isinstance(times, (str, bytes)) or not hasattr(times, "__len__"):
        raise InputError(source, key, f"expected a list of instants [s], got {times!r}")
    try:
        t = np.asarray(times, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InputError(source, key, f"expected a list of instants [s], got {times!r}") from None
    if t.size == 0 or not np.all(np.isfinite(t)) or t[0] != 0 or np.any(np.diff(t) <= 0):
        raise InputError(source, key, f"expected finite increasing instants, the first at 0 s ({first})")
    return tuple(float(v) for v in t)


def check_on_grid(times, scenario, source: str, key: str, first: str = "the baseline") -> None:
    """``times`` [s] are baseline instants (:func:`check_instants`) and each an output instant of
    ``scenario`` within its duration."""
    times = check_instants(times, source, key, first)
    dt = scenario.sample_interval
    for v in times:
        if v > scenario.duration + 1e-6 or abs(v / dt - round(v / dt)) > 1e-6:
            raise InputError(source, key, f"{v:g} s is not an output instant of the scenario "
                                          f"(every {dt:g} s up to {scenario.duration:g} s)")
