"""Regions and roles: where on a machine a load acts or an instrument looks, in words and geometry.

A *region* describes a set of cells (a volume) or boundary faces (a surface) by name and geometry,
never by mesh numbers; :mod:`twin.fem.regions` turns it into cells or facets of a mesh:

* :class:`Parts` — the cells of the named parts (volume), or their faces open to the air and
  the floor (surface);
* :class:`Named` — one of the machine's named surfaces (surface);
* :class:`Facing` — the faces of a surface region whose outward normal is ``"+x"``, ``"-y"`` ...;
* :class:`Band` — the cells or faces of a region whose centre's coordinate along ``axis`` lies in
  [lo, hi] [m] (a height band, the top of a column);
* :class:`InBox` — the cells or faces of a region whose centre lies in a box;
* :class:`Union` — several regions together.

A *role* is a name from :data:`ROLES` that a machine binds to a region (``Machine.roles``): the
contract between machines and effects. Effects address roles (``"spindle.front_bearing"``), so
one effect serves every machine that declares the roles it needs; a machine without one is told
so by name. The vocabulary is closed: a machine declaring an unknown role is an error, so a typo
never leaves an effect silently unplaced.
"""

from __future__ import annotations

from dataclasses import dataclass

AXES = {"x": 0, "y": 1, "z": 2}
DIRECTIONS = ("+x", "-x", "+y", "-y", "+z", "-z")


@dataclass(frozen=True)
class Parts:
    """Cells of the named parts (volume) or their exterior faces (surface)."""

    names: tuple[str, ...]


@dataclass(frozen=True)
class Named:
    """A named :class:`geometries.base.Surface` of the machine (surface only)."""

    surface: str


@dataclass(frozen=True)
class Facing:
    """Faces of the surface region ``base`` whose outward normal is ``direction`` ("+x" ... "-z")."""

    base: object
    direction: str

    def __post_init__(self):
        if self.direction not in DIRECTIONS:
            raise ValueError(f"direction {self.direction!r} is not one of {', '.join(DIRECTIONS)}")


@dataclass(frozen=True)
class Band:
    """Cells or faces of ``base`` whose centre's coordinate along ``axis`` lies in [lo, hi] [m]."""

    base: object
    axis: str
    lo: float
    hi: float

    def __post_init__(self):
        if self.axis not in AXES or not self.hi > self.lo:
            raise ValueError(f"band needs an axis x, y or z and hi > lo, got {self.axis!r} [{self.lo}, {self.hi}]")


@dataclass(frozen=True)
class InBox:
    """Cells or faces of ``base`` whose centre lies inside ``box`` (a :class:`geometries.base.Box`)."""

    base: object
    box: object


@dataclass(frozen=True)
class Union:
    """Every cell or face of any of ``regions``."""

    regions: tuple


# The role vocabulary: name -> (kind, meaning). "volume" roles resolve to cells, "surface" roles
# to boundary faces, "interface" roles to interior faces between two parts, "parts" roles to the
# parts on one side of an interface.
ROLES: dict[str, tuple[str, str]] = {
    "spindle.front_bearing": ("volume", "the front spindle bearing zone, where bearing friction heat arises"),
    "spindle.rear_bearing": ("volume", "the rear spindle bearing zone"),
    "spindle.motor": ("volume", "the spindle motor's body"),
    "spindle.belt_contact": ("surface", "the rim of the spindle's belt pulley, where belt friction heat enters"),
    "spindle.rotating": ("surface", "surfaces turning with the spindle in the air: the test bar and the spindle nose"),
    "spindle.jacket": ("interface", "the cartridge/housing interface where a cooling jacket sits"),
    "test_bar.seat": ("interface", "the contact between the spindle nose and the test bar"),
    "test_bar.body": ("parts", "the test bar's parts: the side of the seat that gets its own temperatures"),
    "structure.skin": ("surface", "every face of the structure open to the room air"),
    "structure.front": ("surface", "the skin facing the operator's side and the hall door"),
    "structure.open_front": ("surface", "the front skin a draft from the hall door reaches (not behind way covers)"),
    "structure.rear": ("surface", "the skin facing the rear wall and its windows"),
    "floor.contact": ("surface", "the foot of the bed standing on the floor"),
    "cabinet.face": ("surface", "the structure face an electrical cabinet stands beside"),
    "z_drive.top": ("volume", "where the Z motor and its brake sit, holding the spindle carrier"),
    "c_axis.motor": ("volume", "the C-axis (rotary) drive motor's body, where its losses arise"),
    "c_axis.bearing": ("volume", "the C-axis bearing zone, where its friction heat arises"),
}


