"""A CSV header cell: a column's name and, in square brackets after it, its unit.

``time [h]`` is the column ``time`` in hours, ``air [degC]`` the column ``air`` in degrees Celsius,
``factor`` a column written without a unit. The unit is any spelling of :mod:`twin.units` (the one
module that parses units; :func:`unit_factor` asks it). The room-air record's reader
(:mod:`twin.io.room_csv`) spells its header this way, with a unit required in every column; an
effect's schedule table (:mod:`twin.effects.custom`) with the time's unit optional; a measurement's
column mapping (:mod:`twin.io.measurement`) may name a column ``t [min]``. Where a TOML file gives a
column's unit as well (a schedule's ``time_unit``, a mapping's ``unit``), the two must agree
(:func:`unit_contradiction`, the one check).
"""

from __future__ import annotations

import re

from twin.units import UnitError, unit_scale

HEADER = re.compile(r"^\s*(?P<name>[^\[\]]*?)\s*\[(?P<unit>[^\[\]]+)\]\s*$")   # "name [unit]"


def name_and_unit(cell: str) -> tuple[str, str | None]:
    """(name, unit) of the header cell ``cell``, both stripped; the unit is None when the cell has
    no brackets. ValueError, in words for the user, when the brackets are malformed (``time [``,
    ``time []``, ``time [s] [min]``, ``[s] time``)."""
    if "[" not in cell and "]" not in cell:
        return cell.strip(), None
    m = HEADER.match(cell)
    if not m:
        raise ValueError(f"{cell.strip()!r} is not a name with its unit in brackets, like 'time [min]'")
    return m["name"], m["unit"].strip()


def unit_factor(unit: str, dimension: str) -> float:
    """The SI value of one ``unit`` of ``dimension`` (``"min"``, ``"time"`` -> 60.0);
    :class:`twin.units.UnitError` for a unit of another kind or none known."""
    return unit_scale(unit, dimension)


def unit_contradiction(cell: str, unit: str, scale: float, dimension: str, csv_src: str,
                       values: str = "values") -> str | None:
    """Why ``unit`` (SI value ``scale`` of ``dimension``), the unit a TOML file gives a CSV column,
    contradicts the unit written in the column's header cell ``cell``, in words naming the CSV
    ``csv_src`` and the cell: ``'min' contradicts the header of run.csv, 'time [s]' (times in s)``,
    ``values`` saying what the column holds. None when the cell names no unit (no brackets at its
    end: ``T [front]_degC`` is a name) or a unit of ``dimension`` of the same value (``h`` and
    ``hr`` agree); a unit of another kind or none known (``room [K]`` for a temperature) contradicts,
    and the words say why. The caller raises them as the :class:`twin.errors.InputError` of its TOML
    key, with its advice: a column read in one unit while its header says another is misread by a
    constant factor, silently."""
    m = HEADER.match(cell)
    if not m:
        return None
    written = m["unit"].strip()
    try:
        if unit_factor(written, dimension) == scale:
            return None
        why = ""
    except UnitError as err:
        why = f"; {err}"
    return f"{unit!r} contradicts the header of {csv_src}, {cell.strip()!r} ({values} in {written}{why})"
