"""``belt-vmc``: a small three-axis C-frame VMC with a belt-driven spindle (seed 000, Machine B).

Seed facts (thesis L4040-4065, L4446-4513): a three-axis vertical milling machine "similar in
concept to Machine A" (table on a saddle over the bed, column at the rear, spindle carrier on the
column face), a DC spindle motor on top of the spindle carrier, the spindle turned by a belt
drive "which may act as a heat source by which the heat flows into the spindle through the
contacting areas", 60-8000 rpm, axis feedback by linear scales (ballscrew growth is corrected by
the position loop, so no ballscrew is modelled), 77 temperature points (Table 4-4) and five
eddy-current probes on a test bar. Travels, dimensions and masses are not given.

Chosen dimensions: the envelope of a small belt-drive VMC, smaller than ``cframe-vmc``: travels
X 400, Y 300, Z 300 mm; bed 1.0 x 1.25 m, 0.30 m high; table 0.80 x 0.34 m, top at 0.50 m; column
0.40 x 0.40 m from the bed top to 1.70 m (room for 300 mm of Z above the test position); spindle
carrier 0.30 m wide, 0.40 m tall (z 1.00-1.40 m), from the column face to 0.10 m in front of the
spindle axis (throat 0.40 m: room for the motor between spindle and column); a spindle boss cast
with the carrier (0.22 m square, 0.10 m tall) under it; a 120 mm steel cartridge from the nose
(0.88 m) to the carrier top with the front bearings in the boss and the rear bearing near its top,
under the pulley; a steel pulley (120 mm, 60 mm wide) on top of the spindle; the DC motor
(0.18 x 0.18 x 0.25 m) on the carrier top, 0.29 m behind the spindle axis (the belt's centre
distance) and 20 mm clear of the column face; the same 40 mm square, 270 mm test bar as
``cframe-vmc`` (the same laboratory's ISO 230-3 set-up).

Construction (issue 8's decision; plausible, not a measured machine): castings of a machine this
size are hollow, ribbed boxes with walls of 15-30 mm, not solid blocks (as solid blocks the model
weighed 5.3 t against about 3 t for a real machine of this class; now 3.9 t, 2.7 t of it the bed,
still solid: it carries no heat source in the spindle tests), and a belt-driven spindle is a cartridge
located by its front flange in the head's boss, the rest of it sliding in a clearance bore so the
shaft can grow. So:

* the column is a hollow box (``column_boxes``): front (guideway) wall, rear and side walls and top
  plate 25 mm thick, open at the bottom onto the bed;
* the carrier (``carrier_boxes``) is a solid spindle housing from its front to 0.10 m behind the
  spindle axis, full height, and behind it a 25 mm top plate (the motor's seat), bottom plate, side
  walls and slide plate on the column face;
* the cartridge touches the carrier only in the boss (z 0.90-1.00 m, where its front bearings sit);
  above it runs in a bore with 10 mm radial clearance (the gap is air: no conduction across it).

The cavities' faces belong to the skin and see the room air's natural convection; a closed casting's
inner air warms up, so this slightly overstates their cooling. Tool-side parts stay bonded to each
other, the carrier at one Z position, as in ``cframe-vmc``.

Calibration (``tests/test_belt_vmc.py``; default effects plus ``belt_drive``, default mesh):
8000 rpm 1 h + 1 h stopped (belt-test-6) gives peak |X| 0.00, |Y| 18.9, |Z| 23.8 um (seed 3,
60-79, 22-24); 4000 rpm 1 h + 1 h (Test I) |Y| 5.2 um (seed 25); Test IV |Y| 13.7 um (seed 39);
the fine mesh is within 0.3 % of the default. The solid-block model gave |Y| 11.3, 3.7, 10.0 um and
its Y peaked an hour after the spindle stopped (Y +0.3 um at 1 h: the top and bottom heat
cancelled); the hollow construction's Y grows through the heating hour as the seed's does (Y -18.4,
Z -23.1 um at 1 h). X and Z are in the seed's range; Y is 3-5 times too small and still a little
smaller than Z. Per source at 1 h (Test VI): the front bearings (123 W at 8000 rpm) -21.6 um Y,
-16.9 um Z (they tilt the head forwards by heating the boss and the carrier's bottom plate, and
grow the boss, cartridge nose and test bar downwards); the rear bearing (107 W) -3.3 / -2.1 (its
heat now flows down the cartridge to the boss instead of into the carrier's top, where it tilted
the head the other way, +6.4 um Y); the belt (50 W) -1.5 / -1.1; the motor on the carrier top
(53 W) +5.9 / -4.8. No path in this model turns heat into Y without about as much Z: per 100 W
held for an hour, heat spread on the hollow carrier's underside gives -29 um Y and +5 um Z (the
best), on the column's front face +1 um Y and +8 um Z; the seed's 60-79 um with Z 22-24 um would
need several hundred watts more on the carrier's underside than any source of this machine puts
there (or a mechanism this twin lacks: warm air from the motor's fan round the head, a joint that
lets the head tilt). The default effect strengths (shared with ``cframe-vmc``) are not bent to fake
it.

Temperature points: ``TEMPERATURE_POINTS`` is T1 .. T77 in the seed's order (Table 4-4).
Structural points lie 1 mm inside the face they are glued to (``sensor_sites``), T71-T72 40 mm
inside the column casting. The seven air points (``AIR_POINTS``: Y-scale air T66-T67, column top
air T70, carrier air T73, spindle air T75, base air T76, tool air T77) lie 30-80 mm out in the
air beside the named place, in ``air_sites`` with part ``"air"``; the model's air is uniform
room air, so they would read the room temperature (an observer for them comes later). Carrier
strip 1 (T8-T33) runs up the carrier's front face, strip 2 (T34-T62) down its right side face:
the seed's clustering (Table 5-4) groups T62 with the boss sensor T63 and T33 with T34, so the
strips meet at the top and strip 2 ends at the bottom next to the boss.

Axes: x along the X travel, y towards the column (rear), z up, floor at z = 0; the spindle axis
is the line x = y = 0.
"""

