"""The linear solvers' shared pieces: the verified tolerance of the iterative heat steps,
preconditioned CG, the AMG V-cycle, the starts from earlier solutions, and the elastic AMG-CG
(which solver a twin uses: :mod:`twin.physics.options`). The heat steppers
built from them are in :mod:`twin.physics.steppers`.

Every theta-step solves A x = b with A = M + theta dt (K + sum_k h_k H_k), symmetric positive
definite (M is, K and the H_k are semi-definite). Two ways:

* **direct** (small meshes): one sparse LU per distinct operator, cached by the caller under the
  load set's ``operator_key`` and every later step is a back-substitution (exact to round-off);
* **iterative** (large meshes): Jacobi-preconditioned conjugate gradients started from the linear
  extrapolation 2 T^n - T^(n-1) of the last two steps. With dt of tens of seconds A is nearly
  mass-dominated, so a handful of iterations reach the tolerance, each at the memory-bandwidth
  limit (one sparse product and five vector passes).

**The iterative tolerance is a verified bound on the outputs.** Let r = b - A x be the residual
of a step and E the accumulated error of the field. Because A >= M (SPD ordering),
||A^-1 r||_M <= ||A^-1 r||_A = (r^T A^-1 r)^(1/2) <= (r^T M^-1 r)^(1/2), and the consistent
trilinear mass is bounded below by its lumped diagonal, M >= M_L / 27 (the eigenvalues of a Q1
element's mass relative to its row sums lie in [1/27, 1]), so

    ||A^-1 r||_M <= rho = (27 r^T M_L^-1 r)^(1/2).

The theta-scheme propagator (M + theta dt A)^-1 (M - (1 - theta) dt A) is a contraction in the M
norm for theta >= 1/2, so after N steps ||E_N||_M <= sum_n rho_n. Every linear output q = w^T T
then errs by at most |w^T E| <= ||w||_(M^-1) ||E||_M <= (27 w^T M_L^-1 w)^(1/2) sum_n rho_n, and
the stored heat 1^T M T by at most (1^T M 1)^(1/2) sum_n rho_n. CG stops each step when
rho <= ``heat_tol`` (C / ...) so that sum rho_n <= heat_tol sqrt(C), C = 1^T M 1 the total heat
capacity [J/K]: ``heat_tol`` [K] bounds the capacity-weighted RMS temperature error the solver adds
over the whole run. The bound per output is reported with the result (:func:`output_bounds`).

The same code runs on a GPU (``device="gpu"``, CuPy): arrays and the sparse matrices live on the
device, the outputs come back every step. CPU results are the reference.
"""

from __future__ import annotations

import threading
from concurrent import futures

import numpy as np
import scipy.sparse as sp

from twin.errors import InputError
from twin.physics import gpu_cg, kernels, parallel

MASS_BOUND = 27.0           # M >= M_L / 27 for trilinear bricks


def array_module(device: str):
    """numpy for the CPU, cupy for the GPU (imported here: CuPy is optional)."""
    if device == "cpu":
        return np
    try:
        import cupy
        if cupy.cuda.runtime.getDeviceCount() < 1:
            raise RuntimeError("no CUDA device")
    except Exception:  # noqa: BLE001 - no CuPy, or CuPy without a driver or a device: one clear error
        raise InputError("command line", "--device", "gpu needs CuPy (pip install cupy-cuda12x) and a CUDA GPU") from None
    return cupy


def to_host(xp, a) -> np.ndarray:
    """``a`` as a numpy array: itself on the CPU (``xp`` numpy), copied from the GPU (cupy)."""
    return a if xp is np else xp.asnumpy(a)


def mass_weights(M: sp.spmatrix) -> np.ndarray:
    """27 / m_L,i [1/(J/K)]: the diagonal weight of the norm rho = (r^T W r)^(1/2) that bounds
    ||A^-1 r||_M (module docstring); m_L the lumped (row-sum) capacity."""
    return MASS_BOUND / np.asarray(M.sum(axis=1)).ravel()


