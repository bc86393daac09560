"""The schedule s(t) of a custom effect (:mod:`twin.effects.custom`) and its reader.

s(t) is dimensionless; the effect's load is its strength times s(t). The kinds: ``constant``
(s = 1), ``spindle_on`` (1 while the spindle turns), ``speed`` (s = (n / n_ref)^x),
``windows`` (1 inside any [start, end) window; no two windows sharing a time) and ``table``
(linear in a CSV table of time and factor covering the whole run). The reader checks every
value against its plausible range and names the effects file and key, or the CSV file and
column, in one :class:`twin.errors.InputError`.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from twin import limits
from twin.errors import InputError, describe
from twin.io.csv_header import name_and_unit, unit_contradiction, unit_factor
from twin.io.table_reader import TableReader
from twin.units import UnitError, parse_quantity

MAX_EXPONENT = 3.0         # speed exponent: windage grows with n^3, nothing on a spindle faster
SPEED_RANGE = (100.0, 60000.0)   # rpm: reference_speed, as the library's speed laws
MAX_FACTOR = 100.0         # a table's factor: the strength's multiple
SCHEDULES = ("constant", "spindle_on", "speed", "windows", "table")
TIME_NAMES = ("time", "t")     # a schedule table's header: column 1 (any case), its unit in brackets or time_unit
FACTOR_NAMES = ("factor",)     # column 2, without a unit


class Schedule:
    """s(t) [-] of a custom effect: ``kind`` and its data; :meth:`signal` binds a scenario."""

    def __init__(self, kind: str, reference_speed: float = 0.0, exponent: float = 1.0,
                 windows: tuple = (), table: tuple = (), file: str = ""):
        self.kind, self.reference_speed, self.exponent = kind, reference_speed, exponent
        self.windows, self.table, self.file = windows, table, file

    def peak(self, machine) -> float:
        """The largest s(t) on ``machine``: 1 (constant, spindle_on, windows), the table's largest
        factor, or (n_max / n_ref)^x at the machine's maximum spindle speed n_max."""
        if self.kind == "speed":
            return (limits.max_speed(machine) / self.reference_speed) ** self.exponent
        if self.kind == "table":
            return float(np.max(self.table[1]))
        return 1.0

    def check_reach(self, scenario, source: str, field: str) -> None:
        """A table must reach the end of ``scenario`` (like a room-air record), and every window
        must open before it (a window after the run would do nothing, as a scenario's event after
        its end, which is refused too); raise :class:`InputError` naming ``source`` and
        ``field``'s key otherwise (``field``: ``effects.NAME``)."""
        total = float(scenario.duration)
        if self.kind == "windows":
            for i, (start, _) in enumerate(self.windows):
                if start >= total * (1 - 1e-9):
                    raise InputError(source, f"{field}.windows[{i}]", f"opens at {start / 3600:g} h, at or after the "
                                                                      f"end of the scenario's {total / 3600:g} h: it "
                                                                      "would do nothing")
        if self.kind != "table":
            return
        end = float(self.table[0][-1])
        if end < total * (1 - 1e-9):
            raise InputError(source, f"{field}.table", f"the schedule table {self.file} ends at {end / 3600:g} h, "
                                                       f"before the scenario's {total / 3600:g} h; it must cover the "
                                                       "whole run (nothing is extrapolated)")

    @property
    def describe(self) -> str:
        if self.kind == "speed":
            return f"x (n / {self.reference_speed:g} rpm)^{self.exponent:g}"
        if self.kind == "windows":
            return "in " + ", ".join(f"{a / 3600:g}-{b / 3600:g} h" for a, b in self.windows)
        return {"constant": "constant", "spindle_on": "while the spindle turns", "table": "from a table"}[self.kind]

    def signal(self, scenario):
        """s(t) for times t [s] of ``scenario``."""
        if self.kind == "constant":
            return lambda t: np.ones(np.shape(t))
        if self.kind == "spindle_on":
            return lambda t: (np.abs(scenario.spindle_speed(t)) > 0).astype(float)
        if self.kind == "speed":
            n_ref, x = self.reference_speed, self.exponent
            return lambda t: np.power(np.abs(scenario.spindle_speed(t)) / n_ref, x)
        if self.kind == "windows":
            return lambda t: np.any([(np.asarray(t) >= a) & (np.asarray(t) < b) for a, b in self.windows],
                                    axis=0).astype(float)
        times, factors = self.table
        return lambda t: np.interp(t, times, factors)