from __future__ import annotations

from geometries.axes import LinearAxis, Scale
from geometries.base import (PROBE_HEIGHTS, Box, Machine, Part, Point, Surface, common_surfaces, material,
                             test_bar_nest)
from geometries import cframe_vmc
from geometries.cframe_vmc import SPINDLE_EFFECTS
from geometries.regions import Named

NAME = "belt-vmc"

# The C-frame's spindle-test effects plus the belt's losses into the spindle pulley (the seed ran no
# ETVE test on Machine B: the C-frame's workshop effects are there by --effects, not by default).
DEFAULT_EFFECTS = SPINDLE_EFFECTS + ("belt_drive",)

MIN_SPEED = 60.0   # [rpm] the spindle's slowest steady speed (seed 000 L4052: "60 rpm to 8000 rpm")

# Every temperature point of the seed's Machine B in its own order (Table 4-4): structural sites
# and air points together, so a study can ask for all 77 by this list.
TEMPERATURE_POINTS: tuple[str, ...] = tuple(f"T{i}" for i in range(1, 78))

# The points that measure air, and the part each sits beside (within ``AIR_GAP_MAX`` of it).
AIR_POINTS: dict[str, str] = {"T66": "bed", "T67": "bed", "T70": "column", "T73": "carrier", "T75": "carrier",
                              "T76": "bed", "T77": "test_bar"}
AIR_GAP_MAX = 0.1  # m

# The hollow carrier's spindle housing reaches this far behind the spindle axis [m] (30 mm of iron
# behind the 10 mm clearance round the 120 mm cartridge, as in front of it).
HOUSING_BACK = 0.10

# Bearing zones get at least two cells in height, as in cframe-vmc (their heat peaks inside them).
_BEARING = (1.0, 1.0, 0.5)


