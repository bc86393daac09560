"""The room air of a scenario: a base (constant, a daily sine, a table or a measured record) plus
events (a door opened, a holiday), read from a scenario's ``[ambient]`` table with units and
checked as air a workshop can have (:mod:`twin.limits`). The table's keys are listed in
:mod:`twin.scenario`'s docstring.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np

from twin import limits
from twin.errors import InputError, describe
from twin.io.room_csv import read_room_csv
from twin.io.table_reader import TableReader

AMBIENT_KEYS = ("kind", "temperature", "mean", "amplitude", "coldest_at", "start_time_of_day", "times",
                "temperatures", "file", "events")
EVENT_KEYS = ("start", "change", "fall", "hold", "recovery", "door")


@dataclass(frozen=True)
class AirEvent:
    """A change of the room air added to the base ambient [K]: a door opened in winter, a
    holiday with the heating turned down. A trapezoid: 0 before ``start``, a linear ramp to
    ``change`` over ``fall``, ``hold`` there, a linear return over ``recovery`` (times [s])."""

    start: float
    change: float
    fall: float
    hold: float = 0.0
    recovery: float = 0.0
    door: bool = False   # a door opened: outside air streams in (the ``door_stream`` effect)

    def __call__(self, t: np.ndarray) -> np.ndarray:
        rel = np.asarray(t, dtype=float) - self.start
        top = self.fall + self.hold
        up = np.clip(rel / self.fall, 0.0, 1.0) if self.fall > 0 else (rel >= 0).astype(float)
        down = np.clip(1.0 - (rel - top) / self.recovery, 0.0, 1.0) if self.recovery > 0 else (rel < top).astype(float)
        return self.change * np.minimum(up, down)

    @property
    def end(self) -> float:
        return self.start + self.fall + self.hold + self.recovery


@dataclass(frozen=True)
class Ambient:
    """Room air temperature T_air(t) [degC]: constant, a daily sine, a linear table (``table``,
    or ``csv`` when it came from a measured record), plus any :class:`AirEvent` s."""

    kind: str
    mean: float = 20.0
    amplitude: float = 0.0
    coldest_at: float = 6 * 3600.0
    start_time_of_day: float = 0.0
    times: tuple[float, ...] = ()
    temperatures: tuple[float, ...] = ()
    events: tuple[AirEvent, ...] = ()
    file: str = ""

    def __call__(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return self.base(t) + sum((e(t) for e in self.events), np.zeros(t.shape))

    def base(self, t: np.ndarray) -> np.ndarray:
        """The air without the events [degC]."""
        t = np.asarray(t, dtype=float)
        if self.kind == "constant":
            return np.full(t.shape, self.mean)
        if self.kind == "daily":
            # T = mean - A cos(2 pi (tod - coldest) / 1 d): coldest at ``coldest_at``
            tod = self.start_time_of_day + t
            return self.mean - self.amplitude * np.cos(2 * np.pi * (tod - self.coldest_at) / 86400.0)
        return np.interp(t, self.times, self.temperatures)


def ambient_from_toml(table, source: str) -> Ambient:
    """The ``[ambient]`` table of a scenario (``source``) as an :class:`Ambient`, checked
    (:func:`check_ambient`); a ``csv`` file is read relative to the scenario."""
    r = TableReader(table, source, "ambient.", known=AMBIENT_KEYS)
    kind = r.get("kind", default="constant")
    if kind == "constant":
        a = Ambient("constant", mean=r.get("temperature", "temperature", required=True))
    elif kind == "daily":
        mean = r.get("mean", "temperature", required=True)
        amplitude = r.get("amplitude", "temperature_difference", required=True)
        times_of_day = {key: r.get(key, "time", default=default)
                        for key, default in (("coldest_at", 6 * 3600.0), ("start_time_of_day", 0.0))}
        a = Ambient("daily", mean=mean, amplitude=amplitude, **times_of_day)
    elif kind == "table":
        times = r.quantities("times", "time")
        temps = r.quantities("temperatures", "temperature")
        a = Ambient("table", times=tuple(times), temperatures=tuple(temps))
    elif kind == "csv":
        name = r.get("file", required=True)
        if not isinstance(name, str) or not name.strip():
            raise InputError(source, "ambient.file", "expected the path of a CSV file (relative to the scenario)")
        path = Path(source).parent / name if not Path(name).is_absolute() else Path(name)
        times, temps = read_room_csv(path, "ambient.file")
        a = Ambient("csv", times=tuple(times), temperatures=tuple(temps), file=str(path))
    else:
        raise InputError(source, "ambient.kind", f"unknown kind {kind!r}; known: constant, daily, table, csv")
    events = tuple(_event(e, source, i) for i, e in enumerate(_events(r, source)))
    r.finish()
    if events:
        a = replace(a, events=events)
    check_ambient(a, source)
    return a


# the fields each kind does not read (a Python-built Ambient must leave them at their defaults)
UNUSED = {"constant": ("amplitude", "coldest_at", "start_time_of_day", "times", "temperatures", "file"),
          "daily": ("times", "temperatures", "file"),
          "table": ("mean", "amplitude", "coldest_at", "start_time_of_day", "file"),
          "csv": ("mean", "amplitude", "coldest_at", "start_time_of_day")}
_DEFAULTS = {f.name: f.default for f in fields(Ambient)}


def check_ambient(a: Ambient, source: str) -> None:
    """The room air's values: temperatures [degC] finite and plausible for room air (a daily
    sine's extremes too, and base + events at their extremes), a daily amplitude not negative and
    its times of day from 0 to 24 h, a table's times increasing with one temperature each, the
    events' times not negative. The loader's checks of ``[ambient]`` (:func:`check_values` runs
    them again on a built scenario)."""
    if not isinstance(a, Ambient):
        raise InputError(source, "ambient", f"expected a twin.scenario.Ambient, got {a!r}")
    if not isinstance(a.kind, str) or a.kind not in UNUSED:     # a list was an unhashable TypeError
        raise InputError(source, "ambient.kind", f"expected one of {', '.join(UNUSED)}, got {describe(a.kind)}")
    for key in UNUSED.get(a.kind, ()):   # a value its kind does not read would be ignored silently
        value = getattr(a, key)
        if isinstance(value, np.ndarray) or not value == _DEFAULTS[key]:     # an array compared elementwise
            raise InputError(source, f"ambient.{key}", f"is not read by kind {a.kind!r}: leave it out (or choose "
                                                       "the kind that uses it)")
    if a.kind == "constant":
        limits.check_temperatures(limits.finite_number(a.mean, source, "ambient.temperature"), source, "ambient.temperature")
    elif a.kind == "daily":
        mean = limits.finite_number(a.mean, source, "ambient.mean")
        limits.check_temperatures(mean, source, "ambient.mean")
        amplitude = limits.finite_number(a.amplitude, source, "ambient.amplitude")
        if amplitude < 0:
            raise InputError(source, "ambient.amplitude", f"must not be negative, got {amplitude:g} K")
        for extreme in (mean - amplitude, mean + amplitude):
            limits.check_temperatures(extreme, source, "ambient.amplitude")
        for key in ("coldest_at", "start_time_of_day"):
            value = limits.finite_number(getattr(a, key), source, f"ambient.{key}")
            if not 0.0 <= value < 86400.0:
                raise InputError(source, f"ambient.{key}", f"a time of day from 0 h to 24 h (excluded), got "
                                                           f"{value / 3600:g} h")
    elif a.kind in ("table", "csv"):
        times = limits.finite_numbers(a.times, source, "ambient.times")
        temps = limits.finite_numbers(a.temperatures, source, "ambient.temperatures")
        if len(times) != len(temps) or len(times) < 1:
            raise InputError(source, "ambient.temperatures", "needs as many entries as ambient.times")
        if np.any(np.diff(times) <= 0):
            raise InputError(source, "ambient.times", "must increase strictly")
        limits.check_temperatures(temps, source, "ambient.temperatures")
    else:
        raise InputError(source, "ambient.kind", f"unknown kind {a.kind!r}; known: constant, daily, table, csv")
    if not isinstance(a.events, (tuple, list)):
        raise InputError(source, "ambient.events", f"expected a tuple of twin.scenario.AirEvent, got {a.events!r}")
    for i, e in enumerate(a.events):
        where = f"ambient.events[{i}]"
        if not isinstance(e, AirEvent):
            raise InputError(source, where, f"expected a twin.scenario.AirEvent, got {e!r}")
        limits.finite_number(e.change, source, f"{where}.change")
        for k in ("start", "fall", "hold", "recovery"):
            if limits.finite_number(getattr(e, k), source, f"{where}.{k}") < 0:
                raise InputError(source, f"{where}.{k}", f"must not be negative, got {getattr(e, k):g} s")
            if getattr(e, k) > limits.MAX_TIME:      # their sums would overflow the check of the air below
                raise InputError(source, f"{where}.{k}", f"{getattr(e, k) / 3600:g} h is beyond any run "
                                                         f"({limits.MAX_TIME / 3600:g} h, about a century)")
        if not isinstance(e.door, bool):
            raise InputError(source, f"{where}.door", f"expected true or false, got {describe(e.door)}")
    if a.events:
        # the extremes of base + events: at every event's corners, from both sides (the events are
        # piecewise linear, and one without hold and recovery jumps back at its peak) and on a
        # fine grid for the base (events apart from each other do not add up)
        corners = np.array([t for e in a.events for t in (e.start, e.start + e.fall, e.start + e.fall + e.hold, e.end)])
        sides = np.concatenate([corners, np.nextafter(corners, -np.inf), np.nextafter(corners, np.inf)])
        t = np.union1d(np.linspace(0.0, corners.max() + 86400.0, 8001), sides[sides >= 0])
        air = a(t)
        limits.check_temperatures([air.min(), air.max()], source, "ambient.events")


def check_air_covers(ambient: Ambient, total: float, source: str, slack: float = 0.0) -> None:
    """A room record (csv) or table covers the run's 0 to ``total`` [s] (to ``slack`` [s] at the
    end): nothing is extrapolated."""
    if ambient.kind == "csv" and ambient.times[-1] < total - slack:
        raise InputError(source, "ambient.file", f"the room record {ambient.file} ends at {ambient.times[-1] / 3600:g} h, "
                                                 f"before the scenario's {total / 3600:g} h")
    if ambient.kind == "table" and (ambient.times[0] > 0 or ambient.times[-1] < total - slack):
        raise InputError(source, "ambient.times", f"the table covers {ambient.times[0] / 3600:g} h to "
                                                  f"{ambient.times[-1] / 3600:g} h; it must cover the scenario's 0 to "
                                                  f"{total / 3600:g} h (nothing is extrapolated)")


def _events(r: TableReader, source: str) -> list:
    raw = r.get("events", default=[])
    if not isinstance(raw, list):
        raise InputError(source, "ambient.events", "expected [[ambient.events]] tables")
    return raw


def _event(raw, source: str, i: int) -> AirEvent:
    """One [[ambient.events]] table: start, change, fall, hold, recovery (times >= 0), door."""
    e = TableReader(raw, source, f"ambient.events[{i}].", known=EVENT_KEYS)
    change = e.get("change", "temperature_difference", required=True)
    times = {k: e.get(k, "time", default=0.0, required=k in ("start", "fall")) for k in ("start", "fall", "hold", "recovery")}
    door = e.get("door", default=False)
    e.finish()
    return AirEvent(change=change, door=door, **times)      # its values: check_ambient