def read_schedule(r: TableReader, src: str, where: str, folder: Path) -> Schedule:
    kind = r.get("schedule", default="constant")
    if kind not in SCHEDULES:
        raise InputError(src, where + ".schedule", f"unknown schedule {describe(kind)}; known: {', '.join(SCHEDULES)}")
    if kind == "speed":
        n_ref = r.positive("reference_speed", "speed", required=True)
        if not SPEED_RANGE[0] <= n_ref <= SPEED_RANGE[1]:
            raise InputError(src, where + ".reference_speed", f"{n_ref:g} rpm is outside {SPEED_RANGE[0]:g} to "
                                                              f"{SPEED_RANGE[1]:g} rpm, the speeds of machine-tool "
                                                              "spindles")
        x = float(r.get("exponent", "dimensionless", default=1.0))
        if not 0 <= x <= MAX_EXPONENT:
            raise InputError(src, where + ".exponent", f"{x:g} is outside 0 to {MAX_EXPONENT:g} (s = (n / n_ref)^x: "
                                                       "friction 1, Palmgren 5/3, windage 3; a negative exponent "
                                                       "is infinite when the spindle stops)")
        return Schedule(kind, n_ref, x)
    if kind == "windows":
        raw = r.get("windows", required=True)
        if not isinstance(raw, list) or not raw:
            raise InputError(src, where + ".windows", "expected a list of [start, end] pairs with units")
        out = []
        for i, w in enumerate(raw):
            if not isinstance(w, list) or len(w) != 2:
                raise InputError(src, f"{where}.windows[{i}]", "expected [start, end]")
            try:
                a, b = (parse_quantity(v, "time") for v in w)
            except UnitError as err:
                raise InputError(src, f"{where}.windows[{i}]", str(err)) from None
            if a < 0:
                raise InputError(src, f"{where}.windows[{i}]", f"start {w[0]!r} is before the run's start "
                                                                "(times count from 0)")
            if not b > a:
                raise InputError(src, f"{where}.windows[{i}]", "end must come after start")
            out.append((a, b))
        _refuse_overlaps(out, raw, src, where)
        return Schedule(kind, windows=tuple(out))
    if kind == "table":
        path, table = _table(r.get("table", required=True), src, where + ".table", folder)
        return Schedule(kind, table=table, file=str(path))
    return Schedule(kind)


def _refuse_overlaps(windows: list[tuple[float, float]], raw: list, src: str, where: str) -> None:
    """Refuse two windows that share a time (one repeated, or overlapping): s(t) is 1 inside any
    window, so the shared time is not loaded twice, as the list seems to ask, and one of the two
    is most likely a typo. Windows that only touch (one's end the next's start) are fine; the
    error names the later-listed window's field and both windows as written (the ends, rounded
    apart by different units, are compared to 1e-9)."""
    order = sorted(range(len(windows)), key=lambda i: windows[i])
    reach = order[0] if order else 0            # the window, of those by start so far, that ends last
    for i in order[1:]:
        if windows[i][0] < windows[reach][1] * (1 - 1e-9):    # "1.1 d" and "26.4 h" touch, rounded apart
            a, b = sorted((reach, i))
            how = "repeats" if windows[a] == windows[b] else "overlaps"
            raise InputError(src, f"{where}.windows[{b}]",
                             f"{_window_text(raw[b])} {how} windows[{a}] {_window_text(raw[a])}: the factor is 1 "
                             "inside any window, so a shared time is not loaded twice; merge them into one window "
                             "(windows may touch: one's end the next's start)")
        if windows[i][1] > windows[reach][1]:
            reach = i


def _window_text(w: list) -> str:
    return "[" + ", ".join(f'"{v}"' if isinstance(v, str) else describe(v) for v in w) + "]"