def build(bar_length: float = 0.27, bar_width: float = 0.04, throat: float = 0.40, column_depth: float = 0.40,
          motor_offset: float = 0.29, wall: float | None = 0.025, bore_gap: float | None = 0.01) -> Machine:
    """Build the belt-driven VMC.

    bar_length [m]: test-bar overhang below the spindle nose; bar_width [m]: square mandrel side;
    throat [m]: spindle axis to the column face; column_depth [m]: column front to rear;
    motor_offset [m]: motor axis behind the spindle axis (the belt's centre distance);
    wall [m]: wall thickness of the hollow column and carrier castings (None: solid blocks);
    bore_gap [m]: radial clearance of the carrier's bore round the spindle cartridge above the
    boss, where the cartridge's front flange is held (None: the cartridge bonded along its length).

    The test bar is meshed three times finer (``refine=1/3``) and the bearing zones split in
    height, as in ``cframe-vmc`` (see its docstring).
    """
    iron, steel = material("grey_cast_iron"), material("steel")
    bed_top, saddle_top, table_top = 0.30, 0.42, 0.50
    car_bot, car_top, car_front, car_half = 1.00, 1.40, -0.10, 0.15
    nose = 0.88                        # spindle nose [m]
    tip = nose - bar_length            # tool reference point [m]
    col_y0, col_y1, col_half, col_top = throat, throat + column_depth, 0.20, 1.70
    rs, boss = 0.06, 0.11              # cartridge and boss half sides [m]
    boss_bot = nose + 0.02
    pulley_top = car_top + 0.06
    mh = 0.09                          # motor half side [m]
    my0, my1 = motor_offset - mh, motor_offset + mh
    if my0 < rs + 0.02 or my1 > col_y0 - 0.01:
        raise ValueError(f"motor at {motor_offset} m does not fit between the pulley and the column face")
    hb = bar_width / 2

    parts = [
        Part("bed", iron, (Box((-0.50, -0.45, 0.0), (0.50, col_y1, bed_top)),), "workpiece"),
        Part("saddle", iron, (Box((-0.30, -0.30, bed_top), (0.30, 0.20, saddle_top)),), "workpiece"),
        Part("table", iron, (Box((-0.40, -0.22, saddle_top), (0.40, 0.12, table_top)),), "workpiece"),
        Part("column", iron, column_boxes((-col_half, col_y0, bed_top), (col_half, col_y1, col_top), wall), "tool"),
        Part("carrier", iron, carrier_boxes((-car_half, car_front, car_bot), (car_half, col_y0, car_top), wall,
                                            None if bore_gap is None else rs + bore_gap)
             + (Box((-boss, -boss, boss_bot), (boss, boss, car_bot)),), "tool"),
        Part("spindle", steel, (Box((-rs, -rs, nose), (rs, rs, car_top)),), "tool"),
        Part("front_bearing", steel, (Box((-rs, -rs, nose + 0.04), (rs, rs, nose + 0.10)),), "tool", refine=_BEARING),
        Part("rear_bearing", steel, (Box((-rs, -rs, car_top - 0.10), (rs, rs, car_top - 0.04)),), "tool",
             refine=_BEARING),
        Part("pulley", steel, (Box((-rs, -rs, car_top), (rs, rs, pulley_top)),), "tool"),
        Part("motor", steel, (Box((-mh, my0, car_top), (mh, my1, car_top + 0.25)),), "tool"),
        Part("test_bar", steel, (Box((-hb, -hb, tip), (hb, hb, nose)),), "tool", refine=1 / 3),
    ]
    surfaces = common_surfaces(parts, nose) + [
        Surface("motor_flange", ("motor",), interface_with=("carrier",)),
        Surface("front_bearing_seat", ("front_bearing",), interface_with=("spindle",)),
        Surface("rear_bearing_seat", ("rear_bearing",), interface_with=("spindle",)),
        Surface("column_face", ("column",), within=Box((-1, col_y0 - 1e-4, 0), (1, col_y0 + 1e-4, 3))),
        Surface("carrier_top", ("carrier",), within=Box((-1, -1, car_top - 1e-4), (1, 1, car_top + 1e-4))),
        Surface("column_side_left", ("column",),
                within=Box((-col_half - 1e-4, col_y0, bed_top), (-col_half + 1e-4, col_y1, col_top))),
        Surface("spindle_jacket", ("spindle", "front_bearing", "rear_bearing"), interface_with=("carrier",)),
        # belt drive (twin/effects/belt.py): the pulley's rim, where the belt runs, and its seat
        Surface("belt_contact", ("pulley",), within=Box((-1, -1, car_top + 1e-4), (1, 1, pulley_top - 1e-4))),
        Surface("pulley_seat", ("pulley",), interface_with=("spindle",)),
    ]

    e = 1e-3  # structural sensors sit 1 mm inside the face they are glued to
    inside = 0.04 if wall is None else wall - e  # T71-T72: inside the column: on its cavity's walls
    structural = [
        # column outside (T1-T7): front face above and beside the carrier, both sides, top, rear
        Point("T1", (0.10, col_y0 + e, 1.60), "column"),
        Point("T2", (-0.175, col_y0 + e, 1.20), "column"),
        Point("T3", (-col_half + e, col_y0 + 0.05, 1.55), "column"),
        Point("T4", (col_half - e, col_y0 + 0.05, 1.20), "column"),
        Point("T5", (0.0, col_y0 + 0.05, col_top - e), "column"),
        Point("T6", (col_half - e, col_y1 - 0.10, 1.55), "column"),
        Point("T7", (0.0, col_y1 - e, 1.40), "column"),
    ]
    n1, n2 = 26, 29  # strip 1 T8-T33 up the front face; strip 2 T34-T62 down the right side face
    h = car_top - car_bot
    structural += [Point(f"T{8 + i}", (0.10, car_front + e, car_bot + (i + 0.5) * h / n1), "carrier") for i in range(n1)]
    structural += [Point(f"T{34 + i}", (car_half - e, 0.15, car_top - (i + 0.5) * h / n2), "carrier") for i in range(n2)]
    structural += [
        # spindle boss (T63-T65): its front face low and high, its right face in between
        Point("T63", (0.0, -boss + e, boss_bot + 0.03), "carrier"),
        Point("T64", (boss - e, 0.0, boss_bot + 0.05), "carrier"),
        Point("T65", (0.0, -boss + e, boss_bot + 0.07), "carrier"),
        # Y bed (T68-T69): the bed's right face beside the Y scale
        Point("T68", (0.50 - e, -0.15, 0.25), "bed"),
        Point("T69", (0.50 - e, 0.15, 0.25), "bed"),
        # inside the column (T71-T72): the front wall above the carrier, the rear wall (glued in the cavity)
        Point("T71", (0.0, col_y0 + inside, 1.55), "column"),
        Point("T72", (0.0, col_y1 - inside, 1.20), "column"),
        Point("T74", (0.30, -0.05, table_top - e), "table"),
    ]
    air = [
        Point("T66", (0.53, -0.15, 0.27), "air"),                          # Y-scale air, 30 mm off the bed's right face
        Point("T67", (0.53, 0.15, 0.27), "air"),
        Point("T70", (0.0, col_y0 + column_depth / 2, col_top + 0.08), "air"),  # 80 mm above the column top
        Point("T73", (-car_half - 0.03, 0.15, 1.20), "air"),               # 30 mm beside the carrier's left face
        Point("T75", (0.0, -boss - 0.03, boss_bot + 0.05), "air"),          # 30 mm in front of the spindle boss
        Point("T76", (0.0, -0.45 - 0.05, 0.15), "air"),                     # 50 mm in front of the bed
        Point("T77", (hb + 0.03, 0.0, tip + 0.05), "air"),                  # 30 mm beside the test bar's end
    ]
    order = {name: i for i, name in enumerate(TEMPERATURE_POINTS)}
    structural.sort(key=lambda p: order[p.name])
    air.sort(key=lambda p: order[p.name])

    nest, probes = test_bar_nest(tip, hb, table_top)
    points = sorted(structural + air, key=lambda p: order[p.name]) + nest
    assert [p.name for p in sorted(structural + air, key=lambda p: order[p.name])] == list(TEMPERATURE_POINTS)
    assert {p.name for p in air} == set(AIR_POINTS)
    return Machine(
        name=NAME,
        parts=parts,
        surfaces=surfaces,
        points=points,
        probes=probes,
        tool_point="tool",
        workpiece_point="workpiece",
        sensor_sites=[p.name for p in structural],
        air_sites=[p.name for p in air],
        resolutions={"coarse": 0.10, "default": 0.06, "fine": 0.04},
        description=("small 3-axis C-frame VMC with a belt-driven spindle (seed Machine B): X 400, Y 300, Z 300 mm, "
                     "60-8000 rpm, DC motor on the carrier top belted to a pulley on the spindle, linear scales on X, Y, Z"),
        roles=roles(col_top, col_y0),
        default_effects=DEFAULT_EFFECTS,
        max_speed=8000.0,
        min_speed=MIN_SPEED,
        axes=axes(bed_top),
        parameters={"bar_length": bar_length, "bar_width": bar_width, "throat": throat, "column_depth": column_depth,
                    "motor_offset": motor_offset, "probe_spacing": PROBE_HEIGHTS[1] - PROBE_HEIGHTS[0], "min_speed": MIN_SPEED,
                    "travel_x": 0.40, "travel_y": 0.30, "travel_z": 0.30, "linear_scales": 1.0},
    )


