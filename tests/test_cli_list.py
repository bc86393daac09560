"""``twin list``: every line that is not indented starts a new entry, whatever the descriptions'
own line breaks (the gantry's scenario descriptions span several lines of their TOML files)."""

from __future__ import annotations

import pytest

from geometries import MACHINES
from twin.cli import main
from twin.dataset.spec import bundled_specs
from twin.effects import EFFECTS
from twin.observe.instruments import INSTRUMENTS
from twin.scenario import available


@pytest.mark.parametrize("what, names", [
    ("scenarios", lambda: list(available()) + list(bundled_specs())),
    ("machines", lambda: sorted(MACHINES)),
    ("effects", lambda: sorted(EFFECTS)),
    ("instruments", lambda: list(INSTRUMENTS)),
])
def test_each_unindented_line_is_one_entry(capsys, what, names):
    """The entries are exactly the unindented lines, one per name, in the listing's order."""
    assert main(["list", what]) == 0
    heads = [line for line in capsys.readouterr().out.splitlines() if line and not line.startswith(" ")]
    expected = names()
    assert len(heads) == len(expected)
    for head, name in zip(heads, expected):
        assert head == name or head.startswith((f"{name}:", f"{name} ("))
