"""Ray casting against a meshed machine's outer surface.

The outer surface is the mesh's boundary facets: faces of cells that no other cell shares, so
faces one part shares with another are not on it. On our rectilinear grid (:mod:`twin.fem.mesh`)
each such facet is an axis-aligned rectangle between consecutive grid lines, and together they
are exactly the boundary of the union of the machine's boxes, whatever the mesh resolution.

Two backends return the first hit of every ray (facet, distance, point):

* ``"grid"`` (numpy, always available, exact for these facets): for each grid plane that carries
  boundary facets, every ray's crossing t = (c - o_a) / d_a of the plane x_a = c is located in the
  plane's 2-D grid by binary search; the nearest crossing (t > 0) that lands on a boundary facet
  is the hit. Cost: O(rays x planes x log(lines)).
* ``"embree"``: the facets split into two triangles each, cast by Intel Embree through trimesh
  (``trimesh.ray.ray_pyembree``), when the optional package ``embreex`` is installed.

``backend="auto"`` takes Embree when it imports, the grid caster otherwise. Occlusion is exact in
both: only the first surface along a ray is seen.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

BACKENDS = ("auto", "grid", "embree")


@dataclass
class OuterSurface:
    """Boundary facets of a mesh as axis-aligned rectangles.

    ``facets`` (nf,) mesh facet ids; ``axis`` (nf,) the axis the facet is flat across; ``normal``
    (nf, 3) outward unit normals; ``owner`` (nf,) the cell each facet bounds; ``lo``/``hi`` (nf, 3)
    the rectangle's corners [m]; ``lines`` the grid coordinates per axis; ``lookup[a]`` an int array
    (planes along a, cells along the next axis, cells along the last axis) of local facet indices
    (-1: no boundary facet there).
    """

    facets: np.ndarray
    axis: np.ndarray
    normal: np.ndarray
    owner: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    lines: list
    lookup: list

    def triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """(vertices (4 nf, 3), faces (2 nf, 3)): each facet as two triangles; triangle k
        belongs to facet k // 2."""
        n = len(self.facets)
        verts = np.empty((n, 4, 3))
        for a in range(3):
            u, v = [b for b in range(3) if b != a]
            sel = self.axis == a
            lo, hi = self.lo[sel], self.hi[sel]
            for c, (cu, cv) in enumerate(((lo, lo), (hi, lo), (hi, hi), (lo, hi))):
                verts[sel, c, a] = lo[:, a]
                verts[sel, c, u] = cu[:, u]
                verts[sel, c, v] = cv[:, v]
        base = 4 * np.arange(n)[:, None]
        faces = np.concatenate([base + [0, 1, 2], base + [0, 2, 3]], axis=1).reshape(-1, 3)
        return verts.reshape(-1, 3), faces


def outer_surface(mm) -> OuterSurface:
    """The boundary facets of ``mm`` (a :class:`twin.fem.mesh.MachineMesh`) as rectangles."""
    mesh = mm.mesh
    facets = mesh.boundary_facets()
    corners = mesh.p[:, mesh.facets[:, facets]]               # (3, 4, nf)
    lo, hi = corners.min(axis=1).T, corners.max(axis=1).T     # (nf, 3)
    axis = np.argmin(hi - lo, axis=1)
    owner = mesh.f2t[0, facets]
    centre = mesh.p[:, mesh.t[:, owner]].mean(axis=1).T
    nf = len(facets)
    normal = np.zeros((nf, 3))
    normal[np.arange(nf), axis] = np.sign(lo[np.arange(nf), axis] - centre[np.arange(nf), axis])
    lines = [np.unique(mesh.p[d]) for d in range(3)]
    lookup = []
    for a in range(3):
        u, v = [b for b in range(3) if b != a]
        table = np.full((len(lines[a]), len(lines[u]) - 1, len(lines[v]) - 1), -1, dtype=np.int64)
        sel = np.flatnonzero(axis == a)
        k = np.searchsorted(lines[a], lo[sel, a])
        i = np.searchsorted(lines[u], lo[sel, u])
        j = np.searchsorted(lines[v], lo[sel, v])
        table[k, i, j] = sel
        lookup.append(table)
    return OuterSurface(facets, axis, normal, owner, lo, hi, lines, lookup)


@dataclass
class Hits:
    """First hits of n rays: ``index`` (n,) into the surface's facets (-1: the ray leaves the
    machine), ``distance`` (n,) [m] along the unit direction (inf on a miss), ``point`` (n, 3) [m]."""

    index: np.ndarray
    distance: np.ndarray
    point: np.ndarray


def cast(surface: OuterSurface, origins: np.ndarray, directions: np.ndarray, backend: str = "auto") -> Hits:
    """First hit of each ray (origins (n, 3) [m], directions (n, 3), normalised here) on
    ``surface``; ``backend`` one of :data:`BACKENDS` (see the module docstring)."""
    if backend not in BACKENDS:
        raise ValueError(f"unknown ray-casting backend {backend!r}; known: {', '.join(BACKENDS)}")
    o = np.broadcast_to(np.asarray(origins, dtype=float), np.shape(directions))
    d = np.asarray(directions, dtype=float)
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    if backend == "embree" or (backend == "auto" and embree_available()):
        index, t = _cast_embree(surface, o, d)
    else:
        index, t = _cast_grid(surface, o, d)
    point = o + np.where(np.isfinite(t), t, 0.0)[:, None] * d
    return Hits(index, t, point)


def embree_available() -> bool:
    """True when trimesh can use Intel Embree (the optional package ``embreex``)."""
    try:
        import embreex  # noqa: F401
    except ImportError:
        return False
    return True


def _cast_grid(surface: OuterSurface, o: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = len(o)
    best_t = np.full(n, np.inf)
    best = np.full(n, -1, dtype=np.int64)
    for a in range(3):
        u, v = [b for b in range(3) if b != a]
        table, lines_u, lines_v = surface.lookup[a], surface.lines[u], surface.lines[v]
        planes = np.flatnonzero((table >= 0).any(axis=(1, 2)))
        moving = np.abs(d[:, a]) > 1e-15
        rays = np.flatnonzero(moving)
        oa, da = o[rays, a], d[rays, a]
        for k in planes:
            t = (surface.lines[a][k] - oa) / da
            front = (t > 1e-12) & (t < best_t[rays])
            if not front.any():
                continue
            r, t = rays[front], t[front]
            i = np.searchsorted(lines_u, o[r, u] + t * d[r, u], side="right") - 1
            j = np.searchsorted(lines_v, o[r, v] + t * d[r, v], side="right") - 1
            inside = (i >= 0) & (i < len(lines_u) - 1) & (j >= 0) & (j < len(lines_v) - 1)
            f = np.full(len(r), -1, dtype=np.int64)
            f[inside] = table[k, i[inside], j[inside]]
            hit = f >= 0
            best_t[r[hit]], best[r[hit]] = t[hit], f[hit]
    return best, best_t


def _cast_embree(surface: OuterSurface, o: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    import trimesh
    from trimesh.ray.ray_pyembree import RayMeshIntersector

    verts, faces = surface.triangles()
    mesh = trimesh.Trimesh(vertices=verts, faces=faces, process=False)
    tri, ray, loc = RayMeshIntersector(mesh).intersects_id(o, d, multiple_hits=False, return_locations=True)
    index = np.full(len(o), -1, dtype=np.int64)
    t = np.full(len(o), np.inf)
    index[ray] = tri // 2
    t[ray] = np.einsum("ij,ij->i", loc - o[ray], d[ray])
    return index, t
