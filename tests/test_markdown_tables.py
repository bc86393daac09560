"""Markdown tables of reports and studies (:mod:`twin.io.markdown`): a ``|`` inside a cell (the
headers ``max |res|``) is escaped so that every row keeps its column count, and a value that rounds
to zero reads 0.000, never -0.000."""

from __future__ import annotations

import re

from twin.io.markdown import table
from validate.studies.common import fmt, markdown_table


def _cells(line: str) -> list[str]:
    """A row's cells, split at the pipes Markdown reads as separators (not the escaped ``\\|``)."""
    return re.split(r"(?<!\\)\|", line.strip())[1:-1]


def test_a_pipe_in_a_cell_does_not_split_it():
    lines = table(["learner", "max |res| um"], [["mlr | ridge", "1.5"], ["multi\nline", "2"]])
    assert [len(_cells(line)) for line in lines if not line.startswith("|---")] == [2, 2, 2]
    assert _cells(lines[0])[1].strip() == "max \\|res\\| um" and lines[1] == "|---|---|"
    assert _cells(lines[3])[0].strip() == "multi line"


def test_a_study_table_keeps_its_columns_and_writes_no_negative_zero():
    text = markdown_table([{"a": -0.0001, "b": "x|y"}, {"a": -1.25, "b": None}], ["a", "b"], ["max |a|", "b"])
    rows = [_cells(line) for line in text.splitlines() if not line.startswith("|---")]
    assert all(len(r) == 2 for r in rows)
    assert [c.strip() for c in rows[1]] == ["0.000", "x\\|y"] and [c.strip() for c in rows[2]] == ["-1.250", ""]
    assert fmt(-0.0) == "0.000" and fmt(-4e-7, 6) == "0.000000" and fmt(-2e5) == "-2e+05"
