"""Drive-side effects beyond the spindle heat: a coolant jacket and the Z-axis holding current."""

from __future__ import annotations

import numpy as np

from twin.effects.base import Convection, Effect, HeatSource, Parameter, Uncertain, constant, register_effect
from twin.fem.regions import role_cells, role_facets


@register_effect
class SpindleCoolant(Effect):
    """A cooling jacket round the spindle cartridge removing heat while the spindle turns.

        Q = G (T_jacket - T_c),  T_c(t) = T_air(t) + offset,

    modelled as a convection condition on the cartridge/carrier interface (``spindle_jacket``)
    with h = G / A_jacket while n(t) > 0 (the chiller runs with the spindle), 0 otherwise.
    G [W/K] is the jacket's overall conductance UA; room-tracking chillers hold T_c at the room
    air plus an offset.
    """

    name = "spindle_coolant"
    strength = "conductance"
    linear = False
    summary = "jacket conductance G to coolant at T_air + offset on the cartridge, while the spindle runs"
    reference = "Bossmanns & Tu, Int. J. Mach. Tools Manuf. 39 (1999) 1345-1366 (spindle cooling)"
    roles = ("spindle.jacket",)
    parameters = (
        Parameter("conductance", "conductance", 20.0, 0.0, 500.0, "jacket conductance G = UA"),
        Parameter("offset", "temperature_difference", 0.0, -10.0, 10.0, "coolant minus room air temperature"),
    )
    uncertain = (
        Uncertain("conductance", 5.0, 100.0, "jacket UA depends on the coolant flow and the jacket's fouling"),
    )

    def loads(self, mm, scenario, p):
        facets = role_facets(mm, "spindle.jacket")
        h = p["conductance"] / mm.facet_area(facets)
        off = p["offset"]
        return [Convection(self.name, facets, lambda t: h * (np.abs(scenario.spindle_speed(t)) > 0),
                           lambda t: scenario.ambient_temperature(t) + off)]


@register_effect
class ZAxisHolding(Effect):
    """The Z servo motor and its brake holding the carrier against gravity at the column top.

        P(t) = P_hold   (constant, also when no axis moves),

    the holding current's copper losses I^2 R (torque = m g p / (2 pi)) plus brake coil heat,
    spread uniformly over the machine's ``z_drive.top`` region (on the C-frame, the column's top
    0.2 m where the Z motor sits).
    """

    name = "z_axis_holding"
    strength = "power"
    linear = True
    summary = "constant holding losses of the Z motor and brake in the column top"
    reference = "Mayr et al., CIRP Annals 61/2 (2012) 771-791, sec. 3.2 (feed drives)"
    roles = ("z_drive.top",)
    parameters = (
        Parameter("power", "power", 25.0, 0.0, 500.0, "holding losses into the column top P_hold"),
    )
    uncertain = (
        Uncertain("power", 5.0, 150.0, "holding current (carrier mass, counterweight) and brake coil", linear=True),
    )

    def loads(self, mm, scenario, p):
        power = p["power"]
        return [HeatSource(self.name, role_cells(mm, "z_drive.top"), constant(power))]
