"""``cframe-vmc``: a small three-axis C-frame vertical machining centre (seed 000, Machine A).

Seed facts (thesis L4014-4038): table moving X 500 mm and Y 400 mm on a saddle over the bed, a
column at the rear, a spindle carrier sliding 330 mm in Z on the column face, a DC spindle motor
on top of the carrier, 9000 rpm maximum. The castings' dimensions are not given in the seeds:
the proportions below are those of a typical small VMC (about 5 t), chosen so that the travels fit.
Castings are modelled as solid grey cast iron blocks by default (ribbed castings' effective
properties are not known; :func:`build` can make the column and carrier hollow); the spindle
cartridge, its bearing zones and the test mandrel are steel.

Axes: x along the X travel, y towards the column (rear), z up, floor at z = 0; the spindle axis
is the line x = y = 0. The carrier is modelled at one Z position (the test position).
"""

from __future__ import annotations

from geometries.axes import FeedDrive, LinearAxis
from geometries.base import (PROBE_HEIGHTS, Box, CameraPose, Finish, Machine, Part, Point, Surface, common_surfaces,
                             material, test_bar_nest)
from geometries.finishes import GROUND_STEEL, MACHINE_PAINT, MASKING_TAPE
from geometries.regions import Band, Facing, InBox, Named, Parts, Union, feed_drive_role

NAME = "cframe-vmc"

# The effects a model of this machine has unless the user says otherwise: the seeds' spindle tests'
# five, plus the workshop's two that carry the ETVE tests' magnitudes (a room swing growing with
# height; the outside air through a scenario's opened door). Both are zero while the room air is
# constant, so the spindle calibration is untouched by them (README "The workshop: ETVE tests").
MAX_SPEED = 9000.0  # rpm, the seeds' spindle maximum

SPINDLE_EFFECTS = ("spindle_bearings", "spindle_motor", "ambient_convection", "spindle_forced_convection", "floor")
DEFAULT_EFFECTS = SPINDLE_EFFECTS + ("stratified_swing", "door_stream")


# Bearing zones get at least two cells in height: their heat peaks at mid-height, and a single
# cell (coarse and default) puts the spindle-boss sensor 0.8 K below the fine mesh; two cells
# bring default within 0.06 K of fine for 3 % more nodes (a z-only refinement).
_BEARING = (1.0, 1.0, 0.5)