def output_bounds(rows: sp.spmatrix | np.ndarray, weights: np.ndarray, rho_sum: float) -> np.ndarray:
    """Bound on each output's solver error, (w^T W w)^(1/2) sum_n rho_n, for rows w (k, n)."""
    rows = sp.csr_matrix(rows)
    return np.sqrt(np.asarray(rows.multiply(rows) @ weights).ravel()) * rho_sum


def pcg(apply, b, x0, precondition, weights, tol, xp=np, max_iterations: int = 2000, residual: bool = False,
        matrix=None):
    """Preconditioned CG on every column of ``b`` (n,) or (n, m) at once.

    ``apply(X)`` is A X and ``precondition(R)`` an SPD approximation of A^-1 R, both on (n, m)
    blocks; ``weights`` (n,) the diagonal of the norm in which each column's residual must fall
    below ``tol`` (a number or one per column). Returns (x, iterations, rho) with rho the final
    residual norm per column, and with ``residual`` also the final residual b - A x (the CG
    recurrence's, equal to it up to round-off); raises RuntimeError if ``max_iterations`` are not
    enough (never a silent unconverged answer). Column sums and the direction update run in
    place (a single column's sums are BLAS dot products): the vector work of an iteration is a
    few passes over n. ``matrix``, when given, is the CSR matrix whose product ``apply`` is: one
    column with the Jacobi preconditioner on a GPU then runs on the fused kernels of
    :mod:`twin.physics.gpu_cg` (unless its ``FUSED`` is switched off, to compare); on the CPU
    one such column runs on numba's kernels from :data:`twin.physics.kernels.CG_FUSED_FROM` unknowns,
    and so does the vector work of a block of columns with any preconditioner (:class:`_BlockWork`).
    """
    if xp is not np and b.ndim == 1 and isinstance(precondition, Jacobi) and matrix is not None and gpu_cg.FUSED:
        return gpu_cg.jacobi_pcg(matrix, b, x0, precondition.dinv, weights, float(tol), max_iterations, residual)
    if xp is np and b.ndim == 1 and isinstance(precondition, Jacobi) and kernels.fused_cg(len(b)):
        return _fused_jacobi_pcg(apply, b, x0, precondition.dinv, weights, float(tol), max_iterations, residual)
    single = b.ndim == 1
    column = (lambda v: v[:, None]) if single else (lambda v: v)
    B = column(b)
    work = _BlockWork(weights) if xp is np and not single and kernels.fused_cg(len(b)) else _ArrayWork(xp, weights)
    X = work.owned(column(x0))
    R = work.fresh(B - apply(X))
    rho = xp.sqrt(work.weighted_squares(R))
    it = 0
    active = rho > tol
    if bool(active.any()):
        Z = precondition(R)
        P = work.owned(Z)
        rz = work.dots(R, Z)
        while bool(active.any()):
            if it >= max_iterations:
                raise RuntimeError(f"PCG did not converge in {max_iterations} iterations "
                                   f"(residual {float(rho.max()):.3g})")
            Q = apply(P)
            pq = work.dots(P, Q)
            alpha = xp.where(active, rz / xp.where(pq > 0, pq, 1.0), 0.0)
            rho = xp.sqrt(work.update(X, R, P, Q, alpha))
            active = active & (rho > tol)
            Z = precondition(R)
            rz_new = work.dots(R, Z)
            beta = xp.where(active, rz_new / xp.where(rz > 0, rz, 1.0), 0.0)
            work.direction(P, Z, beta)
            rz = rz_new
            it += 1
    out = (X[:, 0] if single else X), it, (rho[0] if single else rho)
    return (*out, (R[:, 0] if single else R)) if residual else out


