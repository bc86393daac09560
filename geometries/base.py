"""Machine description: parts made of axis-aligned boxes, named surfaces and named points.

A machine is code (parametric); :meth:`Machine.mesh` turns it into a structured hexahedral mesh
(see :mod:`twin.fem.mesh`). Coordinates are metres: x along the table's X travel, y towards the
column (rear), z up; the floor is z = 0.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from geometries.materials import MATERIALS, Material
from geometries.regions import check_roles

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class Box:
    """Axis-aligned box [lo, hi] in metres."""

    lo: Vec3
    hi: Vec3

    def __post_init__(self):
        if not all(h > l for l, h in zip(self.lo, self.hi)):
            raise ValueError(f"box {self.lo} -> {self.hi} has no volume")

    def contains(self, points: np.ndarray, tol: float = 1e-9) -> np.ndarray:
        """Boolean mask of points (n, 3) inside the closed box."""
        lo, hi = np.asarray(self.lo) - tol, np.asarray(self.hi) + tol
        return np.all((points >= lo) & (points <= hi), axis=1)

    @property
    def volume(self) -> float:
        return float(np.prod(np.subtract(self.hi, self.lo)))


@dataclass(frozen=True)
class Part:
    """A solid of the machine: a name, a material, a place in the kinematic chain, its boxes.

    Parts listed later in a machine overwrite earlier ones where their boxes overlap (a spindle
    cartridge inside a carrier casting, a bearing zone inside a spindle). ``voids`` are carved out
    of the part's own cells: the closed hollows of a ribbed casting, whose faces are no skin
    (:func:`common_surfaces`).
    """

    name: str
    material: Material
    boxes: tuple[Box, ...]
    chain: str = ""  # "workpiece" side (bed, saddle, table) or "tool" side (column, carrier, ...)
    voids: tuple[Box, ...] = ()  # closed hollows carved out of the part's boxes (a box casting's cores)
    refine: float | tuple[float, float, float] = 1.0  # cells across the part's extent are at most
    # refine x the mesh spacing (one factor, or one per axis x, y, z)


@dataclass(frozen=True)
class Surface:
    """A named surface: the exterior faces of ``parts`` (optionally inside ``within`` and outside
    every box of ``without``: a closed cavity's walls), or, when ``interface_with`` is given, the
    faces shared between ``parts`` and those parts."""

    name: str
    parts: tuple[str, ...]
    within: Box | None = None
    interface_with: tuple[str, ...] = ()
    without: tuple[Box, ...] = ()


@dataclass(frozen=True)
class Point:
    """A named point: a location [m] on a part."""

    name: str
    xyz: Vec3
    part: str


@dataclass(frozen=True)
class Probe:
    """An ISO 230-3 non-contact displacement probe: it is fixed to ``fixture`` and reads the
    displacement of ``target`` along ``direction`` relative to the fixture (eddy-current, um)."""

    name: str
    target: str
    direction: Vec3
    fixture: str


@dataclass(frozen=True)
class StrainGauge:
    """A surface strain gauge (a fibre Bragg grating glued along ``direction``, a unit vector):
    it reads the mean strain over ``length`` [m] centred on ``xyz`` [m], on ``part``."""

    name: str
    xyz: Vec3
    direction: Vec3
    length: float
    part: str

    def __post_init__(self):
        if not self.length > 0 or abs(float(np.linalg.norm(self.direction)) - 1.0) > 1e-9:
            raise ValueError(f"strain gauge {self.name!r} needs a positive length and a unit direction")

    @property
    def ends(self) -> tuple[Vec3, Vec3]:
        """The grating's two ends [m], ``length`` apart along ``direction``."""
        c, d = np.asarray(self.xyz, float), np.asarray(self.direction, float)
        return tuple(c - 0.5 * self.length * d), tuple(c + 0.5 * self.length * d)


def common_surfaces(parts: list[Part], nose: float) -> list[Surface]:
    """The surfaces every machine with a test bar in its spindle has: ``skin`` (every part's outer
    faces above the floor, but not the walls of the parts' closed ``voids``, whose still air the
    model leaves out), ``floor_contact`` (the bed's underside), ``test_bar_skin``,
    ``test_bar_seat`` (the bar's interface with the spindle) and ``spindle_nose`` (the spindle's
    faces at z = ``nose`` [m])."""
    everything = tuple(p.name for p in parts)
    return [
        Surface("skin", everything, within=Box((-10, -10, 1e-4), (10, 10, 10)),
                without=tuple(v for p in parts for v in p.voids)),
        Surface("floor_contact", ("bed",), within=Box((-10, -10, -1e-4), (10, 10, 1e-4))),
        Surface("test_bar_skin", ("test_bar",)),
        Surface("test_bar_seat", ("test_bar",), interface_with=("spindle",)),
        Surface("spindle_nose", ("spindle",), within=Box((-1, -1, nose - 1e-4), (1, 1, nose + 1e-4))),
    ]


PROBE_HEIGHTS = (0.03, 0.13)   # [m] above the test bar's tip: ISO 230-3 probe pairs 100 mm apart


def test_bar_nest(tip: float, half_width: float, table_top: float) -> tuple[list[Point], list[Probe]]:
    """The ISO 230-3 five-probe nest round a test bar whose tip is at z = ``tip`` [m] on the
    spindle axis (x = y = 0) and whose faces are ``half_width`` [m] from it: the points ``tool``
    (the tip), ``workpiece`` (on the table top at z = ``table_top``), X1/X2 and Y1/Y2 on the
    bar's -x and -y faces :data:`PROBE_HEIGHTS` above the tip and Z at the tip; and the five
    probes fixed to the workpiece reading them along +x, +y and +z."""
    z1, z2 = tip + PROBE_HEIGHTS[0], tip + PROBE_HEIGHTS[1]
    points = [
        Point("tool", (0.0, 0.0, tip), "test_bar"),
        Point("workpiece", (0.0, 0.0, table_top), "table"),
        Point("X1", (-half_width, 0.0, z1), "test_bar"),
        Point("X2", (-half_width, 0.0, z2), "test_bar"),
        Point("Y1", (0.0, -half_width, z1), "test_bar"),
        Point("Y2", (0.0, -half_width, z2), "test_bar"),
        Point("Z", (0.0, 0.0, tip), "test_bar"),
    ]
    directions = {"X1": (1.0, 0.0, 0.0), "X2": (1.0, 0.0, 0.0), "Y1": (0.0, 1.0, 0.0), "Y2": (0.0, 1.0, 0.0),
                  "Z": (0.0, 0.0, 1.0)}
    return points, [Probe(name, name, d, "workpiece") for name, d in directions.items()]


@dataclass(frozen=True)
class CameraPose:
    """Where a thermal camera stands: ``position`` and ``target`` [m], ``up`` (a direction: the
    image's up), the part it is aimed at (``subject``, where the virtual spots go) and why."""

    name: str
    position: Vec3
    target: Vec3
    up: Vec3 = (0.0, 0.0, 1.0)
    subject: str = ""
    description: str = ""

    @property
    def distance(self) -> float:
        """|target - position| [m]."""
        return float(np.linalg.norm(np.subtract(self.target, self.position)))


@dataclass(frozen=True)
class Finish:
    """The surface finish (an :class:`geometries.finishes.Emissivity`) of the exterior of
    ``parts``, only inside ``within`` when given (a taped patch). Later finishes win where they
    overlap, as parts do."""

    emissivity: object
    parts: tuple[str, ...]
    within: Box | None = None


@dataclass
class Machine:
    """A parametric machine: parts, surfaces, points, probes, its mesh spacings and its contract.

    ``roles`` binds role names of :data:`geometries.regions.ROLES` to regions of this machine (the
    places effects address); ``default_effects`` names the effects a model of this machine has
    unless the user says otherwise; ``air_sites`` are points in the air round the machine where
    sensors read the air temperature (not glued to a part); ``lasers`` are laser triangulation
    sensors (fixed to a fixture, reading a target along a direction, like ``probes``);
    ``strain_gauges`` are FBG strain gauges on the structure; ``max_speed`` is the spindle's maximum
    speed [rpm] (scenarios and measurements beyond it are refused, :mod:`twin.limits`), ``min_speed``
    its slowest steady speed [rpm] where the seed states one (a scenario step between 0, stopped,
    and it is refused; a measured log passes through lower speeds while it ramps).
    """

    name: str
    parts: list[Part]
    surfaces: list[Surface]
    points: list[Point]
    probes: list[Probe]
    tool_point: str
    workpiece_point: str
    sensor_sites: list[str]
    resolutions: dict[str, float]
    description: str = ""
    parameters: dict[str, float] = field(default_factory=dict)
    roles: dict = field(default_factory=dict)
    default_effects: tuple[str, ...] = ()
    air_sites: list[str] = field(default_factory=list)
    max_speed: float | None = None
    min_speed: float | None = None
    camera_poses: list[CameraPose] = field(default_factory=list)
    finishes: list[Finish] = field(default_factory=list)
    axes: list = field(default_factory=list)   # geometries.axes.LinearAxis, commanded by name
    lasers: list[Probe] = field(default_factory=list)   # laser triangulation sensors (as probes)
    strain_gauges: list[StrainGauge] = field(default_factory=list)   # FBG strain gauges
    effect_defaults: dict = field(default_factory=dict)   # {effect: {parameter: SI value}}: this machine's own

    def __post_init__(self):
        check_roles(self.name, self.roles)

    def role(self, name: str):
        """The region bound to role ``name``; KeyError if this machine does not declare it."""
        if name not in self.roles:
            raise KeyError(f"machine {self.name!r} has no role {name!r}")
        return self.roles[name]

    def axis(self, name: str):
        """The :class:`geometries.axes.LinearAxis` called ``name``; KeyError if there is none."""
        for a in self.axes:
            if a.name == name:
                return a
        raise KeyError(f"machine {self.name!r} has no axis {name!r}")

    def part(self, name: str) -> Part:
        for p in self.parts:
            if p.name == name:
                return p
        raise KeyError(f"machine {self.name!r} has no part {name!r}")

    def point(self, name: str) -> Point:
        for p in self.points:
            if p.name == name:
                return p
        raise KeyError(f"machine {self.name!r} has no point {name!r}")

    def surface(self, name: str) -> Surface:
        for s in self.surfaces:
            if s.name == name:
                return s
        raise KeyError(f"machine {self.name!r} has no surface {name!r}")

    def camera_pose(self, name: str) -> CameraPose:
        for p in self.camera_poses:
            if p.name == name:
                return p
        raise KeyError(f"machine {self.name!r} has no camera pose {name!r}")

def material(name: str) -> Material:
    return MATERIALS[name]
