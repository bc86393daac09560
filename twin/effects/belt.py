"""Belt-drive heat: the losses of a belt from the spindle motor to a pulley on the spindle."""

from __future__ import annotations

from twin.effects.base import Effect, Parameter, SurfaceHeatFlux, Uncertain, register_effect, speed_power_law
from twin.fem.regions import role_facets


@register_effect
class BeltDrive(Effect):
    """Belt losses that flow into the spindle top through the pulley's contact band.

    A belt drive loses a few per cent of the power it transmits (V- and poly-V belts are
    93-98 % efficient): bending hysteresis of the belt as it wraps each pulley (a torque loss
    nearly independent of speed, so a power loss ~ n), friction and creep in the belt-groove
    contact, and windage of the belt and pulleys (~ n^3). An idling spindle transmits only its
    own drag, so the whole loss is a function of speed, taken as one power law

        P(n) = P_ref (n / n_ref)^x   (n > 0, else 0),   n_ref = 8000 rpm,

    with x between 1 (pure hysteresis) and 3 (pure windage); the default x = 1.5 is a
    hysteresis-dominated mix. P_ref is only the share that enters the spindle: the belt is heated
    by its own losses and gives them to both pulleys and the air. Default: a 5.5 kW poly-V drive
    loses some 1-2 % of its rating at speed without load, 50-100 W at 40 m/s belt speed, and
    about half of it reaches the spindle pulley: P_ref = 50 W. The load-dependent part
    (1 - eta) P_transmitted of a cutting load is not modelled (the scenarios run the spindle idle).

    The heat arises in the belt-pulley contact, so it enters as a uniform surface flux on the
    pulley's rim (role ``spindle.belt_contact``: its lateral faces; the pulley turns at spindle speed, so the
    contact's heat is spread round the whole rim) and is conducted through the pulley into the
    top of the spindle (seed 000 L4048-4052: the belt drive "may act as a heat source by which the
    heat flows into the spindle through the contacting areas"). A volume source in the pulley
    would differ little on these meshes (the pulley is one or two cells high); the surface flux
    keeps the heat where it arises whatever the mesh. Needs a machine with a belt-driven spindle
    (the role ``spindle.belt_contact``: ``belt-vmc``).
    """

    name = "belt_drive"
    summary = "belt losses into the spindle pulley's rim, P = P_ref (n/n_ref)^x"
    reference = ("seed 000 L4048-4052 (belt drive, heat into the spindle through the contacting areas); "
                 "Gates, 'Belt drive efficiencies' (95-98 %: hysteresis, contact friction, windage); "
                 "P. R. N. Childs, Mechanical Design Engineering Handbook, 2nd ed. (2019), chapter on belt and chain drives")
    parameters = (
        Parameter("power", "power", 50.0, 0.0, 2000.0, "belt loss into the spindle pulley at the reference speed"),
        Parameter("reference_speed", "speed", 8000.0, 100.0, 60000.0, "speed at which the reference power holds"),
        Parameter("exponent", "dimensionless", 1.5, 0.5, 3.0, "speed exponent x (hysteresis 1, windage 3)"),
    )
    uncertain = (
        Uncertain("power", 10.0, 200.0, "belt tension, wrap and belt type set the loss (93-98 % efficiency), and "
                  "how much of it enters the pulley rather than the air", linear=True),
    )
    roles = ("spindle.belt_contact",)
    strength = "power"
    linear = True

    def loads(self, mm, scenario, p):
        return [SurfaceHeatFlux(self.name, role_facets(mm, "spindle.belt_contact"),
                                speed_power_law(scenario, p["reference_speed"], p["exponent"], p["power"]))]