class _ArrayWork:
    """The vector work of a :func:`pcg` iteration by array operations (numpy or CuPy), in place
    where it can be: X += alpha P, R -= alpha Q, the columns' sums (a single column's are BLAS dot
    products), P = beta P + Z."""

    def __init__(self, xp, weights):
        self.xp, self.weights, self.WR = xp, weights[:, None], None

    def owned(self, V):
        """A copy of V this iteration may write into."""
        return V.copy()

    def fresh(self, V):
        """V, just computed and nobody else's, as the iteration keeps it."""
        return V

    def dots(self, A, B):
        return column_dots(self.xp, A, B)

    def weighted_squares(self, R):
        """sum_i w_i R_ic^2 per column."""
        if self.WR is None:
            self.WR = self.xp.empty_like(R)
        self.xp.multiply(self.weights, R, out=self.WR)
        return column_dots(self.xp, self.WR, R)

    def update(self, X, R, P, Q, alpha):
        """X += alpha P, R -= alpha Q; returns sum_i w_i R_ic^2 per column."""
        X += alpha * P
        R -= alpha * Q
        return self.weighted_squares(R)

    def direction(self, P, Z, beta):
        P *= beta
        P += Z


class _BlockWork(_ArrayWork):
    """The same work on several columns in three compiled passes (:func:`twin.physics.kernels.
    block_cg_kernels`: the columns' sums; X += alpha P, R -= alpha Q with sum w R^2; P = beta P
    + Z) over the row blocks of :mod:`twin.physics.parallel`, their partial sums added in block
    order: the same products as the array operations, each column's sum in row order instead of
    numpy's (the numbers do not depend on the threads; the first residual's norm is numpy's).
    5.6 ms an iteration instead of about 20 at 200 k rows and eight columns."""

    def __init__(self, weights):
        super().__init__(np, weights)
        self.sums, self.step, self.turn = kernels.block_cg_kernels()
        self.w = np.ascontiguousarray(weights, dtype=float)
        self.blocks = parallel.even_blocks(len(weights))

    def _over(self, kernel, *args):
        parts = parallel.map_blocks(lambda s: kernel(*args, s.start, s.stop), self.blocks)
        return sum(parts[1:], parts[0]) if parts[0] is not None else None

    def owned(self, V):
        return np.array(V, dtype=float, order="C")

    def fresh(self, V):
        return np.ascontiguousarray(V, dtype=float)

    def dots(self, A, B):
        return self._over(self.sums, A, B)

    def update(self, X, R, P, Q, alpha):
        return self._over(self.step, X, R, P, Q, self.w, np.ascontiguousarray(alpha, dtype=float))

    def direction(self, P, Z, beta):
        self._over(self.turn, P, Z, np.ascontiguousarray(beta, dtype=float))


def column_dots(xp, A, B):
    """sum_i A_ij B_ij for each column j of two (n, m) blocks, without a temporary block (one
    column: a BLAS dot product)."""
    if A.shape[1] == 1:
        return (A.T @ B)[0]
    return xp.einsum("ij,ij->j", A, B)


class Jacobi:
    """The Jacobi preconditioner R -> D^-1 R of a matrix with inverse diagonal ``dinv`` (n,)
    (:func:`pcg` runs one column of it on compiled kernels)."""

    def __init__(self, dinv):
        self.dinv = dinv

    def __call__(self, R):
        return self.dinv[:, None] * R if R.ndim == 2 else self.dinv * R


def jacobi(dinv) -> Jacobi:
    """The Jacobi preconditioner of a matrix with inverse diagonal ``dinv`` (n,)."""
    return Jacobi(dinv)


