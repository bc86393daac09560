"""One TOML table read key by key: types and units checked, unknown and misspelled keys named.

Every input file made of tables (scenarios with their cameras, axis moves, C-axis steps,
interferometer and probing sections; custom effects; dataset specs) reads them through
:class:`TableReader`, so the errors read alike: the file, the key with its table's prefix
(``spindle[2].duration``) and what was wrong (:class:`twin.errors.InputError`).
"""

from __future__ import annotations

import re

from twin import limits
from twin.errors import InputError, describe, refuse_unknown_keys
from twin.units import UnitError, parse_quantity

_WORDS = {"str": "a string", "int": "an integer", "list": "a list", "dict": "a table", "float": "a number",
          "int or float": "a number", "str or list": "a string or a list"}


class TableReader:
    """Reads keys from one TOML table, converting units, remembering which keys were used.

    ``known``: every key the table may hold (for a table whose keys depend on its ``kind``, the
    keys of all kinds, or :meth:`expect` once the kind is read). Before a required key is
    reported missing (:meth:`missing`), a key outside ``known`` is reported as unknown: a
    misspelled ``duraton`` is named, not its correct sibling ``duration``. :meth:`finish` refuses
    every key that was not read."""

    def __init__(self, table, source: str, prefix: str, known=None):
        if not isinstance(table, dict):
            raise InputError(source, prefix.rstrip(".") or "toml", f"expected a table, got {describe(table)}")
        self.table, self.source, self.prefix, self.used = table, source, prefix, set()
        self.known = None if known is None else set(known)

    def field(self, key: str) -> str:
        """The key's name in errors: with the table's prefix (``ambient.mean``)."""
        return self.prefix + key

    def expect(self, *keys: str) -> None:
        """The keys this table may hold (replacing those given before)."""
        self.known = set(keys)

    def missing(self, key: str, message: str = "missing"):
        """Raise the error that ``key`` is missing (``message``), or, first, that the table holds
        a key it does not know (the likely misspelling of ``key``)."""
        if self.known is not None:
            refuse_unknown_keys(self.table, self.known | self.used, self.source, self.prefix)
        raise InputError(self.source, self.field(key), message)

    def get(self, key: str, dimension: str | None = None, default=None, required: bool = False,
            kind: type | tuple | None = None):
        """The value of ``key`` (``default`` when absent; missing is an error when ``required``):
        as the SI value of ``dimension`` when one is given (``"2 h"`` -> 7200.0), else as written,
        of the type ``kind`` when one is given (a boolean is no number)."""
        self.used.add(key)
        if key not in self.table:
            if required:
                self.missing(key)
            return default
        value = self.table[key]
        if dimension is not None:
            try:
                return parse_quantity(value, dimension)
            except UnitError as err:
                raise InputError(self.source, self.field(key), str(err)) from None
        if kind is not None and (not isinstance(value, kind) or isinstance(value, bool) and kind is not bool):
            names = kind.__name__ if isinstance(kind, type) else " or ".join(k.__name__ for k in kind)
            if names == "list" and isinstance(value, dict):   # [x.key] written for [[x.key]]
                header = re.sub(r"\[\d+\]", "", self.field(key))
                raise InputError(self.source, self.field(key), f"expected a list of tables ([[{header}]]), got a "
                                                               f"table ([{header}])")
            raise InputError(self.source, self.field(key), f"expected {_WORDS.get(names, names)}, got "
                                                           f"{describe(value)}")
        return value

    def positive(self, key: str, dimension: str, **kw) -> float:
        """A quantity that must be above zero (``get`` with ``dimension``)."""
        value = self.get(key, dimension, **kw)
        if value is not None and value <= 0:
            raise InputError(self.source, self.field(key), f"must be positive, got {describe(self.table[key])}")
        return value

    def quantities(self, key: str, dimension: str) -> list[float]:
        """A required list of quantities of ``dimension`` (SI values), each entry's unit checked."""
        values = self.get(key, required=True)
        if not isinstance(values, list):
            raise InputError(self.source, self.field(key), "expected a list of quantities")
        out = []
        for i, v in enumerate(values):
            try:
                out.append(parse_quantity(v, dimension))
            except UnitError as err:
                raise InputError(self.source, f"{self.field(key)}[{i}]", str(err)) from None
        return out

    def speed_step(self, dt: float) -> tuple[float, float]:
        """A step's ``speed`` [rpm] (not negative) and ``duration`` [s] (positive, a multiple of
        the sample interval ``dt`` [s]), both required: a [[spindle]] or [[c_axis]] step."""
        speed = self.get("speed", "speed", required=True)
        if speed < 0:
            raise InputError(self.source, self.field("speed"), "must not be negative")
        duration = self.positive("duration", "time", required=True)
        limits.check_whole_samples(duration, dt, self.source, self.field("duration"))
        return speed, duration

    def finish(self, known: tuple[str, ...] = ()) -> None:
        """Refuse every key of the table that was not read (the message lists those read and
        ``known``)."""
        refuse_unknown_keys(self.table, self.used, self.source, self.prefix, shown=set(self.used) | set(known))
