"""A room-air record: a CSV of measured air temperatures that drives a scenario's ambient.

Two columns with the unit of each in its header, in square brackets::

    time [h],air [degC]
    0,18.2
    0.5,18.0
    ...

The time unit is any time unit of :mod:`twin.units` (s, min, h, d), the temperature's degC (an
absolute temperature; a log in kelvin is refused with a hint). Time counts from the first row (a log that starts at
10:00 is shifted to start at 0). Every problem raises :class:`twin.errors.InputError` naming the
file and the column (or line): not UTF-8, not two columns, a header without a unit, a unit of the
wrong kind, an empty or non-numeric cell, NaN or inf, times that do not increase strictly, a
temperature below absolute zero or outside the plausible range of room air
(:func:`twin.limits.check_temperatures`), fewer than two rows.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from twin import limits
from twin.errors import InputError
from twin.io.csv_header import name_and_unit, unit_factor
from twin.io.csv_rows import cell_number, data_rows
from twin.io.paths import read_text
from twin.units import UnitError

def read_room_csv(path: str | Path, field: str = "ambient.file") -> tuple[np.ndarray, np.ndarray]:
    """(times [s] from the first row, air temperatures [degC]) of a room-air CSV ``path``;
    ``field`` names the scenario key that pointed at it (for errors about the file itself)."""
    src = str(path)
    text = read_text(path, field, "room-air CSV file")
    try:
        lines, rows = data_rows(text)
    except csv.Error as err:
        raise InputError(src, field, f"not a readable CSV file ({err})") from None
    if len(rows) < 3:
        raise InputError(src, field, "needs a header row and at least two data rows")
    if len(rows[0]) != 2:
        raise InputError(src, "header", f"expected two columns, 'time [h]' and 'air [degC]', got {len(rows[0])}")
    (t_name, t_unit), (a_name, a_unit) = (_unit(src, h, k) for k, h in enumerate(rows[0]))
    for line, r in zip(lines[1:], rows[1:]):
        if len(r) != 2:
            raise InputError(src, f"line {line}", f"has {len(r)} fields, the header has 2")
    if _is_unit(t_unit, "temperature") and _is_unit(a_unit, "time"):
        raise InputError(src, "header", f"the columns are swapped ({rows[0][0].strip()!r}, {rows[0][1].strip()!r}): "
                                        "the time goes first, then the air, like 'time [h],air [degC]'")
    t = _values(src, lines, rows, 0, t_name, t_unit, "time")
    air = _values(src, lines, rows, 1, a_name, a_unit, "temperature")
    step = np.diff(t)
    if np.any(step <= 0):
        i = int(np.flatnonzero(step <= 0)[0])
        raise InputError(src, t_name, f"time does not increase at line {lines[i + 2]} ({rows[i + 2][0].strip()} after "
                                      f"{rows[i + 1][0].strip()} {t_unit})")
    limits.check_temperatures(air, src, a_name, lines=lines[1:])
    return t - t[0], air


def _unit(src: str, header: str, k: int) -> tuple[str, str]:
    try:
        name, unit = name_and_unit(header)
    except ValueError:
        unit = None
    if unit is None:
        example = "time [h]" if k == 0 else "air [degC]"
        raise InputError(src, "header", f"column {k + 1} {header.strip()!r} needs its unit in brackets, like {example!r}")
    return name or f"column {k + 1}", unit


def _is_unit(unit: str, dimension: str) -> bool:
    try:
        unit_factor(unit, dimension)
    except UnitError:
        return False
    return True


def _values(src: str, lines: list[int], rows, j: int, name: str, unit: str, dimension: str) -> np.ndarray:
    """The column's SI values: each cell a plain number (:func:`twin.io.csv_rows.cell_number`)
    times the header unit's factor (:func:`twin.io.csv_header.unit_factor`)."""
    try:
        factor = unit_factor(unit, dimension)
    except UnitError as err:
        raise InputError(src, name, f"header unit [{unit}]: {err}") from None
    out = np.empty(len(rows) - 1)
    for i, (line, r) in enumerate(zip(lines[1:], rows[1:])):
        cell = r[j].strip()
        try:
            out[i] = cell_number(cell) * factor   # the unit lives in the header; every unit here is offset-free
        except ValueError:
            raise InputError(src, name, f"line {line}: {cell!r} is not a number") from None
        if not np.isfinite(out[i]):
            raise InputError(src, name, f"line {line}: {cell!r} is not a finite number")
    return out
