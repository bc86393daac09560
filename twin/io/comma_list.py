"""Comma-separated lists of names on the command line (``--effects +a,-b``, ``--cases x,y``).

An empty item (``"a,,b"``, ``"a,"``, ``",a"``) is a name left out by mistake: it is refused, never
dropped, so what the user meant is not guessed.
"""

from __future__ import annotations

from twin.errors import InputError


def comma_items(text: str, source: str, field: str, what: str = "name") -> list[str]:
    """The stripped items of ``text`` split at commas; :class:`InputError` naming ``source`` and
    ``field`` when ``text`` holds no item at all or an empty one."""
    items = [item.strip() for item in str(text).split(",")]
    if not any(items):
        raise InputError(source, field, f"no {what} given")
    if not all(items):
        raise InputError(source, field, f"an empty {what} in {text!r}: write the {what}s comma-separated, each once")
    return items
