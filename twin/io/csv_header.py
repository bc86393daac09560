"""A CSV header cell: a column's name and, in square brackets after it, its unit.

``time [h]`` is the column ``time`` in hours, ``air [degC]`` the column ``air`` in degrees Celsius,
``factor`` a column written without a unit. The unit is any spelling of :mod:`twin.units` (the one
module that parses units; :func:`unit_factor` asks it). The room-air record's reader
(:mod:`twin.io.room_csv`) spells its header this way, with a unit required in every column; an
effect's schedule table (:mod:`twin.effects.custom`) with the time's unit optional.
"""

from __future__ import annotations

import re

from twin.units import unit_scale

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