def build(bar_length: float = 0.27, bar_width: float = 0.04, throat: float = 0.45,
          column_wall: float | None = None, column_ribs: bool = False, carrier_wall: float | None = None) -> Machine:
    """Build the C-frame VMC.

    bar_length [m]: test-bar overhang below the spindle nose; bar_width [m]: square mandrel side;
    throat [m]: distance from the spindle axis to the column face; column_wall, carrier_wall [m]:
    make the column (with ``column_ribs`` a web and two diaphragms inside) or the carrier a box
    casting with walls that thick round closed cores (:func:`column_cores`, :func:`carrier_cores`;
    default None: solid blocks, on which the calibrations stand; README "The workshop" gives what
    hollow castings do to them).

    The test bar is meshed three times finer than the rest (``refine=1/3``): it is a fin whose
    length 1/m = sqrt(k A / (h P)) is about 5.5 cm while it rotates (h = 150 W/(m2 K)), one
    default cell, and its temperature is what the Z probe reads (thesis: the test-bar spots rank
    first for Z). Plain 6 cm cells get its base conductance 4 % wrong, 2 cm cells within 1 %
    (``tests/test_physics_heat.py``). The bearing zones are split in height (``_BEARING``).
    """
    iron, steel = material("grey_cast_iron"), material("steel")
    nose = 0.95                    # spindle nose height [m]
    tip = nose - bar_length        # tool reference point height [m]
    col_y0, col_y1 = throat, throat + 0.45
    col_top = 1.90                 # column top [m]; the Z motor and brake sit in its top 0.2 m
    hb = bar_width / 2

    parts = [
        Part("bed", iron, (Box((-0.60, -0.55, 0.0), (0.60, col_y1, 0.35)),), "workpiece"),
        Part("saddle", iron, (Box((-0.35, -0.35, 0.35), (0.35, 0.25, 0.47)),), "workpiece"),
        Part("table", iron, (Box((-0.50, -0.25, 0.47), (0.50, 0.15, 0.55)),), "workpiece"),
        Part("column", iron, (Box((-0.25, col_y0, 0.35), (0.25, col_y1, col_top)),), "tool",
             voids=column_cores(col_y0, col_y1, col_top, column_wall, column_ribs)),
        Part("carrier", iron, (Box((-0.18, -0.12, 1.10), (0.18, col_y0, 1.55)),), "tool",
             voids=carrier_cores(col_y0, carrier_wall)),
        Part("spindle", steel, (Box((-0.075, -0.075, nose), (0.075, 0.075, 1.45)),), "tool"),
        Part("front_bearing", steel, (Box((-0.075, -0.075, 0.99), (0.075, 0.075, 1.05)),), "tool", refine=_BEARING),
        Part("rear_bearing", steel, (Box((-0.075, -0.075, 1.35), (0.075, 0.075, 1.41)),), "tool", refine=_BEARING),
        Part("motor", steel, (Box((-0.11, -0.11, 1.55), (0.11, 0.11, 1.80)),), "tool"),
        Part("test_bar", steel, (Box((-hb, -hb, tip), (hb, hb, nose)),), "tool", refine=1 / 3),
    ]
    surfaces = common_surfaces(parts, nose) + [
        Surface("motor_flange", ("motor",), interface_with=("carrier", "spindle")),
        Surface("front_bearing_seat", ("front_bearing",), interface_with=("spindle",)),
        Surface("rear_bearing_seat", ("rear_bearing",), interface_with=("spindle",)),
        Surface("column_face", ("column",), within=Box((-1, col_y0 - 1e-4, 0), (1, col_y0 + 1e-4, 3))),
        Surface("carrier_top", ("carrier",), within=Box((-1, -1, 1.55 - 1e-4), (1, 1, 1.55 + 1e-4))),
        Surface("column_side_left", ("column",), within=Box((-0.25 - 1e-4, col_y0, 0.35), (-0.25 + 1e-4, col_y1, col_top))),
        Surface("spindle_jacket", ("spindle", "front_bearing", "rear_bearing"), interface_with=("carrier",)),
    ]
    e = 1e-3  # sensors sit 1 mm inside the surface they are glued to
    sensors = [
        Point("motor", (0.0, -0.11 + e, 1.70), "motor"),
        Point("carrier_top", (0.12, 0.20, 1.55 - e), "carrier"),
        Point("carrier_front", (0.0, -0.12 + e, 1.30), "carrier"),
        Point("carrier_side", (-0.18 + e, 0.10, 1.30), "carrier"),
        Point("carrier_rear", (0.0, col_y0 - 0.05, 1.55 - e), "carrier"),
        Point("spindle_boss", (0.0, -0.075 + e, 1.02), "spindle"),
        Point("test_bar", (hb - e, 0.0, nose - 0.05), "test_bar"),
        Point("column_front_top", (0.20, col_y0 + e, 1.80), "column"),
        Point("column_front_bottom", (0.20, col_y0 + e, 0.50), "column"),
        Point("column_rear_top", (0.0, col_y1 - e, 1.80), "column"),
        Point("column_rear_bottom", (0.0, col_y1 - e, 0.50), "column"),
        Point("column_side", (-0.25 + e, col_y0 + 0.2, 1.20), "column"),
        Point("bed_front", (0.0, -0.55 + e, 0.20), "bed"),
        Point("bed_rear", (0.40, col_y1 - e, 0.20), "bed"),
        Point("saddle", (0.35 - e, 0.0, 0.41), "saddle"),
        Point("table", (0.30, -0.10, 0.55 - e), "table"),
    ]
    nest, probes = test_bar_nest(tip, hb, 0.55)
    points = sensors + nest
    return Machine(
        name=NAME,
        parts=parts,
        surfaces=surfaces,
        points=points,
        probes=probes,
        tool_point="tool",
        workpiece_point="workpiece",
        sensor_sites=[p.name for p in sensors],
        resolutions={"coarse": 0.10, "default": 0.06, "fine": 0.04},
        description="small 3-axis C-frame vertical machining centre (seed Machine A): X 500, Y 400, Z 330 mm, 9000 rpm",
        parameters={"bar_length": bar_length, "bar_width": bar_width, "throat": throat, "probe_spacing": PROBE_HEIGHTS[1] - PROBE_HEIGHTS[0]},
        roles=roles(col_top, col_y0),
        default_effects=DEFAULT_EFFECTS,
        max_speed=MAX_SPEED,
        camera_poses=camera_poses(nose, tip),
        finishes=finishes(nose, hb),
        axes=axes(col_y0),
    )