def column_boxes(lo, hi, wall: float | None) -> tuple[Box, ...]:
    """The column between ``lo`` and ``hi`` [m]: a solid block (``wall`` None) or a hollow box
    casting with ``wall`` [m] thick front, rear and side walls and top plate, open at the bottom
    onto the bed (the bed's top closes it)."""
    if wall is None:
        return (Box(lo, hi),)
    (x0, y0, z0), (x1, y1, z1), t = lo, hi, wall
    return (Box((x0, y0, z0), (x1, y0 + t, z1)), Box((x0, y1 - t, z0), (x1, y1, z1)),
            Box((x0, y0 + t, z0), (x0 + t, y1 - t, z1 - t)), Box((x1 - t, y0 + t, z0), (x1, y1 - t, z1 - t)),
            Box((x0 + t, y0 + t, z1 - t), (x1 - t, y1 - t, z1)))


def carrier_boxes(lo, hi, wall: float | None, bore: float | None) -> tuple[Box, ...]:
    """The spindle carrier between ``lo`` and ``hi`` [m] (front at y = lo[1], the column face at
    y = hi[1], the spindle axis at x = y = 0): a solid block (``wall`` None) or a hollow box
    casting: a solid spindle housing from the front to ``HOUSING_BACK`` behind the spindle axis,
    full height, and behind it ``wall`` [m] thick top and bottom plates, side walls and the slide
    plate on the column face. ``bore`` [m]: half side of a clearance bore through the housing
    round the spindle cartridge (None: no bore, the cartridge bonded in the housing)."""
    (x0, _, z0), (x1, y1, z1), t = lo, hi, wall
    if wall is None:
        boxes = [Box(lo, hi)]
    else:
        yh = HOUSING_BACK
        boxes = [Box(lo, (x1, yh, z1)), Box((x0, yh, z0), (x1, y1, z0 + t)), Box((x0, yh, z1 - t), (x1, y1, z1)),
                 Box((x0, yh, z0 + t), (x0 + t, y1, z1 - t)), Box((x1 - t, yh, z0 + t), (x1, y1, z1 - t)),
                 Box((x0 + t, y1 - t, z0 + t), (x1 - t, y1, z1 - t))]
    if bore is None:
        return tuple(boxes)
    housing, rest = boxes[0], boxes[1:]
    (hx0, hy0, hz0), (hx1, hy1, hz1) = housing.lo, housing.hi
    return (Box((hx0, hy0, hz0), (-bore, hy1, hz1)), Box((bore, hy0, hz0), (hx1, hy1, hz1)),
            Box((-bore, hy0, hz0), (bore, -bore, hz1)), Box((-bore, bore, hz0), (bore, hy1, hz1)), *rest)


