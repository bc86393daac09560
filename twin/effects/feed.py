"""Feed-drive heat of a ball-screw axis: nut, support bearings, servo motor, guideways, and the
air gap that keeps the screw apart from the structure between its bearings.

Each family is registered once per linear axis, ``<family>_<axis>`` (``feed_nut_x``,
``feed_nut_y``, ``feed_nut_z``, ...): it acts on that axis's drive (the roles
``feed_drive.<axis>.*``, so it is offered only on machines that model that drive) with the motion
the scenario commands (standing still when it commands none). One instance per axis keeps each
drive's heat a separate candidate for the diagnosis and a separate row in ``twin list effects``. Friction powers are given at
the reference feed v_ref = 20 mm/s (seed 003's Exp I) and scale with the feed |v(t)|: Coulomb
friction (preload torque, rolling resistance) dominates at the low screw speeds of a feed drive
(120 rpm at 20 mm/s with a 10 mm lead), P = M omega = F |v| with M and F constant. Powers are
plausible for a 45 mm screw with a preloaded double nut, not measured on a machine.
"""

from __future__ import annotations

from twin.effects.base import ContactConductance, Effect, HeatSource, Parameter, Uncertain, constant, register_effect
from twin.effects.moving import (REFERENCE_ACCELERATION, REFERENCE_FEED, acceleration_signal, motion_of,
                                speed_signal, travelling_sources)
from geometries.regions import DRIVEN_AXES, feed_drive_role
from twin.fem.regions import role_cells, role_facets, role_parts

_FEED = "at the reference feed 20 mm/s, proportional to the feed"


def _share(name: str, default: float, doc: str) -> Parameter:
    return Parameter(name, "dimensionless", default, 0.0, 1.0, doc)


def _feed_power(default: float, upper: float, what: str, plausible: tuple[float, float, str]):
    """(the ``power`` parameter at the reference feed, its :class:`Uncertain` range): W."""
    lo, hi, why = plausible
    return (Parameter("power", "power", default, 0.0, upper, f"{what} {_FEED}"),
            Uncertain("power", lo, hi, why, linear=True))


class _AxisEffect(Effect):
    """Shared: the effect's ``axis`` ("X", "Y", "Z"; set per registered instance) and its roles."""

    axis = ""

    def role(self, what: str) -> str:
        """This axis's feed-drive role ``what`` (``feed_drive.<axis>.<what>``)."""
        return feed_drive_role(self.axis, what)

    def axis_and_motion(self, mm, scenario):
        axis = mm.machine.axis(self.axis)
        return axis, motion_of(scenario, axis)


class _FeedEffect(_AxisEffect):
    """Shared: a feed-proportional power split in two."""

    strength = "power"
    linear = True

    def split(self, mm, scenario, p, share: str):
        """(axis, motion, a, b): P_ref / v_ref [W s/m] times the fraction ``p[share]`` and the rest."""
        axis, motion = self.axis_and_motion(mm, scenario)
        scale = p["power"] / REFERENCE_FEED
        return axis, motion, p[share] * scale, (1 - p[share]) * scale


class FeedNut(_FeedEffect):
    """Friction heat of the ball nut, shared between the screw and the nut housing.

        P(t) = P_ref |v(t)| / v_ref  (Coulomb: preload torque M_p, P = 2 pi M_p |v| / lead),

    a fraction ``screw_share`` into the screw *where the nut is* (a path basis along the screw,
    :mod:`twin.effects.moving`) and the rest into the nut housing on the moving body (fixed to it).
    """

    family = "feed_nut"
    summary = "ball-nut friction P = P_ref |v|/v_ref, travelling with the nut along the screw"
    reference = ("Xu, Liu, Choi, Int. J. Mach. Tools Manuf. 49 (2009) 1126 (ball-screw nut heat Q = 2 pi n M / 60); "
                 "Mayr et al., CIRP Annals 61/2 (2012) 771, sec. 3.2")
    role_keys = ("screw", "nut_body")
    _power, _range = _feed_power(14.0, 500.0, "nut friction heat", (3.0, 40.0, "nut preload and lubrication"))
    parameters = (_power, _share("screw_share", 0.6, "part of the nut heat that enters the screw (the rest: the "
                                                    "nut housing)"))
    uncertain = (_range,)

    def loads(self, mm, scenario, p):
        axis, motion, screw, housing = self.split(mm, scenario, p, "screw_share")
        return (travelling_sources(self.name, mm, self.role("screw"), axis, motion, scenario, screw, "distance")
                + [HeatSource(f"{self.name}.housing", role_cells(mm, self.role("nut_body")),
                              speed_signal(scenario, motion, housing))])