def column_cores(y0: float, y1: float, top: float, wall: float | None, ribs: bool) -> tuple[Box, ...]:
    """The closed hollows of the column (y0 to y1 front to rear, z 0.35 to ``top`` [m]): none
    (``wall`` None: a solid block), or one core inside four walls ``wall`` thick, closed below by
    the bed and above by a solid 0.2 m head (the Z motor and brake); with ``ribs`` a web at x = 0
    joining the front and rear walls and two horizontal diaphragms (at a third and two thirds of
    the height) divide it into six."""
    if wall is None:
        return ()
    x0, x1, ya, yb, za, zb = -0.25 + wall, 0.25 - wall, y0 + wall, y1 - wall, 0.35, top - 0.2
    if not ribs:
        return (Box((x0, ya, za), (x1, yb, zb)),)
    h = (zb - za - 2 * wall) / 3
    xs = ((x0, -wall / 2), (wall / 2, x1))
    zs = [(za + i * (h + wall), za + i * (h + wall) + h) for i in range(3)]
    return tuple(Box((a, ya, lo), (b, yb, hi)) for a, b in xs for lo, hi in zs)


def carrier_cores(y1: float, wall: float | None) -> tuple[Box, ...]:
    """The carrier's hollows (x +-0.18, y -0.12 to ``y1``, z 1.10-1.55 [m]) round a solid boss
    ``wall`` thick about the spindle cartridge (+-0.075): one core behind the boss, one each side."""
    if wall is None:
        return ()
    b = 0.075 + wall
    x0, x1, z0, z1 = -0.18 + wall, 0.18 - wall, 1.10 + wall, 1.55 - wall
    return (Box((x0, b, z0), (x1, y1 - wall, z1)), Box((x0, -0.12 + wall, z0), (-b, b, z1)),
            Box((b, -0.12 + wall, z0), (x1, b, z1)))


def _drive_effects(axis: str, extra: tuple = ()) -> tuple[str, ...]:
    """The effects an axis's feed drive adds to the machine's default set when a scenario moves it."""
    return tuple(f"{f}_{axis}" for f in ("feed_nut", "feed_bearings", "feed_motor", "feed_guideways",
                                         "feed_screw_gap")) + extra


def _screw_parts(a: str, screw: Box, front: Box, rear: Box, chain: str) -> tuple[Part, ...]:
    """Axis ``a``'s steel screw and its fixed (front) and floating (rear) support bearings."""
    steel = material("steel")
    return (Part(f"{a}_screw", steel, (screw,), chain), Part(f"{a}_front_bearing", steel, (front,), chain),
            Part(f"{a}_rear_bearing", steel, (rear,), chain))


def _drive_roles(a: str, structure: tuple[str, ...], motor, nut_body, rails, carriages) -> dict:
    """Axis ``a``'s ``feed_drive.<a>.*`` roles over the parts :func:`_screw_parts` names."""
    return {feed_drive_role(a, "screw"): Parts((f"{a}_screw",)),
            feed_drive_role(a, "screw_gap"): Named(f"{a}_screw_gap"),
            feed_drive_role(a, "structure_side"): Parts(structure),
            feed_drive_role(a, "front_bearing"): Parts((f"{a}_front_bearing",)),
            feed_drive_role(a, "rear_bearing"): Parts((f"{a}_rear_bearing",)),
            feed_drive_role(a, "motor"): motor,
            feed_drive_role(a, "nut_body"): nut_body,
            feed_drive_role(a, "guideways"): rails,
            feed_drive_role(a, "carriages"): carriages}


def _pair(part: str, box_lo, box_hi, across: int, spans) -> Union:
    """Two boxes in ``part`` (a pair of rails or of carriages), equal but for coordinate
    ``across`` (0 x, 1 y), which takes each of the two ``spans`` (lo, hi) [m]."""
    boxes = []
    for lo, hi in spans:
        a, b = list(box_lo), list(box_hi)
        a[across], b[across] = lo, hi
        boxes.append(InBox(Parts((part,)), Box(tuple(a), tuple(b))))
    return Union(tuple(boxes))


