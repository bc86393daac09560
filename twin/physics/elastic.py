"""Linear quasi-static thermoelasticity and adjoint drift operators.

K u = C (T - T_ref): one-way coupled, thermal strain alpha (T - T_ref), small strains. The machine
stands on levelling feet: a statically determinate 3-2-1 support at three corners of the bed's
floor contact removes the six rigid-body motions and nothing else, so free thermal expansion is
never blocked (the support reactions of a self-equilibrated thermal load are zero).

Every drift output is a linear functional q = g^T u = g^T K^-1 C dT. With one adjoint solve
K lam = g per output, the influence vector is w = C^T lam and q = w^T dT: a dot product per time
step (the adjoint identity g^T K^-1 C = (C^T K^-T g)^T with K symmetric).

Small meshes factorise K_ff (SuperLU); large ones solve by CG with a smoothed-aggregation AMG
preconditioner built on the six rigid-body modes (:class:`twin.physics.solvers.AmgElastic`),
whose cost grows about linearly with the mesh where the factorisation's fill grows faster.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from twin.fem.assembly import ElasticMatrices, assemble_coupling, assemble_elastic
from twin.fem.mesh import MachineMesh
from twin.physics.lu import SymmetricLU
from twin.physics.solvers import AmgElastic, rigid_body_modes


def support_dofs(mm: MachineMesh) -> np.ndarray:
    """3-2-1 support: corner A fixes x, y, z; corner B (along x) fixes y, z; corner C (along y) z.

    A, B, C are the floor-contact nodes nearest the corners of the floor footprint.
    """
    p = mm.mesh.p.T
    floor = np.flatnonzero(p[:, 2] <= p[:, 2].min() + 1e-9)
    lo, hi = p[floor].min(axis=0), p[floor].max(axis=0)

    def nearest(x, y):
        return floor[np.argmin((p[floor, 0] - x) ** 2 + (p[floor, 1] - y) ** 2)]

    a, b, c = nearest(lo[0], lo[1]), nearest(hi[0], lo[1]), nearest(lo[0], hi[1])
    return np.array([3 * a, 3 * a + 1, 3 * a + 2, 3 * b + 1, 3 * b + 2, 3 * c + 2])


def constrained(K: sp.csr_matrix, fixed: np.ndarray, copy: bool = True) -> sp.csr_matrix:
    """K with the rows and columns of the ``fixed`` dofs zeroed and 1 on their diagonal, in the
    same sparsity pattern (no copies of the big matrix by fancy indexing; in place when not
    ``copy``). Solved with a zero load on those dofs it gives u_fixed = 0 and on the rest exactly
    the supported system K_ff u_f = f_f."""
    K = K.tocsr(copy=copy)
    mask = np.zeros(K.shape[0], dtype=bool)
    mask[fixed] = True
    rows = np.repeat(mask, np.diff(K.indptr))
    hit = rows | mask[K.indices]
    where = np.flatnonzero(hit)
    on_diagonal = np.searchsorted(K.indptr, where, side="right") - 1 == K.indices[where]
    values = np.zeros(int(hit.sum()))
    values[on_diagonal] = 1.0
    K.data[hit] = values
    return K


@dataclass
class ElasticSolver:
    """The supported stiffness of a machine, ready to solve K u = f for any load: factorised
    (``method="direct"``) or by AMG-preconditioned CG to ``rtol`` (``method="amg"``, where
    ``matrices.K`` holds the support as identity rows, :func:`constrained`)."""

    matrices: ElasticMatrices
    fixed: np.ndarray
    free: np.ndarray
    _lu: object
    method: str = "direct"
    rtol: float = 0.0

    @classmethod
    def build(cls, mm: MachineMesh, materials: dict | None = None, method: str = "direct",
              rtol: float = 1e-10) -> "ElasticSolver":
        mats = assemble_elastic(mm, materials)
        fixed = support_dofs(mm)
        free = np.setdiff1d(np.arange(mats.K.shape[0]), fixed)
        if method == "direct":
            kff = mats.K[free][:, free]
            solver = SymmetricLU(kff)
            rtol = 0.0
        elif method == "amg":
            modes = rigid_body_modes(mm.mesh.p.T)
            modes[fixed] = 0.0
            mats = ElasticMatrices(constrained(mats.K, fixed, copy=False), mats.C)   # one copy of K in memory
            solver = AmgElastic(mats.K, modes, rtol)
            free = np.arange(mats.K.shape[0])     # the fixed dofs are identity rows with zero load
        else:
            raise ValueError(f"unknown elastic method {method!r}")
        return cls(mats, fixed, free, solver, method, rtol)

    def info(self) -> dict:
        """What solves the adjoints, for the result attributes."""
        if self.method == "direct":
            return {"solver_elastic": "direct (sparse LU of the supported stiffness, SuperLU)"}
        its = self._lu.iterations or [0]
        return {"solver_elastic": "CG + smoothed-aggregation AMG (pyamg, rigid-body modes as near-null space)",
                "elastic_rtol": self.rtol, "elastic_iterations_max": int(max(its))}

    @staticmethod
    def coupling(mm: MachineMesh, materials: dict | None = None) -> sp.csr_matrix:
        """Thermal coupling C [N/K] on the temperature dofs of ``mm`` (see :mod:`twin.fem.assembly`)."""
        return assemble_coupling(mm, materials)

    def solve(self, load: np.ndarray) -> np.ndarray:
        """Displacements u [m] (3 per node, interleaved) for nodal forces ``load`` [N] (columns ok)."""
        load = np.asarray(load, dtype=float)
        u = np.zeros(load.shape)
        f = np.ascontiguousarray(load[self.free])
        if len(self.free) == len(load):
            f[self.fixed] = 0.0
        u[self.free] = self._lu.solve(f)
        return u

    def displacement(self, dT: np.ndarray) -> np.ndarray:
        """Full displacement field (nnodes, 3) [m] of a nodal temperature rise dT [K]."""
        return self.solve(self.matrices.C @ dT).reshape(-1, 3)

    def influence(self, functionals: sp.spmatrix) -> np.ndarray:
        """Adjoint influence matrix W (nnodes, nout): q = W^T dT for q = functionals @ u.

        ``functionals`` (nout, 3 nnodes) maps displacements [m] to outputs.
        """
        g = np.asarray(functionals.todense() if sp.issparse(functionals) else functionals).T
        lam = self.solve(g)
        return np.asarray(self.matrices.C.T @ lam)
