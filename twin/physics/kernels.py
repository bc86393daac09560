"""Sparse kernels on blocks of vectors: Gauss-Seidel sweeps and products of a CSR matrix with an
(n, m) block, compiled with numba when it is installed, with a numpy/pyamg fallback that gives
the same numbers.

Why: the elastic adjoints and the reduced model's basis solve several right-hand sides with one
matrix (3-8 adjoints, blocks of about 7 moments). Their algebraic-multigrid V-cycle
(:func:`twin.physics.solvers.amg_cycle`) is a Gauss-Seidel sweep and a few sparse products per
level, each limited by reading the matrix from memory. Done column by column the matrix is read
once per column; here it is read once per eight columns, every row's eight sums kept in
registers. On the 40 mm C-frame's elastic stiffness (116 k dofs, 9.4 M entries) one forward sweep
costs 10.5 ms for one column and 27 ms for eight (3x less per column), the product 9.4 and 24 ms.
A block of at most four columns takes a four-column pass, and so does each half of an
eight-column V-cycle split over two threads (:func:`twin.physics.solvers.amg_cycle`). The pass
reads the matrix's indices as unsigned (:func:`_csr`) and is compiled with LLVM's SLP vectoriser
(:func:`twin.compiled.compile_kernel`), which puts a row's independent sums in SIMD registers: on
the 200 k-node heat matrix (5.1 M entries) a forward sweep of eight columns 9.2 ms and of four
7.1 ms, against 17.5 and 21.4 ms with signed indices and no vectoriser (pyamg's one column:
5.3 ms).

Each column gets exactly the arithmetic of the one-column kernel (the same sums in the same
order), so the block results equal the column-by-column ones; ``tests/test_kernels.py`` checks
the compiled kernels against the fallback. Without numba (``HAVE_NUMBA`` False) every function
falls back: pyamg's Gauss-Seidel column by column and scipy's sparse product.

    Gauss-Seidel, row i in sweep order:  x_i <- (b_i - sum_(j != i) a_ij x_j) / a_ii
    (rows with no diagonal entry are left unchanged, as pyamg does).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from twin.compiled import HAVE_NUMBA, compile_kernel

WIDTH = 8                               # columns a compiled kernel carries through one pass
HALF = 4                                # the narrower pass: a block of at most four columns, or
                                        # half of a block of eight run on each of two threads


PRODUCT, FORWARD, BACKWARD = 0, 1, 2    # what one pass of :func:`_block_pass` does


def _block_pass(indptr, indices, data, X, B, Y, mode):           # pragma: no cover - compiled
    """One pass over the rows of a CSR matrix A with eight or four columns at once (X, B, Y
    C-ordered, :data:`WIDTH` or :data:`HALF` columns, X's width is the pass's). ``PRODUCT``:
    Y = A X, every row's sum in stored order (scipy's). ``FORWARD`` or ``BACKWARD``: a Gauss-Seidel
    sweep on X in place, x_i <- (b_i - sum_(j != i) a_ij x_j) / a_ii in that row order (pyamg's;
    a row without a diagonal entry is left unchanged). Each column gets the same arithmetic
    whatever the width (the four-column pass is the eight-column one without its last four sums:
    the test on the width does not change inside the loops)."""
    n = Y.shape[0] if mode == PRODUCT else X.shape[0]
    wide = X.shape[1] == 8
    for k in range(n):
        i = n - 1 - k if mode == BACKWARD else k
        s0 = 0.0
        s1 = 0.0
        s2 = 0.0
        s3 = 0.0
        s4 = 0.0
        s5 = 0.0
        s6 = 0.0
        s7 = 0.0
        diag = 0.0
        for jj in range(indptr[i], indptr[i + 1]):
            j = indices[jj]
            a = data[jj]
            if j == i and mode != PRODUCT:
                diag = a
            else:
                s0 += a * X[j, 0]
                s1 += a * X[j, 1]
                s2 += a * X[j, 2]
                s3 += a * X[j, 3]
                if wide:
                    s4 += a * X[j, 4]
                    s5 += a * X[j, 5]
                    s6 += a * X[j, 6]
                    s7 += a * X[j, 7]
        if mode == PRODUCT:
            Y[i, 0] = s0
            Y[i, 1] = s1
            Y[i, 2] = s2
            Y[i, 3] = s3
            if wide:
                Y[i, 4] = s4
                Y[i, 5] = s5
                Y[i, 6] = s6
                Y[i, 7] = s7
        elif diag != 0.0:
            X[i, 0] = (B[i, 0] - s0) / diag
            X[i, 1] = (B[i, 1] - s1) / diag
            X[i, 2] = (B[i, 2] - s2) / diag
            X[i, 3] = (B[i, 3] - s3) / diag
            if wide:
                X[i, 4] = (B[i, 4] - s4) / diag
                X[i, 5] = (B[i, 5] - s5) / diag
                X[i, 6] = (B[i, 6] - s6) / diag
                X[i, 7] = (B[i, 7] - s7) / diag


def _chunks(m: int):
    """Column slices of at most :data:`WIDTH` covering m columns."""
    return [slice(c, min(c + WIDTH, m)) for c in range(0, m, WIDTH)]


def _exact(X: np.ndarray, width: int) -> bool:
    """True when X is itself a C-ordered float (n, width) block the kernel can use in place."""
    return X.shape[1] == width and X.dtype == np.float64 and X.flags.c_contiguous


def block_width(m: int) -> int:
    """The columns a block of m goes through the compiled passes as: :data:`HALF` for at most
    four, else m rounded up to whole :data:`WIDTH`-column passes (zero columns fill the rest)."""
    return HALF if m <= HALF else m + (-m) % WIDTH


def as_block(X: np.ndarray) -> np.ndarray:
    """X (n, m) as a C-ordered float (n, :func:`block_width` (m)) block, zero beyond its last
    column; X itself when it is one. A solver that keeps its vectors so (up to eight columns)
    saves the padded copy each product and sweep would otherwise make of them."""
    width = block_width(X.shape[1])
    if _exact(X, width):
        return X
    out = np.zeros((X.shape[0], width))
    out[:, :X.shape[1]] = X
    return out


def _padded(X: np.ndarray, cols: slice) -> np.ndarray:
    """Columns ``cols`` (at most :data:`WIDTH`) of X as a C-ordered (n, w) block, w = the
    :func:`block_width` of their number, zero beyond X's last column (X itself, not a copy, when
    it is such a block)."""
    whole = cols.start == 0 and cols.stop == X.shape[1]
    return as_block(X if whole else X[:, cols])


def _csr(A: sp.csr_matrix) -> tuple:
    """A's (indptr, indices, data) for a compiled kernel, 32-bit index arrays viewed as unsigned
    (no copy; CSR indices are never negative): numba checks every signed index for a negative
    value to wrap around, and that check in the innermost loop, X[j, c] for a column index j,
    made a sweep 1.2-2.4 times slower (a four-column forward sweep of a 5.1 M-entry matrix 18.0
    ms signed, 7.5 ms unsigned; eight columns 14.5 and 11.8 ms, measured on the development
    machine). The arithmetic is the same."""
    unsigned = [a.view(np.uint32) if a.dtype == np.int32 else a for a in (A.indptr, A.indices)]
    return unsigned[0], unsigned[1], A.data


def compiled(m: int, use_numba: bool | None) -> bool:
    """Whether a block of m columns goes through the compiled kernels: numba present (and not
    refused by ``use_numba=False``) and more than one column (one column is pyamg's and scipy's
    own kernel already)."""
    return HAVE_NUMBA and m > 1 and use_numba is not False


def gauss_seidel(A: sp.csr_matrix, X: np.ndarray, B: np.ndarray, sweep: str, use_numba: bool | None = None) -> None:
    """One Gauss-Seidel sweep (``"forward"``, ``"backward"`` or ``"symmetric"``: forward then
    backward) of A X = B on every column of X (n, m) in place; A in CSR with sorted rows."""
    if sweep not in ("forward", "backward", "symmetric"):
        raise ValueError(f"unknown sweep {sweep!r}")
    directions = (True, False) if sweep == "symmetric" else (sweep == "forward",)
    m = X.shape[1]
    if not compiled(m, use_numba):
        from pyamg.relaxation.relaxation import gauss_seidel as pyamg_gs

        for j in range(m):
            x, b = np.ascontiguousarray(X[:, j]), np.ascontiguousarray(B[:, j])
            for forward in directions:
                pyamg_gs(A, x, b, iterations=1, sweep="forward" if forward else "backward")
            X[:, j] = x
        return
    kernel, arrays = compile_kernel(_block_pass, vectorise=True), _csr(A)
    for cols in _chunks(m):
        x, b = _padded(X, cols), _padded(B, cols)
        for forward in directions:
            kernel(*arrays, x, b, np.empty((0, x.shape[1])), FORWARD if forward else BACKWARD)
        if x is not X:
            X[:, cols] = x[:, :cols.stop - cols.start]


def product(A: sp.csr_matrix, X: np.ndarray, use_numba: bool | None = None) -> np.ndarray:
    """A X for a CSR matrix A and a block X (n, m) (a vector: scipy's product)."""
    if X.ndim == 1 or not compiled(X.shape[1], use_numba):
        return A @ X
    out = np.empty((A.shape[0], X.shape[1]))
    kernel, arrays = compile_kernel(_block_pass, vectorise=True), _csr(A)
    for cols in _chunks(X.shape[1]):
        x = _padded(X, cols)
        y = out if x.shape[1] == X.shape[1] else np.empty((A.shape[0], x.shape[1]))
        kernel(*arrays, x, np.empty((0, x.shape[1])), y, PRODUCT)
        if y is not out:
            out[:, cols] = y[:, :cols.stop - cols.start]
    return out


def _vector_pass(indptr, indices, data, x, y):                 # pragma: no cover - compiled
    """y = A x for a CSR matrix A, every row's sum in stored order (scipy's)."""
    for i in range(y.shape[0]):
        s = 0.0
        for jj in range(indptr[i], indptr[i + 1]):
            s += data[jj] * x[indices[jj]]
        y[i] = s


def vector_product(A: sp.csr_matrix, x: np.ndarray, out: np.ndarray) -> np.ndarray:
    """A x into ``out`` for a CSR matrix A and a vector x (n,): scipy's sums, compiled on the
    matrix's unsigned index views (:func:`_csr`: 3.4 ms instead of scipy's 4.1 on the 200 k-node
    heat matrix), or scipy's own product without numba."""
    if not HAVE_NUMBA:
        out[:] = A @ x
        return out
    compile_kernel(_vector_pass)(*_csr(A), np.ascontiguousarray(x, dtype=float), out)
    return out


# --- one-column Jacobi-PCG: the vector work of an iteration in three passes -------------------------
#
# The heat step's CG (one vector, Jacobi) spends a third of a 200 k-node step on vector passes:
# numpy forms alpha P, X + alpha P, alpha Q, R - alpha Q, w R, (w R) . R, D^-1 R, R . Z, beta P and
# beta P + Z one array at a time, about 28 reads and writes of an n-vector an iteration. These
# kernels do the same arithmetic in three passes (P . Q; the update with both sums; the new
# direction) over a row range, so that :func:`twin.physics.solvers.pcg` can run each over the two
# row blocks of :mod:`twin.physics.parallel` and add the blocks' partial sums in a fixed order.

def _dot(x, y, a, b):                                   # pragma: no cover - compiled
    """sum_i x_i y_i over rows a..b-1."""
    s = 0.0
    for i in range(a, b):
        s += x[i] * y[i]
    return s


def _jacobi_residual(R, w, dinv, Z, a, b):              # pragma: no cover - compiled
    """Z = D^-1 R over rows a..b-1; returns (sum w R^2, sum R Z) there."""
    s1 = 0.0
    s2 = 0.0
    for i in range(a, b):
        r = R[i]
        z = dinv[i] * r
        Z[i] = z
        s1 += w[i] * r * r
        s2 += r * z
    return s1, s2


def _cg_update(X, R, P, Q, w, dinv, alpha, a, b):      # pragma: no cover - compiled
    """X += alpha P, R -= alpha Q, then Z = D^-1 R written over Q, over rows a..b-1; returns
    (sum w R^2, sum R Z) there (Q is not needed once R is updated)."""
    s1 = 0.0
    s2 = 0.0
    for i in range(a, b):
        X[i] += alpha * P[i]
        r = R[i] - alpha * Q[i]
        R[i] = r
        z = dinv[i] * r
        Q[i] = z
        s1 += w[i] * r * r
        s2 += r * z
    return s1, s2


def _cg_direction(P, Z, beta, a, b):                    # pragma: no cover - compiled
    """P = beta P + Z over rows a..b-1."""
    for i in range(a, b):
        P[i] = beta * P[i] + Z[i]


# --- block PCG: the vector work of an iteration on several columns in three passes -----------------
#
# A block CG (the reduced basis's moments, the elastic adjoints) spent about 20 ms an iteration at
# 200 k rows and eight columns on numpy's vector work (alpha P, X + alpha P, alpha Q, R - alpha Q,
# w R, the column sums by einsum, beta P + Z): 5.6 ms in these passes. Each column's sum runs in
# row order; the caller adds row blocks' partial sums in block order.

def _block_dots(A, B, a, b):                            # pragma: no cover - compiled
    """sum_i A_ic B_ic for each column c over rows a..b-1."""
    out = np.zeros(A.shape[1])
    for i in range(a, b):
        for c in range(A.shape[1]):
            out[c] += A[i, c] * B[i, c]
    return out


def _block_cg_update(X, R, P, Q, w, alpha, a, b):       # pragma: no cover - compiled
    """X += alpha P and R -= alpha Q, alpha one per column, over rows a..b-1; returns
    sum_i w_i R_ic^2 per column there."""
    out = np.zeros(X.shape[1])
    for i in range(a, b):
        wi = w[i]
        for c in range(X.shape[1]):
            X[i, c] += alpha[c] * P[i, c]
            r = R[i, c] - alpha[c] * Q[i, c]
            R[i, c] = r
            out[c] += wi * r * r
    return out


def _block_cg_direction(P, Z, beta, a, b):              # pragma: no cover - compiled
    """P = beta P + Z, beta one per column, over rows a..b-1."""
    for i in range(a, b):
        for c in range(P.shape[1]):
            P[i, c] = P[i, c] * beta[c] + Z[i, c]


def block_cg_kernels():
    """The compiled (dots, update, direction) kernels of a block PCG."""
    return compile_kernel(_block_dots), compile_kernel(_block_cg_update), compile_kernel(_block_cg_direction)


CG_FUSED_FROM = 30_000      # unknowns from which a one-column Jacobi-PCG runs on these kernels


def fused_cg(n: int, use_numba: bool | None = None) -> bool:
    """Whether a PCG of n unknowns runs its vector work on the compiled kernels above (a single
    column with the Jacobi preconditioner, or a block with any): numba present and not refused,
    and n from :data:`CG_FUSED_FROM`, or any n when ``use_numba`` is True."""
    return HAVE_NUMBA and use_numba is not False and (use_numba is True or n >= CG_FUSED_FROM)


def cg_kernels():
    """The compiled (dot, jacobi_residual, update, direction) kernels."""
    return (compile_kernel(_dot), compile_kernel(_jacobi_residual), compile_kernel(_cg_update),
            compile_kernel(_cg_direction))
