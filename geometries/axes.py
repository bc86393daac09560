"""Linear axes of a machine: travel, feedback kind and, where the machine has one, the ball-screw
feed drive (its steel screw, support bearings, motor, nut and guideways) as parts and regions.

A machine declares its axes in ``Machine.axes``; a scenario commands them by name
(:mod:`twin.motion`). The drive's parts are *not* in the machine's default mesh (the spindle
tests' meshes stay as they were); :func:`with_feed_drives` adds them when a scenario moves an
axis. Coordinates in metres, positions along the axis in metres of commanded travel.

The commanded position p of an axis puts its nut (and the moving body) at machine coordinate
``nut_at_zero + p`` along ``direction``; the mesh is built at the reference pose ``p_ref``
(:mod:`twin.motion` says what that costs).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

FEEDBACK = ("semi-closed", "closed")


@dataclass(frozen=True)
class FeedDrive:
    """A ball-screw drive's description: ``parts`` (the screw and anything else of its own, added
    to the machine), ``surfaces``, the regions of the ``roles`` it binds (see
    :data:`geometries.regions.ROLES`, the axis's ``feed_drive.<axis>.*`` roles), sensor ``points``,
    ``screw_axis`` (x, z) [m]: the screw's centre line across ``direction`` (the two other machine
    coordinates, in x, y, z order), ``fixed_end`` [m]: the machine coordinate along the axis of the
    fixed (thrust) bearing, ``lead`` [m] per revolution and ``nut_offset`` (x, z) [m] from the
    screw's line to the point where the nut housing holds the moving body."""

    parts: tuple = ()
    surfaces: tuple = ()
    roles: dict = field(default_factory=dict)
    points: tuple = ()
    screw_axis: tuple[float, float] = (0.0, 0.0)
    fixed_end: float = 0.0
    lead: float = 0.01
    nut_offset: tuple[float, float] = (0.0, 0.0)   # [m] from the screw's line to where the nut holds the body
    effects: tuple[str, ...] = ()   # effects added to the machine's default set with the drive


@dataclass(frozen=True)
class Scale:
    """A linear scale's mounting: its ``line`` (the two machine coordinates across the axis, in
    x, y, z order) [m] on the ``carrier`` part whose expansion its graduations follow, and the
    ``head`` (the same two coordinates) [m] of its read head on the moving body."""

    line: tuple[float, float]
    carrier: str
    head: tuple[float, float]


@dataclass(frozen=True)
class LinearAxis:
    """A linear axis: ``name`` ("X", "Y", "Z"), the machine ``direction`` it moves along ("x",
    "y", "z"), its ``travel`` (lo, hi) [m] of commanded position, ``feedback`` ("semi-closed":
    rotary encoder on the motor, the screw's expansion between its fixed bearing and the nut
    becomes positioning error; "closed": a linear scale, whose carrier's expansion does),
    ``moving`` (the parts that move with it), ``nut_at_zero`` [m] (machine coordinate of the nut,
    or of a closed loop's read head, at commanded position 0), ``p_ref`` [m] (the commanded
    position of the mesh's pose), its ``drive`` (a :class:`FeedDrive`, or None when the machine
    does not model it) and, closed loop, its ``scale`` (a :class:`Scale`).

    ``screw_on_body``: the screw and the guide rails ride on the moving body and the nut and the
    guide blocks stand in the structure (a ram: the gantry's Z screw hangs on the ram, its nut is
    bolted to the carriage). ``nut_at_zero`` is then the nut's fixed machine coordinate, and
    :meth:`nut_coordinate` the point of the screw (and of the rails) under it in the mesh, where
    the body stands at ``p_ref``: it moves the other way, nut_at_zero - (p - p_ref)."""

    name: str
    direction: str
    travel: tuple[float, float]
    feedback: str
    moving: tuple[str, ...] = ()
    nut_at_zero: float = 0.0
    p_ref: float = 0.0
    drive: FeedDrive | None = None
    scale: Scale | None = None
    screw_on_body: bool = False

    def __post_init__(self):
        if self.feedback not in FEEDBACK:
            raise ValueError(f"axis {self.name}: feedback {self.feedback!r} is not one of {', '.join(FEEDBACK)}")
        if self.direction not in ("x", "y", "z") or not self.travel[1] > self.travel[0]:
            raise ValueError(f"axis {self.name}: needs a direction x, y or z and travel hi > lo")

    def nut_coordinate(self, p):
        """Machine coordinate [m] along ``direction``, in the mesh, of the screw point under the
        nut at commanded position(s) ``p`` [m]: nut_at_zero + p when the nut rides on the body,
        nut_at_zero - (p - p_ref) when the screw does (``screw_on_body``)."""
        if self.screw_on_body:
            return self.nut_at_zero - (np.asarray(p, float) - self.p_ref)
        return self.nut_at_zero + p


