"""``gantry-ram``: a five-axis gantry milling machine with a ram (seed 000, Machine C).

Seed facts (thesis L4067-4111, L4714-4804, L5606-6106): a fixed table; a gantry travelling X
2.5 m, a carriage on its cross-beam travelling Y 1.2 m, a ram travelling Z 0.7 m; a B/C head at
the ram's tip carrying the spindle (3200 rpm maximum); "all axes move the tool"; linear scales on
X, Y, Z and directly mounted encoders on B and C; the C-axis motor inside the ram near T1; the Z
ballscrew with two support bearings, its nut and the Z motor; no temperature control in the
workshop; 12 temperature sensors, 7 FBG strain gauges (three on the ram, one per side, four on the
cross-beam) and four laser triangulation sensors on a test bar (Y, Z and two for the tilt; X not
measured). Dimensions, masses and materials are not given: plausible, not a measured machine.

Chosen dimensions [m] (x along the X travel, y along the cross-beam, z up, floor z = 0; the
spindle axis is x = y = 0, the machine modelled at one pose, mid-travel on X and Y, Z 150 mm
above its lowest: see :func:`axes`):

* bed 3.5 x 3.2 x 0.5 (grey cast iron), fixed table 2.5 x 1.5, 0.2 thick, top at z 0.70;
* two uprights 0.5 (x) x 0.3 (y) from the bed to z 2.70 at y = +-(1.30..1.60), a cross-beam
  0.5 x 0.5 across them (z 2.70-3.20), both behind the ram (x 0.30-0.80), grey cast iron;
* a carriage (saddle) on the beam's front face, 0.6 (x) x 0.8 (y) x 0.8 (z), a frame round the
  ram: front and side slabs guide the ram, a 80 mm channel behind the ram holds the Z screw;
* a hollow square ram, 0.32 x 0.32 with 40 mm walls (steel weldment), z 1.61-3.35 (0.84 m
  below the carriage at the mesh's pose, Z 150 mm: 0.15 m lower and 0.55 m higher over the travel);
* inside the ram's lower end the C-axis bearing (a 60 mm steel slab across the ram's section,
  z 1.55-1.61) and the C-axis torque motor (steel, filling the 0.24 m bore, z 1.61-1.91);
* the B/C fork head 0.32 x 0.32 x 0.30 below it (grey cast iron), the spindle cartridge
  (steel, 0.12 square, nose at z 1.20), a 40 mm square steel test bar 0.25 m long (tip z 0.95);
* the Z ballscrew (steel, 40 mm) in the channel behind the ram from its lower support bearing
  (steel block on the ram's rear face, z 2.20-2.30, T2 "ram rear") to the upper one under the
  Z motor (z 3.25-3.35); the Z motor (steel, 0.24 square, 0.30 tall) on the ram top. The nut
  is not a separate part: it is bolted to the carriage, its heat travels along the screw
  (:func:`axes`).

Castings are solid blocks (ribs unknown), every joint bonded; the linear scales are not meshed
(closed-loop axes: ``linear_scales`` in ``parameters``); the rotary encoders on B and C neither.

Roles: the C-axis motor and bearing (``c_axis.motor``, ``c_axis.bearing``) for the C-axis
drive effect, the Z motor and upper screw bearing (``z_drive.top``); the Z drive's
``feed_drive.z.*`` roles when a scenario moves Z (:func:`axes`).
"""

from __future__ import annotations

from geometries.axes import FeedDrive, LinearAxis
from geometries.base import Box, Machine, Part, Point, Probe, StrainGauge, Surface, common_surfaces, material
from geometries.regions import Facing, InBox, Named, Parts, Union, feed_drive_role

NAME = "gantry-ram"

MAX_SPEED = 3200.0     # rpm: the seed's spindle maximum
C_MAX_SPEED = 3200.0   # rpm: the C axis (the seed's C-axis test turns it at 2500 rpm; no limit stated)

DEFAULT_EFFECTS = ("c_axis_drive", "ambient_convection", "floor")

