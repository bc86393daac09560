"""Point evaluation on the hexahedral mesh: sparse trilinear interpolation operators."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from twin.errors import InputError
from twin.fem.elements import shape_q1
from twin.fem.mesh import MachineMesh


def locate(mm: MachineMesh, xyz: np.ndarray, names: list[str] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Cell index and reference coordinates xi in [-1, 1]^3 of each point (n, 3) [m].

    Raises :class:`twin.errors.InputError` (a ValueError) naming the first point that lies outside
    the machine (a sensor's position is checked before a run, :func:`twin.limits.check_position`;
    this is the last word, on the mesh itself).
    """
    xyz = np.atleast_2d(np.asarray(xyz, dtype=float))
    lo = mm.mesh.p[:, mm.mesh.t[0]].T  # corner (0,0,0) of every cell
    hi = mm.mesh.p[:, mm.mesh.t[7]].T  # corner (1,1,1)
    cells = np.empty(len(xyz), dtype=int)
    for i, x in enumerate(xyz):
        inside = np.flatnonzero(np.all((x >= lo - 1e-12) & (x <= hi + 1e-12), axis=1))
        if len(inside) == 0:
            label = names[i] if names else f"#{i}"
            raise InputError("command line", f"point {label}", f"({', '.join(f'{c:.4g}' for c in x)}) m is outside "
                                                                "the machine (in no cell of its mesh)")
        cells[i] = inside[0]
    xi = 2.0 * (xyz - lo[cells]) / (hi[cells] - lo[cells]) - 1.0
    return cells, xi


def interpolation_matrix(mm: MachineMesh, xyz: np.ndarray, names: list[str] | None = None,
                         field: str = "temperature") -> sp.csr_matrix:
    """Sparse operator (P @ v)[i] = v at point i (trilinear), for ``field`` "temperature"
    (columns: temperature dofs, ``mm.nheat``) or "mesh" (columns: mesh nodes, for displacements)."""
    cells, xi = locate(mm, xyz, names)
    n, _ = shape_q1(xi)
    rows = np.repeat(np.arange(len(cells)), 8)
    t, ncol = (mm.heat_t, mm.nheat) if field == "temperature" else (mm.mesh.t, mm.nnodes)
    return sp.csr_matrix((n.ravel(), (rows, t[:, cells].T.ravel())), shape=(len(cells), ncol))


def displacement_functional(P: sp.csr_matrix, direction: np.ndarray) -> sp.csr_matrix:
    """Rows mapping interleaved displacements u (3 nnodes) to (P u) . direction, per point."""
    P = P.tocoo()
    d = np.asarray(direction, dtype=float).reshape(-1, 3)
    if len(d) == 1:
        d = np.repeat(d, P.shape[0], axis=0)
    rows = np.concatenate([P.row] * 3)
    cols = np.concatenate([3 * P.col + c for c in range(3)])
    vals = np.concatenate([P.data * d[P.row, c] for c in range(3)])
    return sp.csr_matrix((vals, (rows, cols)), shape=(P.shape[0], 3 * P.shape[1]))
