"""Global sparse matrices of a machine mesh, assembled once.

Element matrices come from :mod:`twin.fem.elements`, computed once per distinct (cell size,
material) pair and scattered pair of corners by pair into the sparsity pattern
(:mod:`twin.fem.scatter`: no per-cell copies, so a million-node mesh assembles in bounded memory). Temperatures live on the
temperature dofs ``mm.heat_t`` (the mesh nodes, plus copies where a contact interface splits
the field, see :meth:`twin.fem.mesh.MachineMesh.split_heat`); displacements on the mesh nodes.
Facet matrices of the axis-aligned rectangular faces are in closed form.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from twin.fem import elements
from twin.fem.scatter import Pattern
from twin.fem.mesh import MachineMesh


def cell_materials(mm: MachineMesh, materials: dict | None = None) -> list:
    """Material of each part in ``mm.part_names`` order (``materials`` overrides by part name)."""
    materials = materials or {}
    return [materials.get(name, mm.machine.part(name).material) for name in mm.part_names]


def _groups(mm: MachineMesh):
    """Unique (size, part) combinations: returns (keys (g, 4), inverse (ncells,))."""
    key = np.column_stack([np.round(mm.cell_size, 12), mm.cell_part])
    uniq, inverse = np.unique(key, axis=0, return_inverse=True)
    return uniq, inverse.ravel()


def _scatter(rows_dofs: np.ndarray, cols_dofs: np.ndarray, blocks: np.ndarray, shape) -> sp.csr_matrix:
    r = np.broadcast_to(rows_dofs[:, :, None], blocks.shape).ravel()
    c = np.broadcast_to(cols_dofs[:, None, :], blocks.shape).ravel()
    return sp.coo_matrix((blocks.ravel(), (r, c)), shape=shape).tocsr()


@dataclass
class HeatMatrices:
    """Conductivity K [W/K] and capacity M [J/K] (consistent) on the mesh nodes."""

    K: sp.csr_matrix
    M: sp.csr_matrix


def assemble_heat(mm: MachineMesh, materials: dict | None = None) -> HeatMatrices:
    """Assemble K = sum k int grad N grad N dV and M = sum rho c int N N dV over all cells."""
    mats = cell_materials(mm, materials)
    uniq, inverse = _groups(mm)
    k_ref, m_ref = elements.heat_matrices(uniq[:, :3])
    part = uniq[:, 3].astype(int)
    k_val = np.array([mats[p].conductivity for p in part])
    c_val = np.array([mats[p].volumetric_heat_capacity for p in part])
    pattern = Pattern(mm.heat_t, mm.heat_t, (mm.nheat, mm.nheat))
    K = pattern.assemble(k_ref * k_val[:, None, None], inverse)
    M = pattern.assemble(m_ref * c_val[:, None, None], inverse)
    return HeatMatrices(K, M)


@dataclass
class ElasticMatrices:
    """Stiffness K [N/m] on 3 dofs per node (x, y, z interleaved) and thermal coupling C [N/K]:
    nodal forces from a nodal temperature rise dT are ``C @ dT``."""

    K: sp.csr_matrix
    C: sp.csr_matrix


def _elastic_groups(mm: MachineMesh, materials: dict | None, stiffness: bool):
    """Per group (size, part): condensed stiffness (g, 8, 8, 3, 3) [N/m] (None unless
    ``stiffness``) and coupling (g, 8, 8, 3, 1) [N/K] in node blocks, and each cell's group."""
    mats = cell_materials(mm, materials)
    uniq, inverse = _groups(mm)
    part = uniq[:, 3].astype(int)
    lame = np.array([mats[p].lame for p in part])
    alpha = np.array([mats[p].expansion for p in part])
    k_e, c_e = elements.elastic_matrices(uniq[:, :3], lame[:, 0], lame[:, 1], alpha)
    g = len(uniq)
    k_blocks = k_e.reshape(g, 8, 3, 8, 3).transpose(0, 1, 3, 2, 4) if stiffness else None
    c_blocks = c_e.reshape(g, 8, 3, 8).transpose(0, 1, 3, 2)[..., None]
    return k_blocks, c_blocks, inverse


def assemble_elastic(mm: MachineMesh, materials: dict | None = None) -> ElasticMatrices:
    """Assemble incompatible-mode brick stiffness and thermal coupling (see :mod:`twin.fem.elements`)."""
    k_blocks, c_blocks, inverse = _elastic_groups(mm, materials, stiffness=True)
    t, n = mm.mesh.t, mm.nnodes
    K = Pattern(t, t, (n, n)).assemble(k_blocks, inverse)
    C = Pattern(t, mm.heat_t, (n, mm.nheat)).assemble(c_blocks, inverse)
    return ElasticMatrices(K, C)


def assemble_coupling(mm: MachineMesh, materials: dict | None = None) -> sp.csr_matrix:
    """The thermal coupling C [N/K] of :func:`assemble_elastic` alone (no stiffness)."""
    _, c_blocks, inverse = _elastic_groups(mm, materials, stiffness=False)
    return Pattern(mm.mesh.t, mm.heat_t, (mm.nnodes, mm.nheat)).assemble(c_blocks, inverse)