class FeedBearings(_FeedEffect):
    """Friction heat of the screw's support bearings (angular-contact pairs, preloaded).

        P(t) = P_ref |v(t)| / v_ref   (Palmgren's load term M_1 = f_1 F dm dominates at low speed),

    a fraction ``front_share`` in the fixed (front) bearing, the rest in the floating one.
    """

    family = "feed_bearings"
    summary = "screw support-bearing friction P = P_ref |v|/v_ref, front and rear"
    reference = "T. A. Harris, Rolling Bearing Analysis (Palmgren M_1 = f_1 F_beta d_m); Mayr et al. 2012, sec. 3.2"
    role_keys = ("front_bearing", "rear_bearing")
    _power, _range = _feed_power(2.0, 200.0, "both bearings' friction heat", (0.5, 10.0, "bearing preload and grease"))
    parameters = (_power, _share("front_share", 0.6, "part in the fixed (front) bearing"))
    uncertain = (_range,)

    def loads(self, mm, scenario, p):
        _, motion, front, rear = self.split(mm, scenario, p, "front_share")
        return [HeatSource(f"{self.name}.{side}", role_cells(mm, self.role(f"{side}_bearing")),
                           speed_signal(scenario, motion, power)) for side, power in (("front", front), ("rear", rear))]


class FeedMotor(_FeedEffect):
    """Losses of the servo motor that enter the structure through its flange.

        P(t) = P_hold + P_ref |v(t)| / v_ref + P_a (a(t) / a_ref)^2,

    P_hold the copper losses of the holding (standstill) current while the drive is enabled,
    P_ref the extra losses at the reference feed (copper losses of the friction torque, iron
    losses growing with speed), P_a the copper losses of the inertia torque at the reference
    acceleration a_ref = 1 m/s2: copper losses are R I^2 = R (M / k_t)^2 with the torque
    M = (m l / (2 pi eta) + J 2 pi / l) a that accelerates the moving mass m (lead l, efficiency
    eta) and the rotor and screw (J). The cross term of the inertia torque with the friction and
    holding torques is left out (it changes sign between accelerating and braking). Every term
    is a step average of a scalar signal of the schedule (mean |v|, mean a^2: exact), so the
    loads stay linear. The fan's share is not in P.
    """

    family = "feed_motor"
    summary = "servo motor losses into its flange, P = P_hold + P_ref |v|/v_ref + P_a (a/a_ref)^2"
    reference = "Mayr et al., CIRP Annals 61/2 (2012) 771, sec. 3.2 (feed drives); Y-motor sensor T1 of seed 003"
    role_keys = ("motor",)
    _power, _range = _feed_power(50.0, 500.0, "motor losses into the structure, above P_hold,",
                                 (10.0, 150.0, "motor size and how much heat its flange passes"))
    parameters = (_power, Parameter("holding_power", "power", 5.0, 0.0, 1000.0,
                                    "losses at standstill with the drive enabled (hundreds of W for a vertical "
                                    "axis without counterbalance)"),
                  Parameter("inertia_power", "power", 12.0, 0.0, 2000.0,
                            "copper losses of the inertia torque at 1 m/s2 (the registry default 12 W: the C-frame's 0.6 t "
                            "saddle and table on a 10 mm lead, eta 0.9, rotor and screw 0.0044 kg m2, "
                            "k_t 1.2 N m/A, R 1.2 ohm)"))
    uncertain = (_range,)

    def loads(self, mm, scenario, p):
        _, motion = self.axis_and_motion(mm, scenario)
        cells = role_cells(mm, self.role("motor"))
        return [HeatSource(f"{self.name}.hold", cells, constant(p["holding_power"])),
                HeatSource(f"{self.name}.feed", cells, speed_signal(scenario, motion, p["power"] / REFERENCE_FEED)),
                HeatSource(f"{self.name}.inertia", cells,
                           acceleration_signal(scenario, motion, p["inertia_power"] / REFERENCE_ACCELERATION ** 2))]


class FeedGuideways(_FeedEffect):
    """Friction heat of the linear guideways (rolling carriages on two rails).

        P(t) = mu F_N |v(t)| = P_ref |v(t)| / v_ref,

    a fraction ``rail_share`` into the rails under the two carriages (front and rear of the moving
    body, ``carriage_offset`` ahead of and behind the nut; a path basis along the rails), the rest
    into the carriages on the moving body.
    """

    family = "feed_guideways"
    summary = "guideway friction P = P_ref |v|/v_ref, into the rails where the carriages are and the carriages"
    reference = "Mayr et al., CIRP Annals 61/2 (2012) 771, sec. 3.2; rolling guide friction mu ~ 0.002-0.005"
    role_keys = ("guideways", "carriages")
    _power, _range = _feed_power(10.0, 200.0, "guideway friction heat", (2.0, 30.0, "carriage preload and lubrication"))
    parameters = (_power, _share("rail_share", 0.7, "part that enters the rails (the rest: the carriages)"),
                  Parameter("carriage_offset", "length", 0.25, 0.0, 2.0, "carriages' distance ahead of and behind the nut"))
    uncertain = (_range,)

    def loads(self, mm, scenario, p):
        axis, motion, rails, carriages = self.split(mm, scenario, p, "rail_share")
        off = p["carriage_offset"]
        return (travelling_sources(self.name, mm, self.role("guideways"), axis, motion, scenario, rails,
                                   "distance", offsets=(-off, off))
                + [HeatSource(f"{self.name}.carriages", role_cells(mm, self.role("carriages")),
                              speed_signal(scenario, motion, carriages))])