def axes(bed_top: float) -> list[LinearAxis]:
    """X 400, Y 300, Z 300 mm, closed loop (seed 000: linear scales on every axis). The Y scale
    lies along the bed's top at x = 0.32 m, just beside the saddle, its read head on the saddle's
    side; commanded Y = p puts the head at y = -0.20 + p [m], the mesh's pose is Y = 150 mm (the
    saddle as built). No feed drive is modelled on this machine (its axes stand still: no feed
    heat); the scales' mountings are plausible, not measured."""
    y_scale = Scale(line=(0.32, bed_top - 0.01), carrier="bed", head=(0.29, bed_top + 0.01))
    return [LinearAxis("X", "x", (0.0, 0.40), "closed", ("table",), -0.20, 0.20),
            LinearAxis("Y", "y", (0.0, 0.30), "closed", ("saddle", "table"), -0.20, 0.15, scale=y_scale),
            LinearAxis("Z", "z", (0.0, 0.30), "closed", ("carrier", "spindle", "front_bearing", "rear_bearing",
                                                         "pulley", "motor", "test_bar"), 1.00, 0.0)]


def roles(col_top: float, col_y0: float) -> dict:
    """The machine contract of the belt-driven VMC: the C-frame's places
    (:func:`geometries.cframe_vmc.roles`), plus the pulley's rim where the belt runs."""
    return {**cframe_vmc.roles(col_top, col_y0), "spindle.belt_contact": Named("belt_contact")}