def axes(col_y0: float) -> list[LinearAxis]:
    """X 500, Y 400, Z 330 mm (seed 000), semi-closed loop (seed 000: ball screws with rotary
    encoders), each with its ball-screw drive: a 40 mm square steel screw (the cross-section of a
    40-45 mm ball screw), lead 10 mm, a fixed (thrust) bearing at the motor end and a floating one
    at the other. Plausible, not a measured machine.

    * Y (seed 003's servo axis; saddle and table on the bed): the screw along y in a trough of
      the bed top under the saddle, x = 0, z 0.31-0.35 m, fixed bearing at the front (motor) end
      y -0.55..-0.50, floating at the rear y 0.40..0.45; the nut under the saddle's centre.
      Commanded Y = p puts the nut at y = -0.25 + p [m]; the mesh's pose is Y = 200 mm.
    * X (table on the saddle): the screw along x in the saddle top under the table, y = 0,
      z 0.43-0.47 m, fixed bearing at the right (motor) end x 0.30..0.35, floating at the left
      x -0.35..-0.30; the motor's flange at the saddle's right end; the nut under the table's
      centre; its carriages within 100 mm of the table's centre (they stay on the saddle's rails
      over the whole travel). X = p puts the nut at x = -0.25 + p; the mesh's pose is X = 250 mm.
    * Z (carrier on the column): the screw upright in the column's front, x = 0, y 0.47-0.51 m,
      z 1.25..1.85, fixed bearing at the top z 1.85..1.90 under the motor (in the column top,
      where ``z_axis_holding`` puts the holding losses), floating at the bottom z 1.20..1.25;
      the nut in the carrier's rear at mid-height. Z = p puts the nut at z = 1.30 + p; the
      mesh's pose is Z = 0 (the carrier as built, the spindle tests' position).
    """
    e = 1e-3
    col_top = 1.90
    # Y: saddle on the bed
    gy = (-0.55, col_y0)                    # the rails' extent along y [m]
    lo, hi = 0.31, 0.35                     # screw's bottom and top [m]
    y_drive = FeedDrive(
        parts=_screw_parts("y", Box((-0.02, -0.50, lo), (0.02, 0.40, hi)), Box((-0.02, -0.55, lo), (0.02, -0.50, hi)),
                           Box((-0.02, 0.40, lo), (0.02, 0.45, hi)), "workpiece"),
        surfaces=(Surface("y_screw_gap", ("y_screw",), interface_with=("bed", "saddle")),),
        roles=_drive_roles("y", ("bed", "saddle"),
                           motor=InBox(Parts(("bed",)), Box((0.05, -0.56, 0.15), (0.30, -0.44, 0.36))),
                           nut_body=InBox(Parts(("saddle",)), Box((-0.10, -0.15, 0.34), (0.10, 0.05, 0.42))),
                           rails=_pair("bed", (0, gy[0], 0.29), (0, gy[1], 0.35), 0, ((-0.30, -0.20), (0.20, 0.30))),
                           carriages=_pair("saddle", (0, -0.35, 0.35), (0, 0.25, 0.42), 0,
                                           ((-0.30, -0.20), (0.20, 0.30)))),
        # seed 003's eleven sites (Table 1), T1..T11 in its order
        points=(Point("Y_motor", (0.15, -0.55 + e, 0.28), "bed"),
                Point("Y_column", (0.20, col_y0 + e, 0.80), "column"),
                Point("Y_guideway_front", (0.25, -0.55 + e, 0.34), "bed"),
                Point("Y_bed", (0.0, -0.55 + e, 0.15), "bed"),
                Point("Y_guideway_back", (0.25, 0.30, 0.35 - e), "bed"),
                Point("Y_air_machine", (0.0, -0.80, 0.60), "air"),
                Point("Y_front_bearing", (0.0, -0.525, hi - e), "y_front_bearing"),
                Point("Y_table", (0.30, -0.10, 0.55 - e), "table"),
                Point("Y_rear_bearing", (0.0, 0.425, hi - e), "y_rear_bearing"),
                Point("Y_nut", (0.0, -0.05, 0.35 + e), "saddle"),
                Point("Y_air_room", (0.0, -1.50, 1.50), "air")),
        screw_axis=(0.0, 0.5 * (lo + hi)), fixed_end=-0.50, lead=0.010, nut_offset=(0.0, 0.03),
        effects=_drive_effects("y"))
    # X: table on the saddle (saddle x -0.35..0.35, top z 0.47; table x -0.5..0.5, y -0.25..0.15)
    xl, xh = 0.43, 0.47
    x_drive = FeedDrive(
        parts=_screw_parts("x", Box((-0.30, -0.02, xl), (0.30, 0.02, xh)), Box((0.30, -0.02, xl), (0.35, 0.02, xh)),
                           Box((-0.35, -0.02, xl), (-0.30, 0.02, xh)), "workpiece"),
        surfaces=(Surface("x_screw_gap", ("x_screw",), interface_with=("saddle", "table")),),
        roles=_drive_roles("x", ("saddle", "table"),
                           motor=InBox(Parts(("saddle",)), Box((0.27, -0.12, 0.35), (0.36, 0.12, 0.47))),
                           nut_body=InBox(Parts(("table",)), Box((-0.10, -0.08, 0.47), (0.10, 0.08, 0.51))),
                           rails=_pair("saddle", (-0.35, 0, 0.43), (0.35, 0, 0.47), 1, ((-0.22, -0.14), (0.04, 0.12))),
                           carriages=_pair("table", (-0.10, 0, 0.47), (0.10, 0, 0.51), 1,
                                           ((-0.22, -0.14), (0.04, 0.12)))),
        points=(Point("X_motor", (0.35 - e, 0.10, 0.40), "saddle"),
                Point("X_front_bearing", (0.325, 0.0, xh - e), "x_front_bearing"),
                Point("X_rear_bearing", (-0.325, 0.0, xh - e), "x_rear_bearing"),
                Point("X_nut", (0.0, -0.05, 0.47 + e), "table")),
        screw_axis=(0.0, 0.5 * (xl + xh)), fixed_end=0.30, lead=0.010, nut_offset=(0.0, 0.03),
        effects=_drive_effects("x"))
    # Z: carrier on the column face (column y from col_y0, carrier z 1.10..1.55 at Z = 0)
    zy0, zy1 = col_y0 + 0.02, col_y0 + 0.06
    z_drive = FeedDrive(
        parts=_screw_parts("z", Box((-0.02, zy0, 1.25), (0.02, zy1, 1.85)), Box((-0.02, zy0, 1.85), (0.02, zy1, col_top)),
                           Box((-0.02, zy0, 1.20), (0.02, zy1, 1.25)), "tool"),
        surfaces=(Surface("z_screw_gap", ("z_screw",), interface_with=("column",)),),
        roles=_drive_roles("z", ("column",),
                           motor=Band(Parts(("column",)), "z", col_top - 0.2, col_top),   # = z_drive.top
                           nut_body=InBox(Parts(("carrier",)), Box((-0.10, col_y0 - 0.10, 1.25), (0.10, col_y0, 1.40))),
                           rails=_pair("column", (0, col_y0, 0.90), (0, col_y0 + 0.04, col_top), 0,
                                       ((-0.22, -0.14), (0.14, 0.22))),
                           carriages=_pair("carrier", (0, col_y0 - 0.04, 1.10), (0, col_y0, 1.55), 0,
                                           ((-0.18, -0.12), (0.12, 0.18)))),
        points=(Point("Z_motor", (0.20, col_y0 + e, col_top - 0.10), "column"),
                Point("Z_front_bearing", (0.0, zy0 + e, 1.875), "z_front_bearing"),
                Point("Z_rear_bearing", (0.0, zy0 + e, 1.225), "z_rear_bearing"),
                Point("Z_nut", (0.0, col_y0 - e, 1.32), "carrier")),
        screw_axis=(0.0, 0.5 * (zy0 + zy1)), fixed_end=1.85, lead=0.010, nut_offset=(0.0, -0.05),
        effects=_drive_effects("z", ("z_axis_holding",)))
    return [LinearAxis("X", "x", (0.0, 0.50), "semi-closed", ("table",), -0.25, 0.25, x_drive),
            LinearAxis("Y", "y", (0.0, 0.40), "semi-closed", ("saddle", "table", "x_screw", "x_front_bearing",
                                                             "x_rear_bearing"), -0.25, 0.20, y_drive),   # X rides on Y
            LinearAxis("Z", "z", (0.0, 0.33), "semi-closed", ("carrier", "spindle", "front_bearing", "rear_bearing",
                                                             "motor", "test_bar"), 1.30, 0.0, z_drive)]


