"""The heat steppers: how each theta-step A x = b of :func:`twin.physics.heat.integrate` is solved,
A = M + theta dt (K + sum_k h_k H_k). One interface (``begin``, ``operator``, ``rhs_operator``,
``solve``, ``info``), two ways:

* :class:`DirectStepper` (small meshes): one sparse LU per distinct operator, cached by the
  caller under the load set's ``operator_key``; every later step is a back-substitution (exact to
  round-off);
* :class:`IterativeStepper` (large meshes): Jacobi-preconditioned CG on the CPU or a GPU, each step
  to the per-step tolerance whose sum over the run is the verified output bound of
  :mod:`twin.physics.solvers`, started from the Galerkin projection on the last solutions
  (:class:`twin.physics.solvers.Projection`) or, on long runs, from the extrapolation corrected
  on the reduced basis (:class:`ReducedStart`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from twin.physics import gpu_cg, kernels, parallel
from twin.physics.lu import SymmetricLU
from twin.physics.solvers import Projection, array_module, jacobi, mass_weights, pcg, to_host


def theta_operators(system, dt: float, theta: float, h: np.ndarray) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """(M + theta dt A, M - (1 - theta) dt A) with A = K + sum_k h_k H_k, as CSR."""
    A = system.K + sum((hk * Hk for hk, Hk in zip(h, system.H) if hk != 0), sp.csr_matrix(system.K.shape))
    return (system.M + theta * dt * A).tocsr(), (system.M - (1.0 - theta) * dt * A).tocsr()


MAX_FACTORISATIONS = 12   # kept per cache; each is tens of MB on a default mesh


class DirectStepper:
    """Sparse LU per distinct operator, cached in ``factorisations`` (kept by the caller)."""

    method = "direct"
    xp = np

    def __init__(self, factorisations: dict | None = None):
        self.cache = {} if factorisations is None else factorisations

    def operator(self, key, system, dt, theta, h):
        if key not in self.cache:
            while len(self.cache) >= MAX_FACTORISATIONS:   # oldest first: a fit that varies h makes many
                self.cache.pop(next(iter(self.cache)))
            lhs, rhs_op = theta_operators(system, dt, theta, h)
            self.cache[key] = (SymmetricLU(lhs), rhs_op)
        return self.cache[key]

    def begin(self, nsteps: int, system) -> None:
        pass

    def rhs_operator(self, op):
        return op[1]

    def solve(self, op, rhs, T):
        return op[0].solve(rhs)

    def info(self) -> dict:
        return {"solver_heat": "direct (sparse LU per operator, SuperLU)"}


class ReducedStart:
    """Starts for the heat steps A x = b from a fixed basis V (n, r) of slow fields (the reduced
    model's block-Krylov basis, :func:`twin.physics.rom.reduced_basis`): from a base field E (the
    stepper passes the extrapolation 2 T^n - T^(n-1)), the remainder x - E, which solves
    A (x - E) = b - A E, is replaced by its Galerkin projection on span(V),

        x0 = E + V (V^T A V)^-1 V^T (b - A E),

    the point of E + span(V) nearest the solution in the A norm (so never worse there than E
    itself). What the extrapolation misses is mostly the structure's slow response to the
    change of the inputs, which the basis spans; CG then resolves the rest. V^T A V (r, r) is
    formed once per operator (r products with A, eight columns at a time); each start costs one
    product with A and two passes over V. V^T M V = I for the reduced basis gives V^T A V >= I, so
    the small solve is well conditioned; it is done by the eigenvalues all the same, any direction
    with less than 1e-12 of the largest left out. V is kept in single precision (its span is then
    the rounded basis's, and V^T A V is formed in double on that basis): the two passes read half
    the memory, and the start is the Galerkin point to about 1e-7 of its correction, which changes
    no solution (CG forms its first residual b - A x0 in double from the matrix) and, measured,
    hardly an iteration (2.15 a step at 200 k nodes, 2.14 in double). Measured (validate/SCALE.md): on
    24 h of room air at 40 mm cells the CG iterations fall from 21 to 2 a step; after a spindle
    start the extrapolated base matters (from T itself the same run needs twice the iterations)."""

    def __init__(self, V: np.ndarray, xp=np, built_s: float = 0.0):
        # single precision (class docstring); columns contiguous: V^T r and V c at twice C order's speed
        self.V = xp.asarray(np.asfortranarray(V, dtype=np.float32))
        self.xp, self.built_s = xp, built_s   # [s] the time the basis took
        self._inverse = {}          # id(operator) -> (operator, (V^T A V)^-1); the operator kept alive

    @property
    def order(self) -> int:
        return int(self.V.shape[1])

    def _gram_inverse(self, op, lhs):
        if id(op) not in self._inverse:
            xp, V = self.xp, self.V.astype(float)       # the stored (rounded) basis, in double
            G = np.empty((V.shape[1], V.shape[1]))
            for a in range(0, V.shape[1], kernels.WIDTH):
                AV = lhs @ V[:, a:a + kernels.WIDTH]
                G[:, a:a + kernels.WIDTH] = to_host(xp, V.T @ AV)
            lam, U = np.linalg.eigh(0.5 * (G + G.T))
            keep = lam > 1e-12 * lam.max()
            self._inverse[id(op)] = (op, xp.asarray((U[:, keep] / lam[keep]) @ U[:, keep].T))
        return self._inverse[id(op)][1]

    def guess(self, op, lhs, b, base):
        """x0 for A = ``lhs`` (the operator tuple ``op`` keys the cache), right-hand side ``b``
        (n,) or (n, m), from the field ``base`` E of the same shape."""
        return base + self.correction(op, lhs, b - lhs @ base)

    def correction(self, op, lhs, r):
        """V (V^T A V)^-1 V^T r: the Galerkin solution of A d = r on span(V) (on the CPU the two
        passes over V in row blocks, :mod:`twin.physics.parallel`)."""
        f32, V = self.xp.float32, self.V
        if self.xp is not np:
            return V @ (self._gram_inverse(op, lhs) @ (V.T @ r.astype(f32)).astype(float)).astype(f32)
        c = self._gram_inverse(op, lhs) @ parallel.transposed_product(V, r.astype(f32)).astype(float)
        return parallel.rows_product(V, c.astype(f32))


PROJECTION_SIZE = 8     # solutions kept for the start of the next heat step (:class:`Projection`)


@dataclass
class IterativeStepper:
    """Jacobi-PCG on the CPU or a GPU (module docstring), each step started from the Galerkin
    projection on the recent solutions (:class:`Projection`, at least as good as the extrapolation
    2 T^n - T^(n-1)); batched columns start from that extrapolation.

    ``operators`` (kept by the caller) caches the CSR operators and their inverse diagonals per key.
    """

    heat_tol: float = 1e-6
    device: str = "cpu"
    max_iterations: int = 2000
    operators: dict = field(default_factory=dict)
    iterations: list = field(default_factory=list)
    rho_sum: float | np.ndarray = 0.0
    weights: np.ndarray | None = None
    projection_size: int = PROJECTION_SIZE
    start: ReducedStart | None = None

    method = "iterative"

    def __post_init__(self):
        self.xp = array_module(self.device)
        self._previous = None
        self._projection = None
        self._images = None       # (operator, A T, A T_prev) of the reduced start (:meth:`_reduced_step`)

    def _matrix(self, A):
        if self.device == "cpu":
            return parallel.split_matrix(A)     # row blocks on two threads when large (the same numbers)
        return gpu_cg.device_matrix(A)

    def begin(self, nsteps: int, system) -> None:
        """Reset the statistics and set the per-step tolerance for a run of ``nsteps`` steps."""
        self.iterations, self.rho_sum, self._previous, self._projection = [], 0.0, None, None
        self._images = None
        self.weights = mass_weights(system.M)
        capacity = float(system.M.sum())
        self.step_tol = self.heat_tol * np.sqrt(capacity) / max(nsteps, 1)
        self._w = self.xp.asarray(self.weights)

    def operator(self, key, system, dt, theta, h):
        if key not in self.operators:
            lhs, rhs_op = theta_operators(system, dt, theta, h)
            dinv = 1.0 / lhs.diagonal()
            self.operators[key] = (self._matrix(lhs), self._matrix(rhs_op), self.xp.asarray(dinv))
        return self.operators[key]

    def rhs_operator(self, op):
        return op[1]

    def solve(self, op, rhs, T):
        if self.start is not None:
            return self._reduced_step(op, rhs, T)
        lhs = op[0]
        apply = lambda v: lhs @ v
        project = rhs.ndim == 1 and self.projection_size >= 2
        if project and (self._projection is None or self._projection.key is not op):
            self._projection = Projection(apply, self.projection_size, self.xp, key=op)   # a new operator: a new basis
            for v in (self._previous, T):
                if v is not None:
                    self._projection.add(v)
        if project:
            guess = self._projection.guess(rhs)
        else:
            guess = T if self._previous is None else 2.0 * T - self._previous
        x = self._finish(op, rhs, guess, T)
        if project:
            self._projection.add(x)
        return x

    def _reduced_step(self, op, rhs, T):
        """The step from the extrapolation E = 2 T - T_prev corrected on the reduced basis
        (:class:`ReducedStart`). b - A E = b - 2 A T + A T_prev needs no product with A: the
        images A x of the last two solutions are b - r, their solves' final residuals (kept while
        the operator stays the same; CG still forms its own first residual b - A x0, so an image
        off by round-off changes the start, never the solution)."""
        lhs = op[0]
        known = self._images is not None and self._images[0] is op
        AT = self._images[1] if known else lhs @ T
        if self._previous is None:
            base, r = T, rhs - AT
        else:
            ATp = self._images[2] if known else lhs @ self._previous
            base, r = 2.0 * T - self._previous, rhs - 2.0 * AT + ATp
        x, R = self._finish(op, rhs, base + self.start.correction(op, lhs, r), T, residual=True)
        self._images = (op, rhs - R, AT)
        return x

    def _finish(self, op, rhs, guess, T, residual: bool = False):
        """CG from ``guess`` to this step's tolerance; the statistics and the residual sum kept
        (with ``residual``: (x, the final residual))."""
        lhs = op[0]
        x, it, rho, *R = pcg(lambda v: lhs @ v, rhs, guess, self.preconditioner(op), self._w, self.step_tol, self.xp,
                             self.max_iterations, residual, matrix=None if self.device == "cpu" else lhs)
        self._previous = T
        self.iterations.append(it)
        self.rho_sum = self.rho_sum + to_host(self.xp, rho)
        return (x, R[0]) if residual else x

    def preconditioner(self, op):
        """R -> an SPD approximation of A^-1 R for the operator ``op``: Jacobi, its inverse
        diagonal (a subclass may return another; the README's "Scale" section compares a
        two-grid cycle with it)."""
        return jacobi(op[2])

    def info(self) -> dict:
        its = np.asarray(self.iterations or [0])
        if self.start is not None:
            start = (f"each step started from the extrapolation 2T^n - T^(n-1) corrected on the reduced basis "
                     f"(order {self.start.order})")
        elif self.projection_size >= 2:
            start = f"started from the projection on the last {self.projection_size} solutions"
        else:
            start = "warm start 2T^n - T^(n-1)"
        info = {"solver_heat": f"Jacobi-PCG, {start}, on {self.device}",
                "heat_start": "reduced" if self.start is not None else "projection",
                "heat_tol_K": self.heat_tol, "heat_residual_sum": float(np.max(self.rho_sum)),
                "heat_iterations_mean": float(its.mean()), "heat_iterations_max": int(its.max())}
        if self.start is not None:
            info.update(heat_start_order=self.start.order, heat_start_basis_s=float(self.start.built_s))
        return info