def _fused_jacobi_pcg(apply, b, x0, dinv, weights, tol: float, max_iterations: int, residual: bool):
    """:func:`pcg` for one column with the Jacobi preconditioner on the CPU: the same iteration,
    its vector work in three compiled passes (P . Q; X += alpha P, R -= alpha Q, Z = D^-1 R with
    both sums; P = beta P + Z: :func:`twin.physics.kernels.cg_kernels`) instead of about ten numpy
    passes. Each pass runs over the two row blocks of :mod:`twin.physics.parallel` (on two threads
    where a helper is idle) and the blocks' partial sums are added in block order, so the numbers
    do not depend on the threads; they differ from the numpy path's in the order of the sums only
    (``tests/test_kernels.py``)."""
    from twin.physics import parallel

    dot, start, update, direction = kernels.cg_kernels()
    blocks = parallel.even_blocks(len(b))

    def over(kernel, *args):
        return parallel.map_blocks(lambda s: kernel(*args, s.start, s.stop), blocks)

    def sums(parts):            # each of a kernel's sums over the blocks, in block order
        return [sum(column) for column in zip(*parts)]

    X = np.array(x0, dtype=float)
    R = np.ascontiguousarray(b - apply(X), dtype=float)
    w, dinv = np.ascontiguousarray(weights, dtype=float), np.ascontiguousarray(dinv, dtype=float)
    Z = np.empty_like(R)
    rho2, rz = sums(over(start, R, w, dinv, Z))
    rho, it = float(np.sqrt(rho2)), 0
    if rho > tol:
        P = Z
        while True:
            if it >= max_iterations:
                raise RuntimeError(f"PCG did not converge in {max_iterations} iterations (residual {rho:.3g})")
            Q = np.ascontiguousarray(apply(P), dtype=float)
            pq = sum(over(dot, P, Q))
            alpha = rz / (pq if pq > 0 else 1.0)
            rho2, rz_new = sums(over(update, X, R, P, Q, w, dinv, alpha))     # Q now holds Z
            rho, it = float(np.sqrt(rho2)), it + 1
            if not rho > tol:
                break
            over(direction, P, Q, rz_new / (rz if rz > 0 else 1.0))
            rz = rz_new
    return (X, it, rho, R) if residual else (X, it, rho)


_AMG_SETUP = threading.Lock()
AMG_SEED = 0        # the seed of pyamg's random start vectors (:func:`smoothed_aggregation`)


def smoothed_aggregation(A: sp.spmatrix, **options):
    """pyamg's smoothed-aggregation hierarchy of ``A`` (``options`` as pyamg's), reproducibly.

    pyamg estimates the spectral radius of D^-1 A for its Jacobi prolongation smoother by Arnoldi
    from a random vector of numpy's global generator (its documentation says so), so two set-ups
    of one matrix differed in the last digits (the C-frame's elastic adjoints by 1e-19 m in
    successive runs). The generator is seeded with :data:`AMG_SEED` for the set-up and restored
    after it, under a lock: a set-up running beside another (:mod:`twin.physics.parallel`) cannot
    draw from the other's sequence."""
    import pyamg

    with _AMG_SETUP:
        state = np.random.get_state()
        np.random.seed(AMG_SEED)
        try:
            return pyamg.smoothed_aggregation_solver(A, **options)
        finally:
            np.random.set_state(state)


