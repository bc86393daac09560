"""An elastic mesh coarser than the temperature mesh, nested in it.

The drift outputs are smooth functionals of the displacement, while the temperature field has
steep gradients near its sources: a large model can solve the heat equation on a fine grid and
the elasticity on a coarser one. The coarse grid keeps every part plane of the fine grid and
every ``factor``-th line between two planes (evenly spread when an interval does not divide), so
each coarse cell is a union of fine cells of one part. The thermal load of a fine temperature
field on the coarse displacements is integrated exactly on the fine cells
(:func:`twin.fem.assembly.assemble_nested_coupling`): a uniform or linear temperature rise gives
the same free expansion and bending on either grid, and only the displacement's discretisation
is coarser.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from twin.fem.mesh import CORNERS, MachineMesh, grid_axes, mesh_on_lines, part_planes


@dataclass
class NestedMesh:
    """``coarse`` nested in the temperature mesh it was made from: ``parent[e]`` is the coarse cell
    that holds that mesh's cell e (and the cell e of any layout of it)."""

    coarse: MachineMesh
    parent: np.ndarray


def split_interval(n: int, factor: int) -> list[int]:
    """Where to cut n fine intervals into about n / factor coarse ones: the cut indices 0 .. n,
    symmetric about the middle (cut k and cut m - k mirror each other), so that a grid symmetric
    about a plane stays symmetric (an asymmetric split gives a symmetric machine a spurious
    drift across its plane of symmetry). m = ceil(n / factor), plus one when n is odd and m even
    (a middle cut would fall inside a fine interval)."""
    m = int(np.ceil(n / factor))
    if n % 2 and not m % 2:
        m += 1
    half = [int(np.floor(k * n / m + 0.5)) for k in range(m // 2 + 1)]
    return sorted(set(half) | {n - c for c in half})


def coarser_lines(lines: np.ndarray, planes: np.ndarray, factor: int) -> np.ndarray:
    """Every plane of ``lines`` and, between two planes, the cuts of :func:`split_interval`."""
    on_plane = np.isclose(lines[:, None], planes[None, :], rtol=0.0, atol=1e-9).any(axis=1)
    ends = np.flatnonzero(on_plane)
    keep = [ends[0]]
    for a, b in zip(ends[:-1], ends[1:]):
        keep += [a + c for c in split_interval(int(b - a), factor)[1:]]
    return lines[np.asarray(keep)]


def coarsen(mm: MachineMesh, factor: int) -> NestedMesh:
    """The mesh of ``mm.machine`` on every ``factor``-th line of ``mm``'s grid (module docstring).
    ``factor`` 1 gives the same grid. Raises ValueError if ``mm`` is not the machine's grid at its
    spacing (a coarse grid is defined only on the lines :func:`twin.fem.mesh.grid_axes` draws)."""
    if int(factor) != factor or factor < 1:
        raise ValueError(f"the elastic coarsening must be a whole number >= 1, got {factor!r}")
    machine = mm.machine
    axes = grid_axes(machine, mm.spacing)
    lattice = [np.unique(mm.mesh.p[d]) for d in range(3)]
    if any(not np.isin(np.round(lattice[d], 9), np.round(axes[d], 9)).all() for d in range(3)):
        raise ValueError("the mesh is not the machine's grid at its spacing: it cannot be coarsened")
    coarse_axes = [coarser_lines(axes[d], part_planes(machine, d), int(factor)) for d in range(3)]
    coarse = mesh_on_lines(machine, coarse_axes, mm.spacing * factor)
    parent = _parents(mm, coarse, coarse_axes)
    if not np.array_equal(coarse.cell_part[parent], mm.cell_part):
        raise ValueError("a coarse cell holds fine cells of two parts: the grids are not nested")
    return NestedMesh(coarse, parent)


def _cell_index(mm: MachineMesh, axes: list[np.ndarray]) -> np.ndarray:
    """(ncells, 3) index of each cell's interval along each of ``axes`` (from its centre)."""
    lo, hi = mm.mesh.p[:, mm.mesh.t[0]], mm.mesh.p[:, mm.mesh.t[7]]
    centre = 0.5 * (lo + hi)
    return np.stack([np.searchsorted(axes[d], centre[d]) - 1 for d in range(3)], axis=1)


def _parents(fine: MachineMesh, coarse: MachineMesh, coarse_axes: list[np.ndarray]) -> np.ndarray:
    """The coarse cell holding each fine cell."""
    dims = tuple(len(a) - 1 for a in coarse_axes)
    key_c = np.ravel_multi_index(_cell_index(coarse, coarse_axes).T, dims)
    key_f = np.ravel_multi_index(_cell_index(fine, coarse_axes).T, dims)
    order = np.argsort(key_c)
    pos = np.searchsorted(key_c[order], key_f)
    found = order[np.minimum(pos, len(order) - 1)]
    if not np.array_equal(key_c[found], key_f):
        raise ValueError("a fine cell lies in no coarse cell: the grids are not nested")
    return found


def prolongation(nested: NestedMesh, layout: MachineMesh) -> sp.csr_matrix:
    """Trilinear interpolation (layout.nheat, coarse nodes) of a field on the coarse grid's nodes
    onto the temperature dofs of ``layout`` (the mesh ``nested`` was made from, split or not):
    each dof takes the value at its node of the coarse cell that holds one of its cells,

        u(x) = sum_k N_k(xi) u_k,  xi = (x - x_low) / H  in the coarse cell [x_low, x_low + H],

    so a field trilinear on every coarse cell (a constant, a linear field) is reproduced exactly
    and every row sums to 1. A dof split by a contact takes its value from its own side's cell;
    the coarse field is continuous there (the coarse grid has no split)."""
    coarse, mesh = nested.coarse, layout.mesh
    dofs, first = np.unique(layout.heat_t.ravel(), return_index=True)
    corner, cell = np.unravel_index(first, layout.heat_t.shape)
    holder = nested.parent[cell]
    low = coarse.mesh.p[:, coarse.mesh.t[0, holder]]
    xi = (mesh.p[:, mesh.t[corner, cell]] - low) / coarse.cell_size[holder].T         # (3, ndofs) in [0, 1]
    weights = np.ones((8, len(dofs)))
    for k in range(8):
        for d in range(3):
            weights[k] *= xi[d] if CORNERS[k, d] else 1.0 - xi[d]
    rows = np.broadcast_to(dofs, weights.shape)
    cols = coarse.mesh.t[:, holder]
    nonzero = weights > 1e-14
    return sp.csr_matrix((weights[nonzero], (rows[nonzero], cols[nonzero])), shape=(layout.nheat, coarse.nnodes))