class FeedScrewGap(_AxisEffect):
    """The air gap between the screw and the structure between its bearings.

        q = h_gap (T_screw - T_structure)   on the screw's faces towards the bed and the moving body,

    h_gap the conductance of the air gap per unit area. In still air it is conduction across the
    gap plus linearised radiation between the two faces, k_air / delta + 4 sigma eps_eff T^3 with
    eps_eff = 1 / (1/eps_1 + 1/eps_2 - 1): 3.9-8.3 W/(m2 K) for a 10 mm gap (a ground screw,
    eps 0.24, in a painted trough, 0.9, to black faces), 2.6-10.9 over 5-20 mm. A turning screw
    stirs the gap's air; as a rotating cylinder (Becker, Nu = 0.133 Re^(2/3) Pr^(1/3),
    Re = omega D^2 / nu) the 40 mm screw gives about 9 W/(m2 K) at 120 rpm (20 mm/s on a 10 mm
    lead) and 38 at 1000 rpm. The constant h_gap does not follow the speed: the default 10 is the
    still gap's top and the stirred one at the seed's 20 mm/s (plausible, and held by the seed 003
    and duty-cycle bands, not measured); the range 3-30 spans a wide, bare gap in still air to a
    screw turning at about 700 rpm. Without the gap the screw would be bonded to the bed along
    its whole length; with it the screw touches the structure only at its bearings. The joint
    stays bonded mechanically (:class:`twin.effects.base.ContactConductance`).
    """

    family = "feed_screw_gap"
    strength = "conductance"
    linear = False
    summary = "air gap h_gap between the screw and the structure between the bearings"
    reference = "VDI Heat Atlas (2010) E2/K1 (gas gap conduction, radiation between surfaces)"
    role_keys = ("screw_gap", "structure_side")
    parameters = (Parameter("conductance", "heat_transfer_coefficient", 10.0, 0.1, 1000.0, "gap conductance per area"),)
    uncertain = (Uncertain("conductance", 3.0, 30.0, "the gap's width (5-20 mm of air), the surfaces' "
                                                     "emissivity (conduction k_air / gap plus radiation) and the "
                                                     "screw's speed (its rotation stirs the gap)"),)

    def loads(self, mm, scenario, p):
        h = p["conductance"]
        return [ContactConductance(self.name, role_facets(mm, self.role("screw_gap")),
                                   role_parts(mm, self.role("structure_side")), constant(h))]


# Defaults that differ between the axes (the rest are the family's): a Z drive holds the carrier
# against gravity, and z_axis_holding (twin.effects.drives) already carries those constant
# losses, so feed_motor_z's holding power is 0 (z_axis_holding joins the Z drive's effects,
# geometries.cframe_vmc); carriages sit closer to the nut on the shorter X table and Z carrier.
AXIS_DEFAULTS = {
    ("feed_motor", "Z"): {"holding_power": 0.0},
    ("feed_guideways", "X"): {"carriage_offset": 0.05},
    ("feed_guideways", "Z"): {"carriage_offset": 0.12},
}


def _register_per_axis(cls) -> None:
    """Register one instance of ``cls`` per axis as ``<family>_<axis>``, its roles this axis's."""
    from dataclasses import replace
    for a in DRIVEN_AXES:
        axis = a.upper()
        changed = AXIS_DEFAULTS.get((cls.family, axis), {})
        params = tuple(replace(q, default=changed[q.name]) if q.name in changed else q for q in cls.parameters)
        register_effect(type(f"{cls.__name__}{axis}", (cls,), {
            "name": f"{cls.family}_{a}", "axis": axis, "parameters": params,
            "roles": tuple(feed_drive_role(a, k) for k in cls.role_keys),
            "summary": f"{axis} axis: {cls.summary}", "__doc__": f"{axis} axis. {cls.__doc__}",
            "__module__": cls.__module__}))


for _cls in (FeedNut, FeedBearings, FeedMotor, FeedGuideways, FeedScrewGap):
    _register_per_axis(_cls)
