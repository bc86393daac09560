"""Structured hexahedral meshing of box-built machines.

The grid is rectilinear: its lines fall on every box face of every part, and each interval
between two such planes is split evenly so that no cell is wider than the spacing ``h`` (or
``part.refine * h`` across the extent of a part that asks for finer cells; the refinement runs
through the whole slab, a tensor grid has no local refinement). A cell belongs to the last part
whose box holds its centre; cells outside every part are dropped, and parts that touch share
nodes (perfectly bonded joints). No external mesher, deterministic. This is the grid of the
finite-difference-element method used for real-time thermal models of machine tools, here with
trilinear (heat) and incompatible-mode Wilson-Taylor (elasticity) bricks (:mod:`twin.fem.elements`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from skfem import MeshHex

from twin import limits
from twin.errors import InputError

# Local node order of a scikit-fem hexahedron (as MeshHex.init_tensor builds it): offsets in
# (i, j, k) of the cell's eight corners.
CORNERS = np.array([[0, 0, 0], [0, 1, 0], [1, 0, 0], [0, 0, 1], [1, 1, 0], [0, 1, 1], [1, 0, 1], [1, 1, 1]])


@dataclass
class MachineMesh:
    """A machine's mesh with names attached.

    ``mesh`` is a scikit-fem MeshHex; ``cell_part[e]`` the index into ``part_names`` of cell e;
    ``facets[name]`` the facet indices of each named surface; ``cell_size[e]`` (dx, dy, dz) [m].
    """

    machine: object
    mesh: MeshHex
    part_names: list[str]
    cell_part: np.ndarray
    cell_size: np.ndarray
    facets: dict[str, np.ndarray]
    spacing: float
    heat_t: np.ndarray | None = None  # (8, ncells) temperature dofs of each cell's corners
    nheat: int = 0                    # number of temperature dofs (>= nnodes when split)

    def __post_init__(self):
        if self.heat_t is None:
            self.heat_t, self.nheat = self.mesh.t, self.mesh.nvertices

    @property
    def nnodes(self) -> int:
        return self.mesh.nvertices

    @property
    def heat_node(self) -> np.ndarray:
        """Mesh node of every temperature dof (nheat,): a split dof maps to the node it copies."""
        node = np.empty(self.nheat, dtype=int)
        node[self.heat_t.ravel()] = self.mesh.t.ravel()
        return node

    def split_heat(self, parts: tuple[str, ...], facets: np.ndarray) -> "MachineMesh":
        """A copy whose temperature field is discontinuous across the interior ``facets``: the
        cells of ``parts`` get their own copies of the nodes on those facets (appended after the
        mesh nodes), so that a contact conductance can couple the two sides. The displacement
        field (``mesh.t``) stays continuous: the joint is bonded mechanically.

        Where a third part, bonded to both sides, meets the interface's edge (a screw's support
        bearing between the screw and the bed, with an air gap along the screw), the nodes that
        part's cells hold are not split: the third part keeps its bond to ``parts``. Splitting
        them would cut a layer of the third part's bond one cell long, an error that shrinks only
        as 1/cells along it (the C-frame's Y screw bearing, one cell long on the default mesh,
        put 3x too much of its heat into the screw; ``tests/test_contact.py``)."""
        cells = self.cells_of(*parts)
        nodes = np.unique(self.mesh.facets[:, facets])
        mine = [self.part_names.index(p) for p in parts]
        sides = self.mesh.f2t[:, facets]
        bonded = np.union1d(mine, self.cell_part[sides[sides >= 0]])   # parts on either side
        touching = np.flatnonzero(np.isin(self.mesh.t, nodes).any(axis=0))
        third = touching[~np.isin(self.cell_part[touching], bonded)]
        nodes = np.setdiff1d(nodes, self.mesh.t[:, third])
        heat_t = self.heat_t.copy()
        sub = heat_t[:, cells]
        on = np.isin(sub, nodes)
        copies = {n: self.nheat + i for i, n in enumerate(np.unique(sub[on]))}
        sub[on] = [copies[n] for n in sub[on]]
        heat_t[:, cells] = sub
        return MachineMesh(self.machine, self.mesh, self.part_names, self.cell_part, self.cell_size, self.facets,
                           self.spacing, heat_t, self.nheat + len(copies))

    @property
    def ncells(self) -> int:
        return self.mesh.nelements

    def cells_of(self, *parts: str) -> np.ndarray:
        """Indices of the cells that belong to any of ``parts``."""
        unknown = set(parts) - set(self.part_names)
        if unknown:
            raise KeyError(f"no parts {sorted(unknown)} in {self.part_names}")
        ids = [self.part_names.index(p) for p in parts]
        return np.flatnonzero(np.isin(self.cell_part, ids))

    def facet_areas(self, facets: np.ndarray) -> np.ndarray:
        """Area (nf,) [m2] of each of the given (axis-aligned, rectangular) facets."""
        corners = self.mesh.p[:, self.mesh.facets[:, facets]]  # (3, 4, nf)
        extent = corners.max(axis=1) - corners.min(axis=1)
        return np.prod(np.sort(extent, axis=0)[1:], axis=0)

    def facet_area(self, facets: np.ndarray) -> float:
        """Total area [m2] of the given facets."""
        return float(np.sum(self.facet_areas(facets)))

    def volume_of(self, cells: np.ndarray) -> float:
        """Total volume [m3] of the given cells."""
        return float(np.sum(np.prod(self.cell_size[cells], axis=1)))


def grid_plan(bounds: list[float], spacing: float, local: list[tuple[float, float, float]] = ()):
    """The planes through every bound (sorted) and the number of cells (floats, >= 1) each interval
    between two of them is split into by :func:`grid_lines`: nothing allocated per cell, so the
    size of a grid is known before it is drawn."""
    planes = np.unique(np.round(np.asarray(bounds, dtype=float), 9))
    counts = np.empty(max(len(planes) - 1, 0))
    for k, (a, b) in enumerate(zip(planes[:-1], planes[1:])):
        h = min([spacing] + [s for lo, hi, s in local if lo <= a + 1e-9 and b <= hi + 1e-9])
        counts[k] = max(1.0, np.ceil((b - a) / h - 1e-9))
    return planes, counts


def grid_lines(bounds: list[float], spacing: float, local: list[tuple[float, float, float]] = ()) -> np.ndarray:
    """Sorted grid coordinates through every bound, no interval wider than ``spacing`` [m], nor
    wider than s inside any ``local`` span (a, b, s) (a part's extent with its finer spacing)."""
    planes, counts = grid_plan(bounds, spacing, local)
    lines = [planes[:1]] + [np.linspace(a, b, int(n) + 1)[1:] for a, b, n in zip(planes[:-1], planes[1:], counts)]
    return np.concatenate(lines)


def refine_factors(part) -> tuple[float, float, float]:
    """The part's cell-size factors along x, y, z (``part.refine``: one number or three)."""
    r = part.refine
    return tuple(float(v) for v in r) if isinstance(r, (tuple, list)) else (float(r),) * 3


def part_planes(machine, axis: int) -> np.ndarray:
    """Sorted coordinates [m] along ``axis`` of every box and void face of every part: the planes
    every grid of the machine has a line on."""
    bounds = [c for part in machine.parts for box in part.boxes + part.voids for c in (box.lo[axis], box.hi[axis])]
    return np.unique(np.round(np.asarray(bounds, dtype=float), 9))


def _local_spans(machine, spacing: float, d: int) -> list[tuple[float, float, float]]:
    """The (lo, hi, finer spacing) spans along axis ``d`` of the parts with ``refine < 1``."""
    return [(box.lo[d], box.hi[d], refine_factors(part)[d] * spacing)
            for part in machine.parts if refine_factors(part)[d] < 1 for box in part.boxes]


def grid_axes(machine, spacing: float) -> list[np.ndarray]:
    """The grid lines along x, y, z of :func:`build_mesh` (no cell wider than ``spacing`` [m], or
    ``part.refine * spacing`` across a refined part)."""
    return [grid_lines(part_planes(machine, d), spacing, _local_spans(machine, spacing, d)) for d in range(3)]


def estimated_nodes(machine, spacing: float) -> float:
    """An upper estimate of the nodes of :func:`build_mesh` at ``spacing`` [m], from the grid plan
    alone (:func:`grid_plan`, nothing allocated per node): the grid nodes inside each box of each
    part, summed (every mesh node lies in a box; nodes shared by touching boxes count twice and
    voids are not taken off: 2-20 % over on the bundled machines)."""
    cumulative = []
    for d in range(3):
        planes, counts = grid_plan(part_planes(machine, d), spacing, _local_spans(machine, spacing, d))
        cumulative.append((planes, np.concatenate([[0.0], np.cumsum(counts)])))
    total = 0.0
    with np.errstate(over="ignore", invalid="ignore"):      # a vanishing spacing: inf nodes, refused
        for part in machine.parts:
            for box in part.boxes:
                lines = 1.0
                for d, (planes, cells) in enumerate(cumulative):
                    i0, i1 = np.searchsorted(planes, np.round([box.lo[d], box.hi[d]], 9))
                    lines *= cells[i1] - cells[i0] + 1.0
                total += lines
    return total


def check_spacing(machine, spacing, source: str = "command line", field: str = "spacing") -> float:
    """``spacing`` [m] as a float when it is a finite positive number whose mesh of ``machine``
    stays within :data:`twin.limits.MAX_NODES` nodes (:func:`estimated_nodes`), else
    :class:`twin.errors.InputError` naming ``field``."""
    if not limits.is_finite_number(spacing) or not spacing > 0:
        raise InputError(source, field, f"a mesh spacing is a finite positive length in m, got {spacing!r}")
    spacing = float(spacing)
    extent = max(float(np.ptp(part_planes(machine, d))) for d in range(3))
    if spacing > extent:
        raise InputError(source, field, f"a spacing of {spacing:g} m is wider than {machine.name} ({extent:.3g} m at "
                                        f"its largest): the mesh would hold only the parts' boundary lines")
    limits.check_mesh_nodes(estimated_nodes(machine, spacing), spacing, machine.name, source, field)
    return spacing


def build_mesh(machine, spacing: float) -> MachineMesh:
    """Mesh ``machine`` with cells no wider than ``spacing`` [m], and no wider than
    ``part.refine * spacing`` across a part with ``refine < 1`` (per axis if ``refine`` is three
    numbers): a thin test bar whose fin length sqrt(k A / h P) is a few cm, a bearing zone whose
    heat peaks inside it (see module docstring). A spacing that is not a finite positive number,
    or whose mesh would exceed :data:`twin.limits.MAX_NODES` nodes, raises
    :class:`twin.errors.InputError` before anything is allocated (:func:`check_spacing`)."""
    from twin.limits import check_machine

    check_machine(machine, "command line")       # a name or None failed as an AttributeError
    spacing = check_spacing(machine, spacing)
    return mesh_on_lines(machine, grid_axes(machine, spacing), spacing)


def mesh_on_lines(machine, axes: list[np.ndarray], spacing: float) -> MachineMesh:
    """The machine's cells on the rectilinear grid ``axes`` (three sorted arrays of line
    coordinates [m], a line on every part plane): a cell belongs to the last part whose box holds
    its centre. ``spacing`` [m] is recorded as the mesh's nominal cell size."""
    centres = [0.5 * (a[1:] + a[:-1]) for a in axes]
    shape = tuple(len(c) for c in centres)
    ci, cj, ck = np.meshgrid(*[np.arange(n) for n in shape], indexing="ij")
    ijk = np.stack([ci.ravel(), cj.ravel(), ck.ravel()], axis=1)
    xyz = np.stack([centres[d][ijk[:, d]] for d in range(3)], axis=1)
    label = np.full(len(ijk), -1)
    for pid, part in enumerate(machine.parts):
        for box in part.boxes:
            label[box.contains(xyz, tol=-1e-12)] = pid
        for void in part.voids:
            label[void.contains(xyz, tol=-1e-12) & (label == pid)] = -1
    keep = label >= 0
    ijk, label = ijk[keep], label[keep]

    # corner node indices on the full lattice, then compress to the used ones
    dims = np.array([len(a) for a in axes])
    corner_ijk = ijk[:, None, :] + CORNERS[None, :, :]
    lattice_id = np.ravel_multi_index(corner_ijk.reshape(-1, 3).T, dims)
    used, t = np.unique(lattice_id, return_inverse=True)
    t = t.reshape(-1, 8).T
    node_ijk = np.array(np.unravel_index(used, dims))
    p = np.stack([axes[d][node_ijk[d]] for d in range(3)])
    mesh = MeshHex(np.ascontiguousarray(p), np.ascontiguousarray(t))

    sizes = np.stack([np.diff(axes[d])[ijk[:, d]] for d in range(3)], axis=1)
    part_names = [part.name for part in machine.parts]
    mm = MachineMesh(machine, mesh, part_names, label, sizes, {}, spacing)
    mm.facets = {s.name: _surface_facets(mm, s) for s in machine.surfaces}
    subdomains = {name: mm.cells_of(name) for name in part_names}
    mm.mesh = mesh.with_subdomains(subdomains).with_boundaries(
        {k: v for k, v in mm.facets.items() if len(v)})
    return mm


def _surface_facets(mm: MachineMesh, surface) -> np.ndarray:
    mesh = mm.mesh
    ids = [mm.part_names.index(p) for p in surface.parts]
    f2t = mesh.f2t
    if surface.interface_with:
        other = [mm.part_names.index(p) for p in surface.interface_with]
        inner = np.flatnonzero(f2t[1] >= 0)
        a, b = mm.cell_part[f2t[0, inner]], mm.cell_part[f2t[1, inner]]
        hit = (np.isin(a, ids) & np.isin(b, other)) | (np.isin(b, ids) & np.isin(a, other))
        chosen = inner[hit]
    else:
        outer = mesh.boundary_facets()
        chosen = outer[np.isin(mm.cell_part[f2t[0, outer]], ids)]
    if (surface.within is not None or surface.without) and len(chosen):
        mid = mesh.p[:, mesh.facets[:, chosen]].mean(axis=1).T
        keep = np.ones(len(chosen), dtype=bool) if surface.within is None else surface.within.contains(mid)
        for box in surface.without:
            keep &= ~box.contains(mid)
        chosen = chosen[keep]
    if len(chosen) == 0:
        raise ValueError(f"surface {surface.name!r} of machine {mm.machine.name!r} has no faces")
    return np.sort(chosen)


def mesh_machine(machine, resolution: str = "default") -> MachineMesh:
    """The structured hexahedral mesh of ``machine`` at one of its named ``resolutions``
    (:func:`build_mesh` with that spacing). Unknown resolutions raise KeyError naming the known ones."""
    if resolution not in machine.resolutions:
        raise KeyError(f"unknown mesh resolution {resolution!r}; known: {', '.join(machine.resolutions)}")
    return build_mesh(machine, machine.resolutions[resolution])
