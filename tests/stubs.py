"""Stand-in machines for tests that need only a sliver of :class:`geometries.base.Machine`:
an axis by name (the laser interferometer's read-out) or parts of one box each (the report's
region map)."""

from __future__ import annotations

from types import SimpleNamespace as NS


class OneAxisMachine:
    """The least a laser interferometer reads of a machine: its axis by name."""

    name = "bench"

    def __init__(self, axis):
        self._axis = axis

    def axis(self, name):
        return self._axis


class TwoPartMachine:
    """Parts 'bed' (0..2 x 0..1 x 0..0.5 m) and 'column' (0..0.5 x 0..1 x 0.5..2 m), one box each."""

    def __init__(self):
        self.parts = [NS(name="bed", boxes=[NS(lo=(0.0, 0.0, 0.0), hi=(2.0, 1.0, 0.5))]),
                      NS(name="column", boxes=[NS(lo=(0.0, 0.0, 0.5), hi=(0.5, 1.0, 2.0))])]

    def part(self, name):
        return next(p for p in self.parts if p.name == name)