# The seed's 12 temperature sensors in its own order: T1-T6 on the structure, T7-T12 in the air.
TEMPERATURE_POINTS: tuple[str, ...] = tuple(f"T{i}" for i in range(1, 13))
FBG_GAUGES: tuple[str, ...] = tuple(f"FBG-{i}" for i in range(1, 8))
LASERS: tuple[str, ...] = ("Y", "Z", "A1", "A2")
TILT_SPACING = 0.10   # m between the tilt pair A1 (lower) and A2


def build(bar_length: float = 0.25, gauge_length: float = 0.05, z_bearing_lower: tuple[float, float] = (2.20, 2.30),
          nut_height: float = 2.95, screw_x: tuple[float, float] = (0.18, 0.22)) -> Machine:
    """Build the gantry with a ram. bar_length [m]: test-bar overhang below the spindle nose;
    gauge_length [m]: the FBG gratings' gauge length (packaged surface gratings: 20-100 mm).
    The Z drive's construction (the alternatives of ``validate.studies.gantry_z_variants``):
    z_bearing_lower [m] the lower screw bearing's z extent at the mesh's pose, nut_height [m]
    the nut's fixed height in the carriage, screw_x [m] the screw's faces across x (the ram's
    rear face is at 0.16: from 0.16 the screw touches it along its length)."""
    iron, steel = material("grey_cast_iron"), material("steel")
    bed_top, table_top = 0.50, 0.70
    nose = 1.20
    tip = nose - bar_length
    head_bot, cbear_bot, ram_bot, motor_top, ram_top = 1.25, 1.55, 1.61, 1.91, 3.35
    ro, ri = 0.16, 0.12                  # ram outer and bore half sides
    car_bot, car_top, car_x0, car_x1, car_y = 2.45, 3.25, -0.30, 0.30, 0.40
    chan = 0.24                          # the screw channel behind the ram: x 0.16-0.24
    beam_x0, beam_x1, beam_bot, beam_top = 0.30, 0.80, 2.70, 3.20
    up_y0, up_y1 = 1.30, 1.60
    zb_lo, zb_hi = z_bearing_lower       # lower Z-screw bearing
    hb = 0.02

    ram = (Box((-ro, -ro, ram_bot), (-ri, ro, ram_top)), Box((ri, -ro, ram_bot), (ro, ro, ram_top)),
           Box((-ri, -ro, ram_bot), (ri, -ri, ram_top)), Box((-ri, ri, ram_bot), (ri, ro, ram_top)))
    carriage = (Box((car_x0, -car_y, car_bot), (-ro, car_y, car_top)),
                Box((chan, -car_y, car_bot), (car_x1, car_y, car_top)),
                Box((-ro, -car_y, car_bot), (chan, -ro, car_top)),
                Box((-ro, ro, car_bot), (chan, car_y, car_top)))
    parts = [
        Part("bed", iron, (Box((-1.75, -1.60, 0.0), (1.75, 1.60, bed_top)),), "workpiece"),
        Part("table", iron, (Box((-1.25, -0.75, bed_top), (1.25, 0.75, table_top)),), "workpiece"),
        Part("upright_left", iron, (Box((beam_x0, -up_y1, bed_top), (beam_x1, -up_y0, beam_bot)),), "tool"),
        Part("upright_right", iron, (Box((beam_x0, up_y0, bed_top), (beam_x1, up_y1, beam_bot)),), "tool"),
        Part("cross_beam", iron, (Box((beam_x0, -up_y1, beam_bot), (beam_x1, up_y1, beam_top)),), "tool"),
        Part("carriage", iron, carriage, "tool"),
        Part("ram", steel, ram, "tool"),
        Part("c_motor", steel, (Box((-ri, -ri, ram_bot), (ri, ri, motor_top)),), "tool"),
        Part("c_bearing", steel, (Box((-ro, -ro, cbear_bot), (ro, ro, ram_bot)),), "tool"),
        Part("head", iron, (Box((-ro, -ro, head_bot), (ro, ro, cbear_bot)),), "tool"),
        Part("spindle", steel, (Box((-0.06, -0.06, nose), (0.06, 0.06, cbear_bot - 0.05)),), "tool"),
        Part("test_bar", steel, (Box((-hb, -hb, tip), (hb, hb, nose)),), "tool"),
        Part("z_bearing_lower", steel, (Box((ro, -0.06, zb_lo), (chan, 0.06, zb_hi)),), "tool"),
        Part("z_screw", steel, (Box((screw_x[0], -0.02, zb_hi), (screw_x[1], 0.02, ram_top - 0.10)),), "tool"),
        Part("z_bearing_upper", steel, (Box((ro, -0.06, ram_top - 0.10), (chan, 0.06, ram_top)),), "tool"),
        Part("z_motor", steel, (Box((-ri, -ri, ram_top), (ri, ri, ram_top + 0.30)),), "tool"),
    ]
    surfaces = common_surfaces(parts, nose) + [
        Surface("upright_left_outer", ("upright_left",),
                within=Box((beam_x0, -up_y1 - 1e-4, bed_top), (beam_x1, -up_y1 + 1e-4, beam_bot))),
    ]
    e = 1e-3  # sensors and gratings sit 1 mm inside the face they are glued to
    structural = [
        Point("T1", (-ro + e, 0.0, 1.88), "ram"),                       # ram front face beside the C motor
        Point("T2", (chan - e, 0.0, 0.5 * (zb_lo + zb_hi)), "z_bearing_lower"),  # lower Z-screw bearing, ram rear
        Point("T3", (0.0, ro - e, 2.25), "ram"),                        # gradient up from the ram's end
        Point("T4", (0.0, ro - e, 2.38), "ram"),
        Point("T5", (-ri + e, 0.0, ram_top + 0.15), "z_motor"),         # Z motor surface, front and side
        Point("T6", (0.0, ri - e, ram_top + 0.15), "z_motor"),
    ]
    air = [
        Point("T7", (-1.80, 0.0, 0.25), "air"),                         # beside the bed
        Point("T8", (-1.30, 0.0, 0.80), "air"),                         # over the table's end
        Point("T9", (-0.25, 0.0, 1.80), "air"),                         # in front of the ram
        Point("T10", (0.55, 0.0, 2.60), "air"),                         # under the cross-beam
        Point("T11", (0.55, -1.65, 1.60), "air"),                       # beside the left upright
        Point("T12", (0.55, 0.0, 3.30), "air"),                         # over the cross-beam
    ]
    gz = (0.0, 0.0, 1.0)
    gauges = [
        StrainGauge("FBG-1", (-ro + e, 0.0, 2.10), gz, gauge_length, "ram"),    # ram front
        StrainGauge("FBG-2", (0.0, -ro + e, 2.10), gz, gauge_length, "ram"),    # ram left (-y)
        StrainGauge("FBG-3", (0.0, ro - e, 2.25), gz, gauge_length, "ram"),     # ram right (+y)
        StrainGauge("FBG-4", (beam_x1 - e, -0.80, 2.95), (0.0, 1.0, 0.0), gauge_length, "cross_beam"),  # beam rear
        StrainGauge("FBG-5", (beam_x1 - e, 0.80, 2.95), (0.0, 1.0, 0.0), gauge_length, "cross_beam"),
        StrainGauge("FBG-6", (0.55, -0.80, beam_top - e), (0.0, 1.0, 0.0), gauge_length, "cross_beam"),  # beam top
        StrainGauge("FBG-7", (0.55, 0.80, beam_top - e), (0.0, 1.0, 0.0), gauge_length, "cross_beam"),
    ]
    # laser triangulation on the test bar, sensors on the table: Y at 30 mm above the tip, Z on the
    # tip, the tilt pair A1/A2 along +y 100 mm apart higher up (X not measured, as the seed)
    z_y, z_a1 = tip + 0.03, tip + 0.10
    nest = [
        Point("tool", (0.0, 0.0, tip), "test_bar"),
        Point("workpiece", (0.0, 0.0, table_top), "table"),
        Point("Y", (0.0, -hb, z_y), "test_bar"),
        Point("Z", (0.0, 0.0, tip), "test_bar"),
        Point("A1", (0.0, -hb, z_a1), "test_bar"),
        Point("A2", (0.0, -hb, z_a1 + TILT_SPACING), "test_bar"),
    ]
    dirs = {"Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0), "A1": (0.0, 1.0, 0.0), "A2": (0.0, 1.0, 0.0)}
    lasers = [Probe(n, n, dirs[n], "workpiece") for n in LASERS]
    return Machine(
        name=NAME,
        parts=parts,
        surfaces=surfaces,
        points=structural + air + nest,
        probes=[],
        lasers=lasers,
        strain_gauges=gauges,
        tool_point="tool",
        workpiece_point="workpiece",
        sensor_sites=[p.name for p in structural],
        air_sites=[p.name for p in air],
        resolutions={"coarse": 0.25, "default": 0.15, "fine": 0.10},
        description=("5-axis gantry milling machine with a ram (seed Machine C): X 2.5 m (gantry), Y 1.2 m, "
                     "Z 0.7 m (ram), B/C head, 3200 rpm, C-axis motor in the ram, Z motor on the ram top"),
        parameters={"bar_length": bar_length, "gauge_length": gauge_length, "travel_x": 2.5, "travel_y": 1.2,
                    "travel_z": 0.7, "linear_scales": 1.0, "c_axis_max_speed": C_MAX_SPEED,
                    "tilt_spacing": TILT_SPACING},
        roles=roles(ram_top),
        default_effects=DEFAULT_EFFECTS,
        max_speed=MAX_SPEED,
        axes=axes(nut_height=nut_height),
        effect_defaults=Z_DRIVE_DEFAULTS,
    )


def roles(ram_top: float) -> dict:
    """The machine contract of the gantry (see :data:`geometries.regions.ROLES`): the C-axis
    motor and bearing in the ram's lower end, the Z motor and upper screw bearing at its top, the
    skin (front: -x, the operator's side; rear: +x), the bed's foot, the left upright's outer face
    (the electrical cabinet's side)."""
    skin = Named("skin")
    return {
        "c_axis.motor": Parts(("c_motor",)),
        "c_axis.bearing": Parts(("c_bearing",)),
        "spindle.rotating": Union((Named("test_bar_skin"), Named("spindle_nose"))),
        "test_bar.seat": Named("test_bar_seat"),
        "test_bar.body": Parts(("test_bar",)),
        "structure.skin": skin,
        "structure.front": Facing(skin, "-x"),
        "structure.open_front": Facing(skin, "-x"),   # no way covers between the door and the front
        "structure.rear": Facing(skin, "+x"),
        "floor.contact": Named("floor_contact"),
        "cabinet.face": Named("upright_left_outer"),
        "z_drive.top": Parts(("z_motor", "z_bearing_upper")),
    }


# The Z drive's own powers (twin.effects.feed gives every family's power at the reference feed
# 20 mm/s, proportional to the feed): the ram's drive runs 58 times faster (70 m/min) than the
# C-frame's seed-003 Y axis, with a larger screw, so its powers at 20 mm/s are set here; at
# 70 m/min (x 58.3) they are about nut 367 W, bearings 198 W, motor 198 W, guideways 35 W while
# the ram moves (README "The linear axes"). The motor's inertia losses at 1 m/s2: the 1.19 t
# that moves with the ram on a 20 mm lead (eta 0.9) and rotor + screw 0.013 kg m2 need
# 8.3 N m, (8.3 / 2 N m/A)^2 x 1.05 ohm = 18 W (tests/test_axis_drives.py). Plausible, not measured.
Z_DRIVE_DEFAULTS = {
    "feed_nut_z": {"power": 6.3, "screw_share": 0.6},
    "feed_bearings_z": {"power": 3.4, "front_share": 0.75},
    "feed_motor_z": {"power": 3.4, "holding_power": 0.0, "inertia_power": 18.0},
    "feed_guideways_z": {"power": 0.6, "rail_share": 0.7, "carriage_offset": 0.30},
}

Z_DRIVE_EFFECTS = ("feed_nut_z", "feed_bearings_z", "feed_motor_z", "feed_guideways_z")


def axes(ro: float = 0.16, chan: float = 0.24, car_x1: float = 0.30, car_y: float = 0.40,
         car_bot: float = 2.45, car_top: float = 3.25, ram_bot: float = 1.61, ram_top: float = 3.35,
         nut_height: float = 2.95) -> list[LinearAxis]:
    """X 2.5 m (the gantry), Y 1.2 m (the carriage on the cross-beam), Z 0.7 m (the ram), all
    closed loop (seed 000: linear scales on X, Y, Z; their mountings are not modelled, so the
    interferometer refuses them); the mesh at mid-travel on X and Y (X 1250, Y 600 mm) and at
    Z 150 mm (the test bar's tip 0.25 m above the table; at Z = 0 it is 0.10 m above it, mid-travel
    would put it into the table). Commanded X = p puts the uprights' centre at x = 0.55 +
    (p - 1.25) [m], Y = p the carriage's centre at y = p - 0.60, Z = p the ram (and the tool)
    p - 0.15 above the mesh's pose.

    Only Z has its ball-screw drive modelled (the seed's Z-axis test; X and Y carry no feed heat).
    The screw hangs on the ram (``screw_on_body``): its lower, floating bearing on the ram's rear
    (``z_bearing_lower``, T2 "ram rear"), its fixed bearing under the Z motor on the ram's top
    (``z_bearing_upper``), the rails on the ram's two sides; the nut and the guide blocks are
    bolted to the carriage, the nut in the carriage's rear wall at z 2.95 m (0.1 m above the
    carriage's middle), the blocks 0.30 m above and below it (``carriage_offset``). So the nut's
    heat enters the screw at z 2.95 - (Z - 0.15) in the mesh (2.40-3.10 m over the travel) and the
    blocks' heat the ram's sides 0.30 m above and below that. Plausible, not measured."""
    tool_side = ("ram", "c_motor", "c_bearing", "head", "spindle", "test_bar", "z_bearing_lower", "z_screw",
                 "z_bearing_upper", "z_motor")
    nut = nut_height
    sides = [(-car_y, -ro), (ro, car_y)]      # the carriage's side walls, beside the ram's sides
    z_drive = FeedDrive(
        roles={feed_drive_role("z", "screw"): Parts(("z_screw",)),
               feed_drive_role("z", "front_bearing"): Parts(("z_bearing_upper",)),
               feed_drive_role("z", "rear_bearing"): Parts(("z_bearing_lower",)),
               feed_drive_role("z", "motor"): Parts(("z_motor",)),
               feed_drive_role("z", "nut_body"): InBox(Parts(("carriage",)), Box((chan, -0.07, car_bot), (car_x1, 0.07, car_top))),
               feed_drive_role("z", "guideways"): Union(tuple(
                   InBox(Parts(("ram",)), Box((-ro, max(lo, -ro), ram_bot), (ro, min(hi, ro), ram_top)))
                   for lo, hi in ((-ro, -ro + 0.04), (ro - 0.04, ro)))),
               feed_drive_role("z", "carriages"): Union(tuple(
                   InBox(Parts(("carriage",)), Box((-ro, lo, car_bot), (chan, hi, car_top))) for lo, hi in sides))},
        screw_axis=(0.20, 0.0), fixed_end=ram_top - 0.10, lead=0.020, nut_offset=(0.07, 0.0),
        effects=Z_DRIVE_EFFECTS)
    return [LinearAxis("X", "x", (0.0, 2.5), "closed", ("upright_left", "upright_right", "cross_beam", "carriage")
                       + tool_side, 0.55 - 1.25, 1.25),
            LinearAxis("Y", "y", (0.0, 1.2), "closed", ("carriage",) + tool_side, -0.60, 0.60),
            LinearAxis("Z", "z", (0.0, 0.7), "closed", tool_side, nut, 0.15, z_drive, screw_on_body=True)]
