"""The workshop round the machine in an environmental (ETVE) test: the outside air that streams in
through a door the scenario opens. Without door events it puts no heat into the machine, so the
spindle calibration is untouched by it.
"""

from __future__ import annotations

import numpy as np

from twin.effects.base import Convection, Effect, Parameter, Uncertain, register_effect
from twin.fem.regions import role_facets


def door_open(scenario, t: np.ndarray) -> np.ndarray:
    """1 while a door event of the scenario's ambient is open (from its start to the end of its
    fall and hold), else 0; times [s]."""
    t = np.asarray(t, dtype=float)
    w = np.zeros(t.shape)
    for e in getattr(scenario.ambient, "events", ()):
        if e.door:
            w = np.maximum(w, ((t >= e.start) & (t < e.start + e.fall + e.hold)).astype(float))
    return w


@register_effect
class DoorStream(Effect):
    """The outside air streaming in through a door the scenario opens (``[[ambient.events]]`` with
    ``door = true``) onto the machine's front where a draft reaches it (``structure.open_front``:
    on the C-frame the head, spindle and motor, the bed, saddle and table, not the column face
    behind the Z way covers) and round the spindle and test bar (``spindle.rotating``):

        -k dT/dn = h_d w(t) (T - T_air(t) - dT),  w(t) = 1 while a door is open, else 0,

    added to the natural convection (``ambient_convection``'s 8 W/(m2 K) is not repeated here);
    dT is the stream's temperature below the mixed room air (snow outside). h_d of a 1-3 m/s
    stream is 6-11 W/(m2 K) on a 0.4 m plate (Nu = 0.664 Re^0.5 Pr^(1/3)) and 15-30 W/(m2 K)
    round a 40 mm bar in cross flow (Hilpert, Nu = 0.193 Re^0.618 Pr^(1/3): 22 at 2 m/s); one
    h_d serves both, the bar's, which carries the event's Z. The thin steel test bar follows such
    a stream within minutes (lumped time constant rho c d / (4 (h_d + 8)) about 20 min), the
    castings in hours: the door event's fast Z step is mostly the bar and the spindle nose, which
    is why the seed put a fourth probe on the casting (thesis L6225-6277).
    """

    name = "door_stream"
    strength = "h"
    linear = False
    summary = "outside air T_air + dT with h_d on the open front and the test bar while a scenario door is open"
    reference = "VDI Heat Atlas G4 (plate) and G6 (cylinder in cross flow); seed 000 L6225-6277 (door events)"
    roles = ("structure.open_front", "spindle.rotating")
    parameters = (
        Parameter("h", "heat_transfer_coefficient", 22.0, 0.0, 100.0, "stream heat-transfer coefficient h_d"),
        Parameter("temperature_difference", "temperature_difference", -12.0, -40.0, 40.0,
                  "stream minus mixed room air dT"),
    )
    uncertain = (      # they leave no trace in a record without a door event (scenario door = true)
        Uncertain("h", 6.0, 40.0, "a 1-4 m/s stream: 6-11 W/(m2 K) on the castings' plates, 15-30 round the "
                                  "test bar (Hilpert); how far it reaches the machine depends on the door"),
        Uncertain("temperature_difference", -25.0, 0.0, "the outside air in winter, mixed on its way in: from the "
                                                        "room's own air to 25 K below it"),
    )

    def acts(self, scenario, params: dict | None = None) -> bool:
        """Only while a door of the scenario is open."""
        return any(e.door for e in getattr(scenario.ambient, "events", ()))

    def loads(self, mm, scenario, p):
        if not self.acts(scenario):
            return []   # no door in this scenario: no load (and no input for a reduced model)
        facets = np.union1d(role_facets(mm, "structure.open_front"), role_facets(mm, "spindle.rotating"))
        h, dT = p["h"], p["temperature_difference"]
        return [Convection(self.name, facets, lambda t: h * door_open(scenario, t),
                           lambda t: scenario.ambient_temperature(t) + dT)]
