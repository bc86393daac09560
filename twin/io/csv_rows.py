"""The rows of a CSV data file with the line each was written on, and the numbers in its cells.

Every CSV reader of the twin (room records, measurements, learners' tables, effect schedules)
reads its rows and numbers here, so that:

* blank lines are skipped but still counted: an error names the line an editor shows;
* a cell is a number only as a data file writes one: ASCII digits with an optional sign, decimal
  point and exponent (``-1.5e3``), or a spelling of NaN or infinity, which the caller judges.
  Python's ``float()`` also reads ``1_0`` as 10 and Arabic-Indic or full-width digits, which no
  logger writes and a user never means.
"""

from __future__ import annotations

import csv
import io
import re

NUMBER = re.compile(r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?|[-+]?(?:nan|inf|infinity)",
                    re.IGNORECASE)


def data_rows(text: str) -> tuple[list[int], list[list[str]]]:
    """(line numbers from 1, rows) of every row of the CSV ``text`` that holds a non-blank cell;
    a quoted cell spanning lines counts at its last line. :class:`csv.Error` propagates."""
    reader = csv.reader(io.StringIO(text, newline=""))
    lines, rows = [], []
    for row in reader:
        if row and any(cell.strip() for cell in row):
            lines.append(reader.line_num)
            rows.append(row)
    return lines, rows


def cell_number(text: str) -> float:
    """The number written in a cell (surrounding blanks allowed), NaN and infinity included;
    ValueError for anything else (:data:`NUMBER`)."""
    if not NUMBER.fullmatch(text.strip()):
        raise ValueError(f"not a number: {text!r}")
    return float(text)
