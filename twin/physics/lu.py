"""Sparse LU of the twin's symmetric positive definite operators: the heat steps' M + theta dt A,
the supported stiffness K_ff and a reduced model's reference operator on small layouts.

SuperLU with the minimum-degree ordering of A^T + A, no pivoting (``diag_pivot_thresh`` 0: an SPD
matrix needs none) and its symmetric mode: the fill of a Cholesky ordering, twice the entries of
a Cholesky factor. Factorisation and back-substitution are chains of small dense kernels, one per
supernode, and both run with BLAS held to one thread (:func:`twin.physics.parallel.single_blas`):

* OpenBLAS's threads slow these small kernels down. Measured on the default C-frame mesh (15.6 k
  heat nodes, 49 k elastic dofs), 2 cores at load 2: eight heat right-hand sides at once 20-22 ms
  on one thread against 164-170 ms with OpenBLAS's threads, eight elastic ones 0.16 s against
  0.9-1.6 s (a run's adjoints, some hundred columns, took 34 s before); one right-hand side
  (heat 5.4-6.2 ms) and the factorisation (elastic 4.2-4.4 s) are alike either way. On one thread
  several right-hand sides at once cost less than column by column (heat: 29 against 71 ms for
  eight, at load 5).
* OpenBLAS's sums depend on its thread count: on one thread the factors and the solutions are the
  same bits on any machine.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from twin.physics.parallel import single_blas


class SymmetricLU:
    """The factorised SPD matrix ``A`` (scipy sparse, n x n); :meth:`solve` takes one right-hand
    side (n,) or several (n, k)."""

    def __init__(self, A: sp.spmatrix):
        with single_blas():
            self._lu = spla.splu(sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                 options={"SymmetricMode": True})

    def solve(self, b: np.ndarray) -> np.ndarray:
        """A^-1 b."""
        with single_blas():
            return self._lu.solve(np.asarray(b, dtype=float))
