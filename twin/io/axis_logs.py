"""Logged axis motion in a measurement (:mod:`twin.io.measurement`): the axis an
``axis_position`` or ``axis_feed`` column names, positions held to the axis's travel, and a logged
signed feed integrated to positions from the mapping's ``start``; a log's feed held to
:data:`twin.limits.MAX_FEED` (the twin moves the axis linearly between samples, at
(x[i+1] - x[i]) / (t[i+1] - t[i])). Every problem is an
:class:`twin.errors.InputError` naming the mapping's key or the CSV column, and the sample by the
line an editor shows (``lines``, a CSV's) or else its data row."""

from __future__ import annotations

import numpy as np

from twin.errors import InputError
from twin.io.times import sample_place
from twin.limits import MAX_FEED
from twin.units import UnitError, parse_quantity


def axis_name(entry: dict, seen: dict, mach, msrc: str, key: str) -> str:
    """The axis an ``axis_position`` or ``axis_feed`` column names: given once, known to the
    machine (when one is given)."""
    axis = entry.get("axis")
    if not isinstance(axis, str) or not axis:
        raise InputError(msrc, key + ".axis", "expected an axis name such as \"Y\"")
    if axis in seen:
        raise InputError(msrc, key + ".axis", f"axis {axis} mapped twice")
    return known_axis(axis, mach, msrc, key + ".axis")


def known_axis(axis: str, mach, src: str, field: str) -> str:
    """``axis`` when ``mach`` has it (or no machine is given), else an error listing its axes."""
    if mach is not None:
        try:
            mach.axis(axis)
        except KeyError:
            known = ", ".join(a.name for a in mach.axes) or "none"
            raise InputError(src, field, f"machine {mach.name} has no axis {axis!r}; its axes: {known}") from None
    return axis


def integrated_feed(t: np.ndarray, feed: np.ndarray, entry: dict, mach, msrc: str, src: str, key: str,
                     column: str, lines=None) -> np.ndarray:
    """Positions [m] of an ``axis_feed`` column: x(t) = start + integral of the signed feed [m/s],
    trapezoidal between the samples (exact for a feed linear between them), held to the travel
    like a logged position."""
    if "start" not in entry:
        raise InputError(msrc, key + ".start", "missing: the axis position at the first sample, e.g. \"0 mm\"")
    try:
        start = parse_quantity(entry["start"], "length")
    except (UnitError, TypeError, ValueError) as err:
        raise InputError(msrc, key + ".start", str(err)) from None
    check_feeds(feed, src, column, "logged feed", lines=lines)
    x = start + np.concatenate([[0.0], np.cumsum(0.5 * (feed[1:] + feed[:-1]) * np.diff(t))])
    check_travel(entry["axis"], x, mach, src, column, " (integrated from the feed)", lines)
    return x


def check_log(axis: str, t: np.ndarray, x: np.ndarray, mach, src: str, column: str, lines=None) -> None:
    """Logged positions ``x`` [m] of ``axis`` at times ``t`` [s]: within the travel, and the feed
    between two samples, |x[i+1] - x[i]| / (t[i+1] - t[i]) [m/s], at most :data:`MAX_FEED` (a
    faster log is in the wrong unit or not a position)."""
    check_travel(axis, x, mach, src, column, lines=lines)
    check_feeds(np.diff(x) / np.diff(t), src, column, "feed between samples", offset=1, lines=lines)


def check_feeds(v: np.ndarray, src: str, column: str, what: str, offset: int = 0, lines=None) -> None:
    """Signed feeds ``v`` [m/s] at most :data:`MAX_FEED` in size; the error names the first sample
    beyond it (``offset`` samples later for a feed between two samples: the sample it arrives at)."""
    bad = np.flatnonzero(~(np.abs(v) <= MAX_FEED))
    if len(bad):
        i = int(bad[0])
        raise InputError(src, column, f"{sample_place(i + offset, lines)}: a {what} of {v[i]:g} m/s "
                                      f"({v[i] * 60:g} m/min) is "
                                      f"beyond {MAX_FEED:g} m/s ({MAX_FEED * 60:g} m/min), the fastest machine "
                                      "tools' (check the unit)")


def check_travel(axis: str, values: np.ndarray, mach, src: str, column: str, how: str = "", lines=None) -> None:
    """Positions [m] of ``axis`` within the machine's travel (when a machine is given)."""
    if mach is None:
        return
    lo, hi = mach.axis(axis).travel
    bad = np.flatnonzero((values < lo - 1e-9) | (values > hi + 1e-9))
    if len(bad):
        raise InputError(src, column, f"{sample_place(int(bad[0]), lines)}: {values[bad[0]] * 1e3:g} mm{how} "
                                      f"is outside the {axis} "
                                      f"travel {lo * 1e3:g} .. {hi * 1e3:g} mm")
