"""Spindle heat: bearing friction, motor losses and speed-dependent forced convection."""

from __future__ import annotations

from twin.effects.base import (ContactConductance, Convection, Effect, HeatSource, Parameter, Uncertain, constant,
                               register_effect, speed_power_law)
from twin.fem.regions import role_cells, role_facets, role_parts

_REF = Parameter("reference_speed", "speed", 9000.0, 100.0, 60000.0, "speed at which the reference value holds")


@register_effect
class SpindleBearings(Effect):
    """Friction heat of the front and rear spindle bearings, growing with speed.

    Palmgren's viscous friction torque M_v = 1e-7 f0 (nu n)^(2/3) dm^3 gives a power
    P = M_v omega proportional to n^(5/3) at fixed lubrication, so

        P_front(n) = P_front,ref (n / n_ref)^x,   P_rear(n) = P_rear,ref (n / n_ref)^x,

    with x = 5/3 by default, each spread uniformly over its bearing zone (volumetric, W).
    The reference powers are plausible for a 9000 rpm grease-lubricated 70 mm cartridge.
    """

    name = "spindle_bearings"
    strength = "front_power"
    linear = True
    summary = "friction heat at the front and rear spindle bearings, P = P_ref (n/n_ref)^x"
    reference = "T. A. Harris, Rolling Bearing Analysis (Palmgren friction model); Bossmanns & Tu 1999"
    roles = ("spindle.front_bearing", "spindle.rear_bearing")
    parameters = (
        Parameter("front_power", "power", 150.0, 0.0, 2000.0, "front bearing heat at the reference speed"),
        Parameter("rear_power", "power", 130.0, 0.0, 2000.0, "rear bearing heat at the reference speed"),
        _REF,
        Parameter("exponent", "dimensionless", 5.0 / 3.0, 0.5, 3.0, "speed exponent x (Palmgren viscous: 5/3)"),
    )
    uncertain = (
        Uncertain("front_power", 50.0, 450.0, "bearing losses depend on preload, fit and lubricant (grease or "
                  "oil-air); measured losses scatter by a factor of 2-3 about Palmgren's estimate", linear=True),
        Uncertain("rear_power", 40.0, 400.0, "as the front bearing: preload, fit and lubricant", linear=True),
    )

    def loads(self, mm, scenario, p):
        return [
            HeatSource(f"{self.name}.{side}_bearing", role_cells(mm, f"spindle.{side}_bearing"),
                       speed_power_law(scenario, p["reference_speed"], p["exponent"], p[f"{side}_power"]))
            for side in ("front", "rear")
        ]


@register_effect
class SpindleMotor(Effect):
    """Losses of the DC spindle motor on top of the carrier that go into the structure.

        P(n) = P_ref (n / n_ref)^x   (n > 0),

    iron and friction losses of an idling motor grow about linearly with speed (x = 1); the part
    carried off by the motor's fan is not in P_ref. Spread uniformly over the motor body, which
    conducts into the carrier top through the motor flange.
    """

    name = "spindle_motor"
    strength = "power"
    linear = True
    summary = "motor losses into the carrier top, P = P_ref (n/n_ref)^x"
    reference = "seed 000 L4024-4028, L4249-4253 (motor on the carrier, most influential area)"
    roles = ("spindle.motor",)
    parameters = (
        Parameter("power", "power", 60.0, 0.0, 5000.0, "heat into the structure at the reference speed"),
        _REF,
        Parameter("exponent", "dimensionless", 1.0, 0.0, 3.0, "speed exponent x"),
    )
    uncertain = (
        Uncertain("power", 15.0, 240.0, "the share of a motor's losses that reaches the structure depends on its "
                  "fan and flange: a factor of 4 either way", linear=True),
    )

    def loads(self, mm, scenario, p):
        return [HeatSource(self.name, role_cells(mm, "spindle.motor"),
                           speed_power_law(scenario, p["reference_speed"], p["exponent"], p["power"]))]


@register_effect
class SpindleForcedConvection(Effect):
    """Forced convection on the rotating surfaces (test bar, spindle nose), rising with speed.

    For a cylinder rotating in still air Becker's correlation Nu = 0.133 Re^(2/3) Pr^(1/3),
    Re = omega D^2 / nu_air, gives h proportional to n^(2/3):

        h(n) = h_ref (n / n_ref)^x,  x = 2/3,

    added to the natural convection on those faces, air at the room temperature. For a 40 mm bar
    at 9000 rpm Becker gives about 150 W/(m2 K).
    """

    name = "spindle_forced_convection"
    strength = "h_reference"
    linear = False
    summary = "h on rotating surfaces, h = h_ref (n/n_ref)^(2/3) (Becker)"
    reference = "K. M. Becker, Int. J. Heat Mass Transfer 6 (1963) 1053-1062"
    roles = ("spindle.rotating",)
    parameters = (
        Parameter("h_reference", "heat_transfer_coefficient", 150.0, 0.0, 2000.0, "h at the reference speed"),
        _REF,
        Parameter("exponent", "dimensionless", 2.0 / 3.0, 0.0, 2.0, "speed exponent x (Becker: 2/3)"),
    )
    uncertain = (
        Uncertain("h_reference", 50.0, 450.0, "Becker's correlation holds for a smooth cylinder in still air; tool "
                  "holders, flats and the air flow round the spindle nose change h by a factor of 2-3"),
    )

    def loads(self, mm, scenario, p):
        return [Convection(self.name, role_facets(mm, "spindle.rotating"),
                           speed_power_law(scenario, p["reference_speed"], p["exponent"], p["h_reference"]),
                           scenario.ambient_temperature)]


@register_effect
class TestBarContact(Effect):
    """Finite thermal conductance between the spindle nose and the test bar (taper contact).

        Q = G (T_spindle - T_bar)   across the seat,   h_c = G / A_seat,

    instead of the default perfect (bonded) contact: the temperature field is split at the seat
    and the two sides exchange h_c (T_a - T_b) per unit area; the joint stays bonded
    mechanically. Taper contacts have h_c of a few 1000 to a few 10 000 W/(m2 K) depending on
    clamping force and surface finish, i.e. G of some 10 W/K for a 40 mm shank.
    """

    name = "test_bar_contact"
    strength = "conductance"
    linear = False
    summary = "finite conductance G between spindle and test bar (default model: perfect contact)"
    reference = "M. M. Yovanovich, thermal contact resistance (Handbook of Heat Transfer, ch. 4); Bossmanns & Tu 1999"
    roles = ("test_bar.seat", "test_bar.body")
    parameters = (
        Parameter("conductance", "conductance", 20.0, 0.1, 1000.0, "conductance G of the bar's seat in the spindle"),
    )
    uncertain = (
        Uncertain("conductance", 1.0, 200.0, "clamping force, surface finish and a holder between bar and spindle: "
                  "1 to 200 W/K (Yovanovich)"),
    )

    def loads(self, mm, scenario, p):
        facets = role_facets(mm, "test_bar.seat")
        hc = p["conductance"] / mm.facet_area(facets)
        return [ContactConductance(self.name, facets, role_parts(mm, "test_bar.body"), constant(hc))]