def carried_sign(machine, axis: LinearAxis) -> float:
    """+1 when ``axis`` moves the tool point's part, -1 when it moves the workpiece point's (0 when
    it moves both or neither): the sign with which the axis's own positioning error, along its
    direction, enters the tool's position relative to the workpiece."""
    parts = {p.name: p.part for p in machine.points}
    return float(parts[machine.tool_point] in axis.moving) - float(parts[machine.workpiece_point] in axis.moving)


def with_feed_drives(machine, axes=None):
    """A copy of ``machine`` with the parts, surfaces, roles, sensor points and default effects of
    the :class:`FeedDrive` of every axis named in ``axes`` (all axes that have one when None; the
    machine itself when none is left to add). A scenario adds only the drives of the axes it
    commands (:func:`twin.motion.machine_for`), so a spindle test's mesh has no drive parts and
    a Y-only scenario no X or Z screw."""
    have = {p.name for p in machine.parts}
    drives = [a.drive for a in machine.axes if a.drive is not None and (axes is None or a.name in axes)
              and not any(p.name in have for p in a.drive.parts)]   # not added already
    if not drives:
        return machine
    from geometries.base import Machine
    parts = list(machine.parts) + [p for d in drives for p in d.parts]
    surfaces = list(machine.surfaces) + [s for d in drives for s in d.surfaces]
    points = list(machine.points) + [p for d in drives for p in d.points]
    roles = dict(machine.roles)
    for d in drives:
        roles.update(d.roles)
    sites = list(machine.sensor_sites) + [p.name for d in drives for p in d.points if p.part != "air"]
    air = list(machine.air_sites) + [p.name for d in drives for p in d.points if p.part == "air"]
    effects = tuple(dict.fromkeys(tuple(machine.default_effects) + tuple(e for d in drives for e in d.effects)))
    return Machine(**{**machine.__dict__, "parts": parts, "surfaces": surfaces, "points": points, "roles": roles,
                      "sensor_sites": sites, "air_sites": air, "default_effects": effects})


def at_pose(machine, axis_name: str, p: float):
    """A copy of ``machine`` built with axis ``axis_name`` at commanded position ``p`` [m]
    instead of its reference pose: the axis's moving parts, the points on them and the regions
    (boxes) of roles on them shifted by p - p_ref along the axis. For checking what the single
    reference pose costs (:mod:`twin.motion`); the axis's own drive stays where it is (a drive that
    rides on the axis, the C-frame's X drive on the Y saddle, moves with it when its parts are
    among the axis's moving parts; its :class:`FeedDrive` line data do not)."""
    from dataclasses import replace

    from geometries.base import Box, Machine, Point
    from geometries.regions import InBox, Parts, Union

    axis = machine.axis(axis_name)
    k = "xyz".index(axis.direction)
    delta = [0.0, 0.0, 0.0]
    delta[k] = p - axis.p_ref
    move = set(axis.moving)

    def shift(box):
        return Box(tuple(np.add(box.lo, delta)), tuple(np.add(box.hi, delta)))

    def region(r):
        if isinstance(r, InBox) and isinstance(r.base, Parts) and set(r.base.names) <= move:
            return InBox(r.base, shift(r.box))
        if isinstance(r, Union):
            return Union(tuple(region(x) for x in r.regions))
        return r

    parts = [replace(q, boxes=tuple(shift(b) for b in q.boxes), voids=tuple(shift(b) for b in q.voids))
             if q.name in move else q for q in machine.parts]
    points = [Point(q.name, tuple(np.add(q.xyz, delta)), q.part) if q.part in move else q for q in machine.points]
    surfaces = [replace(s, within=shift(s.within)) if s.within is not None and set(s.parts) <= move else s
                for s in machine.surfaces]
    roles = {name: region(r) for name, r in machine.roles.items()}
    axes = [replace(a, p_ref=p) if a.name == axis_name else a for a in machine.axes]
    return Machine(**{**machine.__dict__, "parts": parts, "points": points, "surfaces": surfaces, "roles": roles,
                      "axes": axes})