# The ball-screw feed drive of each linear axis (geometries.axes.FeedDrive): role
# ``feed_drive.<axis>.<what>``, axis x, y or z (the axis's name in lower case).
FEED_DRIVE_ROLES = {
    "screw": ("parts", "the ball screw, its own steel part, on whose cells the nut's heat travels"),
    "screw_gap": ("interface", "the screw's faces towards the structure between its bearings (an air gap)"),
    "structure_side": ("parts", "the structure across the screw's air gap (gets its own temperatures there)"),
    "front_bearing": ("volume", "the screw's fixed support bearing at the motor end"),
    "rear_bearing": ("volume", "the screw's support bearing at the far end"),
    "motor": ("volume", "where the feed motor's losses enter the structure (its flange)"),
    "nut_body": ("volume", "the nut housing on the moving body (heat moves with the body)"),
    "guideways": ("volume", "the guideway rails along the travel, where the carriages run"),
    "carriages": ("volume", "the guideway carriages on the moving body"),
}
DRIVEN_AXES = ("x", "y", "z")


def feed_drive_role(axis: str, what: str) -> str:
    """The role name of ``what`` (a key of :data:`FEED_DRIVE_ROLES`) of axis ``axis`` ("X" or "x")."""
    if what not in FEED_DRIVE_ROLES:
        raise KeyError(f"no feed-drive role {what!r}; known: {', '.join(FEED_DRIVE_ROLES)}")
    return f"feed_drive.{axis.lower()}.{what}"


ROLES.update({feed_drive_role(a, what): (kind, f"{a.upper()} axis: {doc}")
              for a in DRIVEN_AXES for what, (kind, doc) in FEED_DRIVE_ROLES.items()})


def check_roles(machine_name: str, roles: dict) -> None:
    """Raise ValueError naming the machine and the role if a role is not in :data:`ROLES`."""
    unknown = sorted(set(roles) - set(ROLES))
    if unknown:
        raise ValueError(f"machine {machine_name!r} declares unknown role(s) {', '.join(unknown)}; "
                         f"known: {', '.join(ROLES)}")


# The region vocabulary users write (custom effects, the diagnosis's map): a part's name is its
# cells (a volume) or, for a surface load, its faces open to the air and the floor; "part.+x" is
# the part's outer faces whose outward normal is +x (any of DIRECTIONS).
def region_by_name(machine, name: str, surface: bool) -> object:
    """The region a user names: ``"column"`` (the part's cells, or its outer faces when
    ``surface``) or ``"column.+x"`` (the part's outer faces facing +x; surface only). ValueError
    naming the known parts and directions otherwise."""
    part, _, direction = str(name).partition(".")
    known = [p.name for p in machine.parts]
    if part not in known:
        raise ValueError(f"unknown part {part!r} of {machine.name}; known: {', '.join(known)}")
    if not direction:
        return Parts((part,))
    if direction not in DIRECTIONS:
        raise ValueError(f"{name!r}: direction {direction!r} is not one of {', '.join(DIRECTIONS)}")
    if not surface:
        raise ValueError(f"{name!r} is a set of faces; a volume load needs a part's name")
    return Facing(Parts((part,)), direction)


def partition(machine) -> dict[str, tuple[str, object]]:
    """The machine's fixed partition into named regions, name -> (kind, region): each part's cells
    (``"column"``, kind ``"volume"``) and each part's outer faces by direction (``"column.+x"``,
    kind ``"surface"``). A face region may be empty on a mesh (a part buried in another); the
    caller drops those."""
    out: dict[str, tuple[str, object]] = {}
    for p in machine.parts:
        out[p.name] = ("volume", Parts((p.name,)))
        for d in DIRECTIONS:
            out[f"{p.name}.{d}"] = ("surface", Facing(Parts((p.name,)), d))
    return out