def assemble_nested_coupling(nested, layout: MachineMesh, materials: dict | None = None) -> sp.csr_matrix:
    """Thermal coupling C [N/K] from the temperature dofs of ``layout`` (a layout of the mesh
    ``nested`` was made from, split or not) to the displacement dofs of the coarser ``nested.coarse``
    (:mod:`twin.fem.nesting`): each fine cell adds int B_coarse^T D m alpha N_fine^T dV over its
    own volume (:func:`twin.fem.elements.nested_coupling`) to its coarse cell's corners."""
    coarse, parent = nested.coarse, nested.parent
    mats = cell_materials(layout, materials)
    offset = layout.mesh.p[:, layout.mesh.t[0]].T - coarse.mesh.p[:, coarse.mesh.t[0, parent]].T
    geometry = np.column_stack([coarse.cell_size[parent], layout.cell_size, offset])
    key = np.column_stack([np.round(geometry, 12), layout.cell_part])
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    part = layout.cell_part[first]
    lame = np.array([mats[p].lame for p in part])
    alpha = np.array([mats[p].expansion for p in part])
    g = geometry[first]                       # each group's own values, not their rounded keys
    blocks = elements.nested_coupling(g[:, 0:3], g[:, 3:6], g[:, 6:9], lame[:, 0], lame[:, 1], alpha)
    blocks = blocks.reshape(len(first), 8, 3, 8).transpose(0, 1, 3, 2)[..., None]
    return Pattern(coarse.mesh.t[:, parent], layout.heat_t, (coarse.nnodes, layout.nheat)).assemble(
        blocks, inverse.ravel())


@dataclass
class FacetMatrices:
    """For a set of facets: H = int N N dA [m2] and r = int N dA [m2] (so r @ T = int T dA)."""

    H: sp.csr_matrix
    r: np.ndarray
    area: float


def _facet_dofs(mm: MachineMesh, facets: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Temperature dofs (nf, 4) of each facet's corners, as seen from the adjacent ``cells``."""
    corners = mm.mesh.facets[:, facets]                       # (4, nf) mesh nodes
    cell_nodes = mm.mesh.t[:, cells]                          # (8, nf)
    pos = np.argmax(cell_nodes[None, :, :] == corners[:, None, :], axis=1)  # (4, nf)
    return mm.heat_t[pos, cells[None, :]].T


def _facet_mass(mm: MachineMesh, facets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Closed-form bilinear mass of rectangles: (nf, 4, 4) [m2] and areas (nf,) [m2].

    int N_a N_b dA = A/36 * (4, 2, 1) for corners a, b that differ in (0, 1, 2) in-plane coordinates.
    """
    xyz = mm.mesh.p.T[mm.mesh.facets[:, facets].T]            # (nf, 4, 3)
    area = mm.facet_areas(facets)
    differ = np.sum(np.abs(xyz[:, :, None, :] - xyz[:, None, :, :]) > 1e-12, axis=3)
    weight = np.choose(np.minimum(differ, 2), [4.0, 2.0, 1.0])
    return weight * (area / 36.0)[:, None, None], area


def assemble_facets(mm: MachineMesh, facets: np.ndarray, weights: np.ndarray | None = None) -> FacetMatrices:
    """Boundary mass matrix and load vector of the given facets (convection, surface flux),
    on the temperature dofs of the cell on each facet's first side; ``weights`` (one per facet)
    scale each facet's share of the load vector r = int w N dA (the mass matrix is unweighted)."""
    facets = np.asarray(facets)
    mass, area = _facet_mass(mm, facets)
    dofs = _facet_dofs(mm, facets, mm.mesh.f2t[0, facets])
    n = mm.nheat
    r = np.zeros(n)
    share = area if weights is None else area * np.asarray(weights, dtype=float)
    np.add.at(r, dofs.ravel(), np.repeat(share / 4.0, 4))
    return FacetMatrices(_scatter(dofs, dofs, mass, (n, n)), r, float(area.sum()))


def assemble_interface(mm: MachineMesh, facets: np.ndarray) -> sp.csr_matrix:
    """Contact matrix of interior facets: int (N_a - N_b)(N_a - N_b) dA [m2] over the facets,
    a the dofs of the first adjacent cell, b of the second; times h_c [W/(m2 K)] it gives the
    heat h_c (T_a - T_b) exchanged across a (split) contact interface."""
    facets = np.asarray(facets)
    mass, _ = _facet_mass(mm, facets)
    a = _facet_dofs(mm, facets, mm.mesh.f2t[0, facets])
    b = _facet_dofs(mm, facets, mm.mesh.f2t[1, facets])
    shape = (mm.nheat, mm.nheat)
    return (_scatter(a, a, mass, shape) + _scatter(b, b, mass, shape)
            - _scatter(a, b, mass, shape) - _scatter(b, a, mass, shape)).tocsr()


def volume_vector(mm: MachineMesh, cells: np.ndarray) -> np.ndarray:
    """b_i = int_V N_i dV over ``cells`` [m3]; a trilinear function integrates to V/8 per corner."""
    b = np.zeros(mm.nheat)
    vol = np.prod(mm.cell_size[cells], axis=1)
    np.add.at(b, mm.heat_t[:, cells].ravel(), np.repeat(vol[None, :] / 8.0, 8, axis=0).ravel())
    return b
