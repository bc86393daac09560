"""Dense virtual surface sensors: a regular grid of temperature points on a machine's exterior.

Seed 001 (ANFIS-FCM) reduced a thermal-camera view of the spindle carrier to 525 "virtual sensor"
spots and let a selection method pick a few of them. :func:`surface_sensor_grid` is the twin's
equivalent: points every ``spacing`` metres on the exterior faces of named parts, each 1 mm inside
the surface (as the machine's own glued sensors are), so that they interpolate from the part's own
cells. Pass the result as ``sensors=`` to :func:`twin.api.simulate`.

Which faces are exterior is decided on the box geometry, not on the mesh: a grid point ``p`` on a
face with outward normal ``n`` is kept when the point ``p - inset n`` belongs to the part (the
*last* part in the machine's list whose boxes contain it, the same overwrite rule the mesher uses)
and the point ``p + inset n`` belongs to no part (air). So faces glued to another part (the carrier
against the column, the column on the bed) and face areas where a later part overwrites this one
(the spindle passing through the carrier) carry no sensors.

Grid on one face: along an edge of length ``L`` [m] there are ``n = max(1, floor(L / spacing))``
points, ``spacing`` apart and centred on the edge (margins ``(L - (n - 1) spacing) / 2 >=
spacing / 2``); a face carries ``n_u * n_v`` candidates before the exterior test. Points are
named ``{part}:{face}:{u:.3f}:{v:.3f}`` with ``face`` one of ``-x +x -y +y -z +z`` and ``u, v`` the
two in-plane coordinates [m] in axis order (for a ``+y`` face: x then z); a part with several boxes
gets ``{part}#{box}`` as its prefix.
"""

from __future__ import annotations

import math

import numpy as np

from geometries.base import Box, Machine, Point

__all__ = ["surface_sensor_grid", "axis_positions", "owner_of", "FACES"]

FACES = ("-x", "+x", "-y", "+y", "-z", "+z")


def axis_positions(lo: float, hi: float, spacing: float) -> np.ndarray:
    """Grid positions [m] on the edge [lo, hi]: ``max(1, floor(L/spacing))`` points, centred."""
    length = hi - lo
    n = max(1, int(math.floor(length / spacing + 1e-9)))
    start = lo + (length - (n - 1) * spacing) / 2.0
    return start + spacing * np.arange(n)


def owner_of(machine: Machine, xyz: np.ndarray) -> np.ndarray:
    """Index into ``machine.parts`` of the part owning each point (n, 3) [m], -1 for air.

    Later parts overwrite earlier ones where boxes overlap (the mesher's rule).
    """
    xyz = np.atleast_2d(np.asarray(xyz, dtype=float))
    owner = np.full(len(xyz), -1, dtype=int)
    for i, part in enumerate(machine.parts):
        for box in part.boxes:
            owner[box.contains(xyz, tol=0.0)] = i
    return owner


def _face_points(box: Box, face: str, spacing: float) -> tuple[np.ndarray, np.ndarray, tuple[int, int]]:
    """Grid points (n, 3) on one face of ``box``, the outward normal (3,) and the in-plane axes."""
    axis = "xyz".index(face[1])
    sign = 1.0 if face[0] == "+" else -1.0
    u_ax, v_ax = [a for a in range(3) if a != axis]
    u = axis_positions(box.lo[u_ax], box.hi[u_ax], spacing)
    v = axis_positions(box.lo[v_ax], box.hi[v_ax], spacing)
    uu, vv = np.meshgrid(u, v, indexing="ij")
    pts = np.empty((uu.size, 3))
    pts[:, axis] = box.hi[axis] if sign > 0 else box.lo[axis]
    pts[:, u_ax], pts[:, v_ax] = uu.ravel(), vv.ravel()
    normal = np.zeros(3)
    normal[axis] = sign
    return pts, normal, (u_ax, v_ax)


def surface_sensor_grid(machine: Machine, parts=("carrier", "column", "test_bar"), spacing: float = 0.05,
                        inset: float = 1e-3) -> list[Point]:
    """Virtual temperature sensors every ``spacing`` [m] on the exterior faces of ``parts``.

    Each point lies ``inset`` [m] (default 1 mm) inside its face. The order is deterministic:
    parts as given, boxes in order, faces ``-x +x -y +y -z +z``, then u, then v. Unknown part names
    raise KeyError; ``spacing`` and ``inset`` must be positive and ``inset`` smaller than half of
    every box side of the parts.
    """
    if spacing <= 0 or inset <= 0:
        raise ValueError(f"spacing and inset must be positive, got {spacing!r}, {inset!r}")
    names = [p.name for p in machine.parts]
    out: list[Point] = []
    for pname in parts:
        part = machine.part(pname)
        index = names.index(pname)
        for b, box in enumerate(part.boxes):
            prefix = pname if len(part.boxes) == 1 else f"{pname}#{b}"
            for face in FACES:
                pts, normal, (u_ax, v_ax) = _face_points(box, face, spacing)
                inner, outer = pts - inset * normal, pts + inset * normal
                keep = (owner_of(machine, inner) == index) & (owner_of(machine, outer) == -1)
                for p in inner[keep]:
                    name = f"{prefix}:{face}:{p[u_ax]:.3f}:{p[v_ax]:.3f}"
                    out.append(Point(name, (float(p[0]), float(p[1]), float(p[2])), pname))
    return out
