"""GitHub Markdown tables for reports and studies: one place that joins cells and escapes what
would break a row (a ``|`` inside a cell, as in ``max |residual|``, ends the cell; a line break
ends the row)."""

from __future__ import annotations


def cell(text) -> str:
    """``text`` as one table cell: ``|`` escaped, line breaks as spaces."""
    return " ".join(str(text).replace("|", "\\|").splitlines())


def fixed(value: float, digits: int = 3) -> str:
    """``value`` to ``digits`` decimals, a value that rounds to zero written without its sign
    (0.000, never -0.000)."""
    text = f"{value:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0.0 else text


def table(header: list, rows: list[list]) -> list[str]:
    """The lines of a Markdown table with ``header`` and ``rows`` (each a list of cell texts)."""
    lines = ["| " + " | ".join(cell(h) for h in header) + " |", "|" + "---|" * len(header)]
    return lines + ["| " + " | ".join(cell(c) for c in r) + " |" for r in rows]