def amg_cycle(ml):
    """The V-cycle of an algebraic multigrid hierarchy ``ml`` (pyamg) as a preconditioner
    R -> B R: from x = 0 on each level, pre-smoothing, the coarse correction
    x += P (cycle of the coarse level on R_l (b - A x)), post-smoothing; a direct solve on the
    coarsest level. The same operator as pyamg's ``aspreconditioner(cycle="V")`` (symmetric when
    the post-smoother is the pre-smoother's adjoint), without the two residual norms that wrapper
    computes on the finest level every call (about a quarter of its cost).

    A block R (n, m) goes through every level as one block when the smoothers are pyamg's
    one-sweep Gauss-Seidel: the sweeps and products of :mod:`twin.physics.kernels` read each
    level's matrices once per eight columns instead of once per column, with the same arithmetic
    per column (equal to the column-by-column cycle to round-off). A block of five to eight
    columns goes through two cycles of four columns each, side by side, when a second core is
    idle at that moment (:func:`twin.physics.parallel.on_idle_helper`; the elastic chain beside a
    reduced basis has finished, say), else through one of eight: each column gets the same
    arithmetic either way, so the result does not depend on which. Other smoothers, and a single
    vector, take pyamg's own level functions column by column."""
    levels = ml.levels
    sweeps = [(_gs_sweep(lv.presmoother), _gs_sweep(lv.postsmoother)) for lv in levels[:-1]]
    blockwise = all(pre and post for pre, post in sweeps)
    csr = [(sp.csr_matrix(lv.A), sp.csr_matrix(lv.P), sp.csr_matrix(lv.R)) for lv in levels[:-1]] if blockwise else []
    split = blockwise and levels[0].A.nnz >= parallel.SPLIT_FROM      # two half cycles gain on large levels only

    def cycle(lvl: int, b: np.ndarray) -> np.ndarray:
        level = levels[lvl]
        if lvl == len(levels) - 1:
            return np.asarray(ml.coarse_solver(level.A, b)).reshape(b.shape)
        x = np.zeros_like(b)
        level.presmoother(level.A, x, b)
        x += level.P @ cycle(lvl + 1, level.R @ (b - level.A @ x))
        level.postsmoother(level.A, x, b)
        return x

    def block(lvl: int, B: np.ndarray) -> np.ndarray:
        if lvl == len(levels) - 1:
            return np.column_stack([cycle(lvl, B[:, j]) for j in range(B.shape[1])])
        (A, P, R), (pre, post) = csr[lvl], sweeps[lvl]
        X = np.zeros_like(B)
        kernels.gauss_seidel(A, X, B, pre)
        X += kernels.product(P, block(lvl + 1, kernels.product(R, B - kernels.product(A, X))))
        kernels.gauss_seidel(A, X, B, post)
        return X

    def apply(R: np.ndarray) -> np.ndarray:
        if R.ndim == 1:
            return cycle(0, R)
        m = R.shape[1]
        if not (blockwise and kernels.compiled(m, None)):
            return np.column_stack([cycle(0, R[:, j]) for j in range(R.shape[1])])
        half = kernels.HALF
        if split and half < m <= kernels.WIDTH:
            second = parallel.on_idle_helper(block, 0, kernels.as_block(R[:, half:]))
            if second is not None:              # a free core: each half through its own cycle
                try:
                    first = block(0, kernels.as_block(R[:, :half]))
                finally:
                    futures.wait([second])
                return np.hstack([first, second.result()[:, :m - half]])
        return block(0, kernels.as_block(R))[:, :m]         # block() does not write into its argument

    if split:           # factorise the coarsest level now: pyamg does it on first use, not thread-safely
        cycle(len(levels) - 1, np.zeros(levels[-1].A.shape[0]))
    return apply


def _gs_sweep(smoother) -> str | None:
    """The sweep of a pyamg smoother that is one plain Gauss-Seidel sweep ("forward", "backward" or
    "symmetric"), else None (another relaxation, or several sweeps)."""
    from pyamg.relaxation.relaxation import gauss_seidel

    kw = getattr(smoother, "keywords", {})
    if getattr(smoother, "func", None) is gauss_seidel and kw.get("iterations", 1) == 1 \
            and kw.get("omega", 1.0) == 1.0 and not getattr(smoother, "args", ()):
        return kw.get("sweep", "forward")
    return None


class Projection:
    """Starts for successive solves A x_n = b_n with one SPD A (P. F. Fischer, Projection techniques
    for iterative solution of Ax = b with successive right-hand sides, CMAME 163, 1998): keep an
    A-orthonormal basis Q of the recent solutions (A Q kept beside it) and start from the Galerkin
    projection x0 = Q Q^T b, the point of span(Q) nearest the solution in the A norm. The span
    always holds the last two solutions (on a restart when ``size`` columns are full, it is rebuilt
    from them), so the start is never worse in the A norm than the extrapolation 2 x_n - x_(n-1).
    Costs one product with A per solve (to add the new solution) and a few passes over Q."""

    def __init__(self, apply, size: int, xp=np, key=None):
        self.apply, self.size, self.xp, self.key = apply, size, xp, key
        self.Q = self.AQ = None
        self.last = None

    def guess(self, b):
        return self.xp.zeros_like(b) if self.Q is None else self.Q @ (self.Q.T @ b)

    def add(self, x) -> None:
        """Add the solution x (restart from the last two solutions when the basis is full)."""
        if self.Q is not None and self.Q.shape[1] >= self.size:
            self.Q = self.AQ = None
            self._append(self.last)
        self._append(x)
        self.last = x

    def _append(self, x) -> None:
        xp = self.xp
        ax = self.apply(x)
        energy = float(x @ ax)
        if self.Q is not None:
            for _ in range(2):                      # twice is enough (Kahan-Parlett)
                c = self.Q.T @ ax
                x, ax = x - self.Q @ c, ax - self.AQ @ c
        rest = float(x @ ax)
        if energy > 0 and rest > 1e-20 * energy:
            q, aq = (x / np.sqrt(rest))[:, None], (ax / np.sqrt(rest))[:, None]
            self.Q = q if self.Q is None else xp.hstack([self.Q, q])
            self.AQ = aq if self.AQ is None else xp.hstack([self.AQ, aq])


