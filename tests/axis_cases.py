"""The C-frame moving its three axes: the scenario and the coarse twin that the feed-drive tests
(tests/test_axis_drives.py) and the pose read-out tests (tests/test_axis_pose.py) share."""

from __future__ import annotations

import functools

from geometries import build_machine
from twin.fem.mesh import mesh_machine
from twin.motion import machine_for
from twin.scenario import scenario_from_dict

# whole strokes of each axis (within its travel), 20 mm/s, 10 mm/s2: (from, to, stroke [m])
STROKES = {"X": ("50 mm", "450 mm", 0.40), "Y": ("0 mm", "400 mm", 0.40), "Z": ("0 mm", "330 mm", 0.33)}


def axis_scenario(axes=("X", "Y", "Z"), count: int = 6, duration: str = "10 min"):
    """``count`` reciprocations of each named axis over its whole stroke (:data:`STROKES`), the
    spindle standing, a constant 20 degC room, sampled every 10 s."""
    moves = [{"name": a, "move": [{"kind": "reciprocate", "between": [STROKES[a][0], STROKES[a][1]],
                                   "feed": "20 mm/s", "acceleration": "10 mm/s2", "count": count}]} for a in axes]
    return scenario_from_dict({"sample_interval": "10 s", "ambient": {"temperature": "20 degC"},
                               "spindle": [{"speed": "0 rpm", "duration": duration}], "axis": moves}, "test.toml")


@functools.cache
def cframe_all_axes():
    """(machine, coarse mesh, scenario): the C-frame with the three drives and
    :func:`axis_scenario` moving all three axes, built once for the test session (read only)."""
    sc = axis_scenario()
    machine = machine_for(build_machine("cframe-vmc"), sc)
    return machine, mesh_machine(machine, "coarse"), sc
