"""Global sparse matrices of a machine mesh, assembled once.

Element matrices come from :mod:`twin.elements`, computed once per distinct (cell size,
material) pair and scattered with one COO -> CSR conversion. Facet (convection) matrices use
scikit-fem's FacetBasis on the same trilinear element, so that node i is dof i everywhere.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import BilinearForm, ElementHex1, FacetBasis, LinearForm, asm

from twin import elements
from twin.mesh import MachineMesh


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
    t = mm.mesh.t.T
    n = mm.nnodes
    K = _scatter(t, t, (k_ref * k_val[:, None, None])[inverse], (n, n))
    M = _scatter(t, t, (m_ref * c_val[:, None, None])[inverse], (n, n))
    return HeatMatrices(K, M)


@dataclass
class ElasticMatrices:
    """Stiffness K [N/m] on 3 dofs per node (x, y, z interleaved) and thermal coupling C [N/K]:
    nodal forces from a nodal temperature rise dT are ``C @ dT``."""

    K: sp.csr_matrix
    C: sp.csr_matrix


def assemble_elastic(mm: MachineMesh, materials: dict | None = None) -> ElasticMatrices:
    """Assemble incompatible-mode brick stiffness and thermal coupling (see :mod:`twin.elements`)."""
    mats = cell_materials(mm, materials)
    uniq, inverse = _groups(mm)
    part = uniq[:, 3].astype(int)
    lame = np.array([mats[p].lame for p in part])
    alpha = np.array([mats[p].expansion for p in part])
    k_e, c_e = elements.elastic_matrices(uniq[:, :3], lame[:, 0], lame[:, 1], alpha)
    t = mm.mesh.t.T
    dofs = (3 * t[:, :, None] + np.arange(3)[None, None, :]).reshape(len(t), 24)
    n = mm.nnodes
    K = _scatter(dofs, dofs, k_e[inverse], (3 * n, 3 * n))
    C = _scatter(dofs, t, c_e[inverse], (3 * n, n))
    return ElasticMatrices(K, C)


@dataclass
class FacetMatrices:
    """For a set of facets: H = int N N dA [m2] and r = int N dA [m2] (so r @ T = int T dA)."""

    H: sp.csr_matrix
    r: np.ndarray
    area: float


@BilinearForm
def _surface_mass(u, v, w):
    return u * v


@LinearForm
def _surface_unit(v, w):
    return v


def assemble_facets(mm: MachineMesh, facets: np.ndarray) -> FacetMatrices:
    """Boundary mass matrix and load vector of the given facets (convection, surface flux)."""
    fb = FacetBasis(mm.mesh, ElementHex1(), facets=facets, intorder=2)
    r = asm(_surface_unit, fb)
    return FacetMatrices(asm(_surface_mass, fb).tocsr(), r, float(r.sum()))


def volume_vector(mm: MachineMesh, cells: np.ndarray) -> np.ndarray:
    """b_i = int_V N_i dV over ``cells`` [m3]; a trilinear function integrates to V/8 per corner."""
    b = np.zeros(mm.nnodes)
    vol = np.prod(mm.cell_size[cells], axis=1)
    np.add.at(b, mm.mesh.t[:, cells].ravel(), np.repeat(vol[None, :] / 8.0, 8, axis=0).ravel())
    return b