ADJOINT_STARTS = 64     # elastic solutions kept for the start of the next adjoint solve


def rigid_body_modes(points: np.ndarray) -> np.ndarray:
    """The six rigid-body modes (3 n, 6) of nodes at ``points`` (n, 3) [m], dofs interleaved:
    translations x, y, z and rotations about x, y, z (about the centroid)."""
    p = points - points.mean(axis=0)
    n = len(p)
    B = np.zeros((n, 3, 6))
    for i in range(3):
        B[:, i, i] = 1.0
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    B[:, 1, 3], B[:, 2, 3] = -z, y          # about x: (0, -z, y)
    B[:, 0, 4], B[:, 2, 4] = z, -x          # about y: (z, 0, -x)
    B[:, 0, 5], B[:, 1, 5] = -y, x          # about z: (-y, x, 0)
    return B.reshape(3 * n, 6)


class AmgElastic:
    """CG with a smoothed-aggregation algebraic multigrid preconditioner (pyamg) for the
    supported stiffness (SPD under the 3-2-1 support), built with the six rigid-body modes as the
    near-null space so that the coarse levels keep them (without them aggregation-AMG converges
    badly on elasticity). ``rtol``: relative residual ||K x - f|| <= rtol ||f||.

    The V-cycle smooths by one forward Gauss-Seidel sweep before the coarse correction and one
    backward sweep after it (a symmetric preconditioner at half the cost of two symmetric sweeps).
    A block of loads is solved as one CG run (each column to its own tolerance), whose V-cycles
    and products take all columns in one pass over each matrix (:mod:`twin.physics.kernels`):
    the prepared twin solves the adjoints of all its displacement observers so, as one block
    (:meth:`twin.physics.prepared.PreparedTwin.adjoints`). Every solve starts from the Galerkin
    projection of its loads on the solutions found before (:class:`Projection`: x0 = Q Q^T f, Q
    their K-orthonormal basis, the energy-optimal start in that span), so a later adjoint (an
    interferometer's) starts closer."""

    def __init__(self, k: sp.csr_matrix, modes: np.ndarray, rtol: float = 1e-10, max_iterations: int = 500):
        self.rtol, self.max_iterations = rtol, max_iterations
        self.k = k.tocsr()
        self.cycle = amg_cycle(smoothed_aggregation(
            self.k, B=modes, symmetry="hermitian", strength="symmetric", smooth="jacobi", max_coarse=500,
            coarse_solver="splu", presmoother=("gauss_seidel", {"sweep": "forward"}),
            postsmoother=("gauss_seidel", {"sweep": "backward"})))
        self.ones = np.ones(self.k.shape[0])
        self.iterations: list[int] = []
        self.starts = Projection(lambda v: self.k @ v, ADJOINT_STARTS)

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """K^-1 rhs for a load (n,) or a block (n, m): the block's non-zero columns are solved
        together (one V-cycle and one product a CG iteration for all of them, each column to
        its own tolerance), started from the projection on the solutions found before."""
        rhs = np.asarray(rhs, dtype=float)
        cols = rhs[:, None] if rhs.ndim == 1 else rhs
        out = np.zeros(cols.shape)
        live = np.flatnonzero(np.any(cols != 0, axis=0))
        if len(live):
            b = np.ascontiguousarray(cols[:, live])
            x, it, _ = pcg(lambda v: kernels.product(self.k, v), b, self.starts.guess(b), self.cycle, self.ones,
                           self.rtol * np.linalg.norm(b, axis=0), max_iterations=self.max_iterations)
            out[:, live] = x
            self.iterations.append(it)
            for j in range(x.shape[1]):
                self.starts.add(x[:, j])
        return out[:, 0] if rhs.ndim == 1 else out