def camera_poses(nose: float, tip: float) -> list[CameraPose]:
    """Where a thermal camera looks from. ``carrier-front`` is the seeds' view (seed 000 L4146,
    seed 001 L213): about 1.5 m in front of the spindle carrier, whose front face (0.36 x 0.45 m)
    then fills the S65's 24 x 18 deg field (0.63 x 0.47 m at 1.5 m)."""
    carrier_front = (0.0, -0.12, 1.325)  # centre of the carrier's front face [m]
    bar = (0.0, -0.02, 0.5 * (nose + tip) + 0.05)
    return [
        CameraPose("carrier-front", (0.0, -0.12 - 1.5, 1.325), carrier_front, subject="carrier",
                   description="the seeds' view: the spindle carrier's front face from 1.5 m"),
        CameraPose("spindle-front", (0.0, bar[1] - 1.5, bar[2]), bar, subject="test_bar",
                   description="spindle nose and test bar from 1.5 m (the shiny mandrel with its taped band)"),
        CameraPose("machine-front", (0.0, -6.0, 1.0), (0.0, 0.2, 0.95), subject="column",
                   description="the whole machine from the front, 6 m away"),
        CameraPose("machine-iso", (2.6, -4.2, 2.4), (0.0, 0.2, 0.95), subject="column",
                   description="the whole machine from the front right, above"),
    ]


