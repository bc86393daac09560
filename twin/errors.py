"""One error type for bad user input.

Every problem with what a user gave us (an unknown name, a malformed file, a value with the wrong
unit, a missing column, a NaN) is raised as :class:`InputError`, naming the *source* (a file path,
``"--set"``, ``"command line"`` ...) and the *field* (a TOML key, a CSV column, a parameter). The CLI
turns it into one line on stderr and exit code 2.
"""

from __future__ import annotations


class InputError(ValueError):
    """Bad user input: ``InputError(source, field, message)``.

    ``str(err)`` reads ``"<source>: <field>: <message>"``.
    """

    def __init__(self, source: str, field: str, message: str):
        self.source = str(source)
        self.field = str(field)
        self.message = str(message)
        super().__init__(f"{self.source}: {self.field}: {self.message}")


def describe(value) -> str:
    """``value`` (read from TOML, a CSV or a Python call) in the user's terms, not as a Python
    repr: ``a TOML date (1979-05-27)``, ``the boolean true``, ``a table (keys: name)``, ``nothing``."""
    import datetime

    if value is None:
        return "nothing"
    if isinstance(value, bool):
        return f"the boolean {str(value).lower()}"
    if isinstance(value, datetime.datetime):
        return f"a TOML date-time ({value.isoformat()})"
    if isinstance(value, datetime.date):
        return f"a TOML date ({value.isoformat()})"
    if isinstance(value, datetime.time):
        return f"a TOML time ({value.isoformat()})"
    if isinstance(value, dict):
        return f"a table (keys: {', '.join(map(str, value))})" if value else "an empty table"
    if isinstance(value, (list, tuple)):
        return f"a list of {len(value)} value{'s' if len(value) > 1 else ''}" if value else "an empty list"
    if isinstance(value, str):
        return repr(value)
    if isinstance(value, (int, float)):
        if isinstance(value, float) and value.is_integer() and abs(value) < 1e15:
            return repr(float(value))       # 2.0, not 2: "expected an integer, got 2" reads as a contradiction
        return f"{value:g}" if isinstance(value, float) else str(value)
    import numpy as np

    if isinstance(value, np.generic) and value.dtype.kind in "biuf":   # read from a NetCDF attribute
        return describe(value.item())
    if isinstance(value, np.ndarray):
        return f"an array of {value.size} value{'s' if value.size != 1 else ''}"
    return type(value).__name__


def refuse_unknown_keys(table: dict, known, source: str, prefix: str, shown=None) -> None:
    """Raise :class:`InputError` naming the first key of ``table`` not in ``known`` and listing
    the known ones (``shown``, by default ``known``): the one check of every TOML table reader,
    at its end and before a key is reported missing, so that a misspelled key is named rather
    than its correct sibling."""
    unknown = sorted(set(table) - set(known), key=str)
    if unknown:
        names = sorted(set(known if shown is None else shown), key=str)
        raise InputError(source, f"{prefix}{unknown[0]}", f"unknown key (known: {', '.join(names)})")
