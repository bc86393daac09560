"""Sparse assembly of repeated element matrices, one pair of local corners at a time.

On the rectilinear grid the element matrices repeat: every cell uses the matrix of its group
(cell size and material, :func:`twin.fem.assembly._groups`). The global matrix

    A = sum_e  P_e^T A_g(e) Q_e        (P_e, Q_e: the cell's row and column dofs)

is assembled here without the (cells, p, q) array of element matrices and its COO index copies
(about 14 KB per elastic cell): the sparsity pattern (which node pairs couple) is built once from
the pairs of corners, with the position in it of every (cell, corner a, corner b) found by binary
search; then for each local pair (a, b) every cell adds the block A_g(e)[a, b] at its position.
On a grid a cell's corner a is a different node for every cell (cell = node - offset of corner
a), so one pass writes each position at most once and a plain ``data[pos] += block`` is exact;
where a layout breaks that (never on our meshes) the pass falls back to ``np.add.at``. Blocks of
``br x bc`` values per node pair (3 x 3 for the elastic stiffness, 3 x 1 for the thermal
coupling) give a block-sparse matrix, returned as CSR. One pattern serves every matrix on the
same corners (conduction and capacity).

Memory: the pattern (8 bytes per node pair, 4 or 8 per cell and corner pair) and the block
values, plus one pass's (cells, br, bc) values.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from twin.compiled import HAVE_NUMBA, compile_kernel


def _injective(nodes: np.ndarray, n: int) -> bool:
    """True when no node appears twice in ``nodes`` (one entry per cell)."""
    return len(nodes) == 0 or int(np.bincount(nodes, minlength=n).max()) <= 1


COMPILED_FROM = 2_000_000   # (corner, corner, cell) lookups from which the compiled search pays its import
                            # (about 0.4 s; np.searchsorted takes about that for 2 M lookups)


def _positions(indptr, indices, rows, cols, out):                 # pragma: no cover - compiled
    """out[a, b, e] = the position of column cols[b, e] among the sorted columns
    indices[indptr[r] : indptr[r + 1]] of row r = rows[a, e] (binary search; it is there)."""
    for e in range(rows.shape[1]):
        for a in range(rows.shape[0]):
            r = rows[a, e]
            first, end = indptr[r], indptr[r + 1]
            for b in range(cols.shape[0]):
                c = cols[b, e]
                lo, hi = first, end
                while lo < hi:
                    mid = (lo + hi) >> 1
                    if indices[mid] < c:
                        lo = mid + 1
                    else:
                        hi = mid
                out[a, b, e] = lo


def _accumulate(positions, group, ref, data):                     # pragma: no cover - compiled
    """data[positions[a, b, e]] += ref[group[e], a, b] for every corner pair (a, b) in turn and
    every cell e: :meth:`Pattern.assemble`'s passes in their order, without their temporaries."""
    p, q, ne = positions.shape
    br, bc = data.shape[1], data.shape[2]
    for a in range(p):
        for b in range(q):
            for e in range(ne):
                k = positions[a, b, e]
                g = group[e]
                for i in range(br):
                    for j in range(bc):
                        data[k, i, j] += ref[g, a, b, i, j]


class Pattern:
    """The node-pair sparsity of cells with row nodes ``rows`` (p, ne) and column nodes ``cols``
    (q, ne) in a matrix of ``shape`` (row nodes, column nodes), and every (corner a, corner b,
    cell)'s position in it: a binary search of the column in its row's sorted columns, compiled
    by numba (:func:`_positions`; ``use_numba=True``, and by default from :data:`COMPILED_FROM`
    lookups where numba is installed), else one ``np.searchsorted`` of the node pair in all pairs
    per corner pair (``use_numba=False``, and small meshes, where it costs less than importing
    numba); the two give the same positions. A compiled pattern also assembles by a compiled
    loop (:func:`_accumulate`), with the same sums in the same order."""

    def __init__(self, rows: np.ndarray, cols: np.ndarray, shape: tuple[int, int], use_numba: bool | None = None):
        rows = np.asarray(rows, dtype=np.int64)
        cols = np.asarray(cols, dtype=np.int64)
        self.shape = shape
        nr, nc = shape
        keys = np.sort((rows[:, None, :] * nc + cols[None, :, :]).ravel())    # node pairs, sorted
        keys = keys[np.concatenate([[True], keys[1:] != keys[:-1]])]           # (np.unique hashes: slow)
        dtype = np.int32 if len(keys) < 2**31 else np.int64
        self.indices = keys % nc
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(keys // nc, minlength=nr))])
        self.positions = np.empty((rows.shape[0], cols.shape[0], rows.shape[1]), dtype=dtype)
        lookups = rows.shape[0] * cols.shape[0] * rows.shape[1]
        self.compiled = HAVE_NUMBA and (use_numba is True or (use_numba is None and lookups >= COMPILED_FROM))
        if self.compiled:
            compile_kernel(_positions)(self.indptr, self.indices, rows, cols, self.positions)
        else:
            for a in range(rows.shape[0]):
                for b in range(cols.shape[0]):
                    self.positions[a, b] = np.searchsorted(keys, rows[a] * nc + cols[b])
        self.once = np.array([[_injective(rows[a], nr) or _injective(cols[b], nc) for b in range(cols.shape[0])]
                              for a in range(rows.shape[0])])

    def assemble(self, ref: np.ndarray, group: np.ndarray) -> sp.csr_matrix:
        """The sum over cells e of the element matrix ``ref[group[e]]`` at the cell's nodes.

        ref (g, p, q) or (g, p, q, br, bc): one element matrix per group, in node blocks of
        br x bc; group (ne,): each cell's group. Returns the CSR matrix of shape (row nodes * br,
        column nodes * bc), dofs interleaved (node i owns rows i br .. i br + br - 1).
        """
        ref = np.asarray(ref, dtype=float)
        if ref.ndim == 3:
            ref = ref[..., None, None]
        p, q, br, bc = ref.shape[1:]
        data = np.zeros((len(self.indices), br, bc))
        if self.compiled:                                    # the same sums in the same order, in one loop
            compile_kernel(_accumulate)(self.positions, np.asarray(group, dtype=np.int64), np.ascontiguousarray(ref), data)
        else:
            for a in range(p):
                for b in range(q):
                    block = ref[:, a, b][group]              # (ne, br, bc)
                    if self.once[a, b]:
                        data[self.positions[a, b]] += block
                    else:
                        np.add.at(data, self.positions[a, b], block)
        nr, nc = self.shape
        if br == bc == 1:
            return sp.csr_matrix((data[:, 0, 0], self.indices, self.indptr), shape=(nr, nc))
        return sp.bsr_matrix((data, self.indices, self.indptr), shape=(nr * br, nc * bc)).tocsr()