def finishes(nose: float, hb: float) -> list[Finish]:
    """Painted castings and motor, bare ground steel on the spindle nose and the test mandrel,
    masking tape (the seeds' emissivity 0.95) on the carrier's front face and on a band of the
    mandrel 20-100 mm below the nose (seed 000 L4140: tape on the rotating test bar)."""
    castings = ("bed", "saddle", "table", "column", "carrier", "motor")
    return [
        Finish(MACHINE_PAINT, castings),
        Finish(GROUND_STEEL, ("spindle", "front_bearing", "rear_bearing", "test_bar")),
        Finish(MASKING_TAPE, ("carrier",), Box((-0.19, -0.1205, 1.095), (0.19, -0.1195, 1.555))),
        Finish(MASKING_TAPE, ("test_bar",), Box((-hb - 1e-3, -hb - 1e-3, nose - 0.10), (hb + 1e-3, hb + 1e-3, nose - 0.02))),
    ]


def roles(col_top: float, col_y0: float) -> dict:
    """The machine contract: where each role of :data:`geometries.regions.ROLES` lies on the C-frame.
    The operator and the hall door are in front (-y), the rear wall with its windows behind (+y),
    the electrical cabinet beside the column's left side, the Z motor and brake in the column's
    top 0.2 m (``col_top`` [m]: the column's top; ``col_y0`` [m]: its front face)."""
    skin = Named("skin")
    return {
        "spindle.front_bearing": Parts(("front_bearing",)),
        "spindle.rear_bearing": Parts(("rear_bearing",)),
        "spindle.motor": Parts(("motor",)),
        "spindle.rotating": Union((Named("test_bar_skin"), Named("spindle_nose"))),
        "spindle.jacket": Named("spindle_jacket"),
        "test_bar.seat": Named("test_bar_seat"),
        "test_bar.body": Parts(("test_bar",)),
        "structure.skin": skin,
        "structure.front": Facing(skin, "-y"),
        # the column's front carries the Z guideways under their way covers: a draft reaches the
        # head, the spindle and the bed, saddle and table in front of it, not the column face
        "structure.open_front": InBox(Facing(skin, "-y"), Box((-10, -10, -10), (10, col_y0 - 0.01, 10))),
        "structure.rear": Facing(skin, "+y"),
        "floor.contact": Named("floor_contact"),
        "cabinet.face": Named("column_side_left"),
        "z_drive.top": Band(Parts(("column",)), "z", col_top - 0.2, col_top),
    }