def _table(spec, src: str, where: str, folder: Path) -> tuple[Path, tuple[np.ndarray, np.ndarray]]:
    """(path, (times [s], factors)) of a schedule table: a header row naming the time first and
    the factor second (:data:`TIME_NAMES`, :data:`FACTOR_NAMES`; the time's unit in brackets,
    ``time [min]``, or from ``time_unit``), then at least two rows of time (from 0, the run's start,
    increasing) and factor (0 to :data:`MAX_FACTOR`)."""
    r = TableReader(spec, src, where + ".", known=("file", "time_unit"))
    name = r.get("file", required=True)
    unit = r.get("time_unit")
    r.finish()
    if not isinstance(name, str) or not name.strip():
        raise InputError(src, where + ".file", f"expected the path of a CSV file, got {describe(name)}")
    scale = None
    if unit is not None:
        if not isinstance(unit, str):
            raise InputError(src, where + ".time_unit", f"expected a time unit such as \"min\", got {describe(unit)}")
        try:
            scale = unit_factor(unit, "time")
        except UnitError as err:
            raise InputError(src, where + ".time_unit", str(err)) from None
    from twin.io.csv_rows import NUMBER, cell_number, data_rows
    from twin.io.paths import read_text

    path = folder / name
    csv_src = str(path)
    try:
        lines, rows = data_rows(read_text(path, "file", "schedule table"))
    except csv.Error as err:
        raise InputError(csv_src, "table", f"not a readable CSV file ({err})") from None
    if len(rows) < 3:
        raise InputError(csv_src, "table", "needs a header row (e.g. 'time,factor') and at least two data rows")
    for line, row in zip(lines, rows):
        if len(row) != 2:
            raise InputError(csv_src, f"line {line}", f"has {len(row)} fields; expected two columns: time, factor")
    if all(NUMBER.fullmatch(c.strip()) for c in rows[0]):
        raise InputError(csv_src, "header", f"the first row {','.join(rows[0])!r} is numbers; the table needs a "
                                            "header row such as 'time,factor'")
    scale, unit = _table_header(rows[0], unit, scale, src, where, csv_src)
    values = np.empty((len(rows) - 1, 2))
    for i, (line, row) in enumerate(zip(lines[1:], rows[1:])):
        for j, cell in enumerate(row):
            what = ("time", "factor")[j]
            try:
                values[i, j] = cell_number(cell)
            except ValueError:
                raise InputError(csv_src, what, f"line {line}: {cell.strip()!r} is not a number") from None
            if not np.isfinite(values[i, j]):
                raise InputError(csv_src, what, f"line {line}: {cell.strip()!r} is not a finite number")
    times, factors = values[:, 0] * scale, values[:, 1]
    if times[0] != 0:
        raise InputError(csv_src, "time", f"line {lines[1]}: the table starts at {rows[1][0].strip()} {unit}; it "
                                          "must start at 0, the run's start (times count from it; nothing is extrapolated)")
    step = np.diff(times)
    if np.any(step <= 0):
        i = int(np.flatnonzero(step <= 0)[0])
        raise InputError(csv_src, "time", f"must increase strictly (line {lines[i + 2]}: {rows[i + 2][0].strip()} "
                                          f"after {rows[i + 1][0].strip()} {unit})")
    bad = np.flatnonzero((factors < 0) | (factors > MAX_FACTOR))
    if bad.size:
        i = int(bad[0])
        raise InputError(csv_src, "factor", f"line {lines[i + 1]}: {factors[i]:g} is outside 0 to {MAX_FACTOR:g} (the "
                                            "factor multiplies the effect's strength; a sink has a negative "
                                            "strength, not a negative factor)")
    return path, (times, factors)


def _table_header(header: list[str], unit, scale, src: str, where: str, csv_src: str) -> tuple[float, str]:
    """(seconds per time unit, the unit's spelling) of a schedule table whose header row is
    ``header`` (two cells), ``unit``/``scale`` those of ``time_unit`` (None when not given).

    The rule: column 1 is the time (:data:`TIME_NAMES`), column 2 the factor (:data:`FACTOR_NAMES`),
    names in any case; the time's unit is in the header (``time [min]``, any time unit of
    :mod:`twin.units`) or in ``time_unit``; both given must agree (``h`` and ``hr`` do), else the
    two are a contradiction. The factor is a plain number: a unit on it is refused. Errors name the
    CSV file and the column (its header cell), or the TOML field ``time_unit``."""
    cells = []
    for k, cell in enumerate(header):
        try:
            cells.append(name_and_unit(cell))
        except ValueError as err:
            raise InputError(csv_src, "header", f"column {k + 1}: {err}") from None
    (t_name, t_unit), (f_name, f_unit) = cells
    expected = "the time first, then the factor: 'time,factor' or 'time [min],factor'"
    if t_name.lower() not in TIME_NAMES or f_name.lower() not in FACTOR_NAMES:
        swapped = t_name.lower() in FACTOR_NAMES and f_name.lower() in TIME_NAMES
        bad, k = ((header[0], 1) if t_name.lower() not in TIME_NAMES else (header[1], 2))
        raise InputError(csv_src, "header", f"column {k} is {bad.strip()!r}; the header names {expected}"
                                            + (" (the columns are swapped)" if swapped else ""))
    if f_unit is not None:
        raise InputError(csv_src, "factor", f"header {header[1].strip()!r}: the factor is a plain number (a multiple "
                                            "of the effect's strength) and has no unit; write 'factor'")
    if t_unit is None:
        if unit is None:
            raise InputError(src, where + ".time_unit", f"missing: the header of {csv_src} gives the time no unit "
                                                        f"({header[0].strip()!r}); write time_unit = \"min\" here or "
                                                        "the unit in the header, 'time [min]'")
        return scale, unit
    try:
        t_scale = unit_factor(t_unit, "time")
    except UnitError as err:
        raise InputError(csv_src, "time", f"header unit [{t_unit}]: {err}") from None
    conflict = None if scale is None else unit_contradiction(header[0], unit, scale, "time", csv_src, "times")
    if conflict:
        raise InputError(src, where + ".time_unit", f"{conflict}; give the time's unit once: leave time_unit out "
                                                    "or make the two agree")
    return t_scale, t_unit
