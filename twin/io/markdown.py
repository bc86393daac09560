"""GitHub Markdown tables for reports and studies: one place that joins cells and escapes what
would break a row (a ``|`` inside a cell, as in ``max |residual|``, ends the cell; a line break
ends the row)."""

from __future__ import annotations


def cell(text) -> str:
    """``text`` as one table cell: ``|`` escaped, line breaks as spaces."""
    return " ".join(str(text).replace("|", "\\|").splitlines())


def table(header: list, rows: list[list]) -> list[str]:
    """The lines of a Markdown table with ``header`` and ``rows`` (each a list of cell texts)."""
    lines = ["| " + " | ".join(cell(h) for h in header) + " |", "|" + "---|" * len(header)]
    return lines + ["| " + " | ".join(cell(c) for c in r) + " |" for r in rows]
