"""The room: natural convection to the air and the floor under the bed."""

from __future__ import annotations

from twin.effects.base import Convection, Effect, Parameter, Uncertain, constant, first_order_lag, register_effect
from twin.fem.regions import role_facets


@register_effect
class AmbientConvection(Effect):
    """Natural convection and radiation of every skin face to the room air.

        -k dT/dn = h (T - T_air(t)),

    h combines free convection of large vertical and horizontal faces (about 2-5 W/(m2 K),
    Churchill-Chu) with linearised radiation to the room (4 eps sigma T^3, about 5 W/(m2 K)).
    """

    name = "ambient_convection"
    strength = "h"
    linear = False
    summary = "natural convection + linearised radiation of the skin to the room air"
    reference = "VDI Heat Atlas, F2 (free convection) and K1 (radiation)"
    roles = ("structure.skin",)
    parameters = (
        Parameter("h", "heat_transfer_coefficient", 8.0, 0.5, 50.0, "combined natural-convection and radiation coefficient"),
    )
    uncertain = (
        Uncertain("h", 4.0, 16.0, "free convection 2-5 W/(m2 K) by face size and orientation (Churchill-Chu) plus "
                  "radiation 2-6 W/(m2 K) by emissivity (bare 0.3, painted 0.9)"),
    )

    def loads(self, mm, scenario, p):
        h = p["h"]
        return [Convection(self.name, role_facets(mm, "structure.skin"), constant(h), scenario.ambient_temperature)]


@register_effect
class Floor(Effect):
    """Heat exchange of the bed's foot with the floor, which follows the room with a lag.

        -k dT/dn = h_c (T - T_floor(t)),   tau dT_floor/dt = T_air(t) + offset - T_floor,

    with h_c the conductance per unit area of the foot contact (levelling feet on a slab) and tau
    the foundation's thermal time constant (hours).
    """

    name = "floor"
    strength = "conductance"
    linear = False
    summary = "bed foot held to a floor temperature lagging the room air"
    reference = "seed 000 L318-336 (ambient and foundation effects); ISO 230-3 Annex (environment)"
    roles = ("floor.contact",)
    parameters = (
        Parameter("conductance", "heat_transfer_coefficient", 20.0, 0.0, 1000.0, "contact conductance of the foot per unit area"),
        Parameter("lag", "time", 6 * 3600.0, 0.0, 7 * 86400.0, "time constant tau of the floor following the room"),
        Parameter("offset", "temperature_difference", 0.0, -10.0, 10.0, "floor minus lagged room temperature"),
    )
    uncertain = (
        Uncertain("conductance", 2.0, 200.0, "levelling feet on a slab (a few W/(m2 K)) to a bed grouted onto its "
                  "foundation (hundreds)"),
    )

    def loads(self, mm, scenario, p):
        lagged = first_order_lag(scenario.ambient_temperature, p["lag"], scenario.duration)
        offset, hc = p["offset"], p["conductance"]
        return [Convection(self.name, role_facets(mm, "floor.contact"), constant(hc),
                           lambda t: lagged(t) + offset)]
