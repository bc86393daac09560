"""Reduced-order heat model: a block-Krylov basis, affine in the film coefficients, every observer
projected exactly, and an error estimate for every output.

With u = T - T_0 (T_0 the uniform start temperature; K 1 = 0, H_k 1 = r_k for a film and
H_c 1 = 0 for a contact, so T_0 drops out of the operator) the full model is

    M u' + (K + sum_k h_k(t) H_k) u = F s(t) + sum_k h_k(t) (T_air,k(t) - T_0) r_k,   u(0) = 0.

**Basis** (offline): V (n, r) spans the block Krylov space of the moments at s = 0,

    A_ref^-1 B,  (A_ref^-1 M) A_ref^-1 B,  ...,   B = [F, r_1 .. r_m],
    A_ref = K + sum_k hbar_k H_k + sigma_0 M,

(hbar the mean film coefficients of the run that built it, sigma_0 = 1 / (10 days) keeps A_ref
definite without any film), M-orthonormalised block by block (twice-iterated Gram-Schmidt, rank
deflation by the eigenvalues of each block's M-Gram matrix). Modal truncation is not used: local
heat inputs excite many modes quasi-statically (notes/engine-performance.md). On large layouts
each block is solved by AMG-CG when it is used, started from the Galerkin projection on the basis
built so far and stopped at :data:`BASIS_RTOL` of that start's residual: what the basis gains from
a block is its part outside the basis, which this resolves to a fixed relative accuracy (a
tolerance on the whole block would resolve it ever worse as the moments converge, and a second
operator's first block, nearly inside the first operator's span, would enter as solver error).
Directions new by less than ten times that accuracy are dropped with the dependent ones: they
would be mostly solver error (on 40 mm cells, `spindle-heat-cool-9000`: drift error 5 % of its
peak when kept, 0.6 % when dropped; the LU-built basis, which keeps down to 1e-10, 2.5 %).

**Reduced model** (online): with V^T M V = I, z' + (K_r + sum_k h_k(t) H_k,r) z = F_r s +
sum_k h_k (T_air,k - T_0) r_k,r, K_r = V^T K V, H_k,r = V^T H_k V, F_r = V^T F, r_k,r = V^T r_k:
affine in the h_k, so any film schedule (speed-dependent, another scenario) runs on the same
reduction. The same theta-scheme as the full model; every observer's rows W give W V and W 1
exactly (y = T_0 W 1 + (W V) z). Each step costs O(r^2) per case.

**Error, reported two ways.** (1) A verified bound: a reduced step leaves the full-space residual
R_n = M V (z+ - z) + dt (K + sum h_k H_k) V z_theta - dt f_n = Y c_n, Y = [M V, K V, H_k V, F, r_k]
(c_n from the reduced state and the signals), and exactly as for an iterative solver
(:mod:`twin.physics.solvers`) the error of every output q = w^T T over the run is at most
(27 w^T M_L^-1 w)^(1/2) sum_n rho_n with rho_n = (c_n^T G c_n)^(1/2), G = Y^T 27 M_L^-1 Y
computed once offline (plus a round-off allowance 64 eps (sum_i |c_i| G_ii^(1/2))^2 under the
root). It holds for any film schedule, any input, any mesh; it is pessimistic (about sqrt(n)
for a point sensor). (2) An estimate: the model is also integrated with its leading blocks less
the last two (order r - b, b the size of two blocks: one more moment of each reference
operator), and max_t |y_r - y_(r-b)| per output estimates the error of y_r (when the moments
converge geometrically it exceeds the error by the ratio of a two-block step; not guaranteed). Both come with the result; tests/test_scale.py holds
the error against full runs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from twin.errors import InputError
from twin.physics import kernels
from twin.physics.lu import SymmetricLU
from twin.physics.options import DIRECT_LIMIT, ROM_ORDER
from twin.physics.solvers import amg_cycle, mass_weights, output_bounds, pcg, smoothed_aggregation

SIGMA0 = 1.0 / (10 * 86400.0)    # [1/s]: keeps the reference operator definite without any film
DROP = 1e-10        # directions new to the basis by less than this share of their block's largest are dropped
GRAM_EPS = 1e-13    # Gram eigenvalues below this share of the largest are round-off (:func:`_m_orthonormalise`)
BASIS_RTOL = 1e-6   # residual reduction of the basis's iterative solves (large layouts), relative to
                    # the Galerkin start's: the span is what the reduced model needs, and its error is
                    # bounded and estimated from the basis actually built (validate/SCALE.md)
BASIS_STRENGTH = [("symmetric", {"theta": 0.0}), ("symmetric", {"theta": 0.05})]
                    # pyamg's strength of connection for the basis's AMG, per level (the last repeated):
                    # every connection on the finest level (pyamg's default, theta 0; at 0.1 there the
                    # 200 k-node C-frame took 80 V-cycles a block instead of 15), |a_ij| >= 0.05
                    # (a_ii a_jj)^(1/2) below it, where the coarse levels' aggregates then stop crossing
                    # weak couplings: 11-12 V-cycles a block instead of 14-16 (validate/SCALE.md)
START_BASIS_RTOL = 1e-5   # the same for a basis that only starts full-order heat steps
                    # (:class:`twin.physics.steppers.ReducedStart`): CG corrects what its span misses, so
                    # it needs the slow directions, not their last digits. Measured at 200 k nodes, 24 h
                    # of room air: basis 19 s instead of 25, CG 2.19 iterations a step instead of 2.15;
                    # at 1e-4 3.3 a step (the drop threshold, 10 rtol, discards whole directions)


@dataclass
class ReducedModel:
    """Projected matrices of one load set (module docstring): basis ``V`` (n, r), ``K`` (r, r),
    ``H`` (ncv, r, r), ``F`` (r, nsrc), ``R`` (r, ncv), ``order_estimate`` the size of the
    sub-basis whose difference estimates the error, ``offline_s`` the time the reduction took."""

    V: np.ndarray
    K: np.ndarray
    H: np.ndarray
    F: np.ndarray
    R: np.ndarray
    order_estimate: int
    offline_s: float
    gram: np.ndarray | None = None        # residual Gram matrix (:func:`residual_gram`)
    outputs: np.ndarray | None = None     # (nout, r) W V
    ones: np.ndarray | None = None        # (nout,) W 1
    output_norms: np.ndarray | None = None   # (nout,) (27 w^T M_L^-1 w)^(1/2)

    @property
    def order(self) -> int:
        return self.V.shape[1]

    def project_outputs(self, outputs: sp.spmatrix, weights: np.ndarray) -> "ReducedModel":
        """A copy observing ``outputs`` (nout, n): W V and W 1 (exact), and each row's bounding
        norm for the error bound (``weights``: :func:`twin.physics.solvers.mass_weights`)."""
        W = sp.csr_matrix(outputs)
        return ReducedModel(self.V, self.K, self.H, self.F, self.R, self.order_estimate, self.offline_s, self.gram,
                            np.asarray(W @ self.V), np.asarray(W @ np.ones(W.shape[1])).ravel(),
                            output_bounds(W, weights, 1.0))

    def integrate(self, T0: float, dt: float, nsteps: int, h, air, s, theta: float = 0.5, on_step=None,
                  progress=None, bound: bool = True) -> tuple[np.ndarray, dict]:
        """The theta-scheme on the reduced model: outputs (nsteps+1, nout[, m]) and the run info
        (order; ``_estimate``: max_t |y_r - y_(r-b)| per output; ``_bound``: the verified bound
        of each output's error, ||w||_W sum_n rho_n (module docstring), when ``bound``).

        Batched cases: ``air`` (nsteps, ncv, m) and ``s`` (nsteps, nsrc, m) and optionally ``h``
        (nsteps, ncv, m), one column per case; otherwise 2-D as in :func:`twin.physics.heat.integrate`.
        ``on_step(n, T)`` gets the reconstructed field T_0 + V z (costs n r per step).
        """
        if bound and self.gram is None:
            raise InputError("reduced model", "bound", "the verified bound needs the residual Gram matrix: build the "
                                                        "model with gram=True, or integrate with bound=False")
        batched = np.ndim(s) == 3
        m = np.shape(s)[2] if batched else 1
        s3 = np.asarray(s, float).reshape(nsteps, -1, m)
        air3 = np.asarray(air, float).reshape(nsteps, -1, m)
        h = np.asarray(h, float)
        h3 = h if h.ndim == 3 else np.repeat(h[:, :, None], m, axis=2)
        shared = h.ndim == 2 or bool(np.all(h3 == h3[:, :, :1]))
        r, r0 = self.order, self.order_estimate
        z = np.zeros((r, m))
        z0 = np.zeros((r0, m))
        W, W0 = self.outputs, self.outputs[:, :r0]
        base = (T0 * self.ones)[:, None]
        out = np.empty((nsteps + 1, len(self.ones), m))
        est = np.zeros((len(self.ones), m))
        out[0] = base
        cache: dict = {}
        eye = np.eye(r)
        G = self.gram
        gdiag = np.sqrt(np.maximum(np.diag(G), 0.0)) if bound else None
        rho_sum = np.zeros(m)
        for n in range(nsteps):
            z_old = z
            if shared:
                key = tuple(np.round(h3[n, :, 0], 12))
                if key not in cache:
                    A = self.K + np.tensordot(h3[n, :, 0], self.H, axes=1)
                    cache[key] = (_step_matrices(A, dt, theta, eye), _step_matrices(A[:r0, :r0], dt, theta, eye[:r0, :r0]))
                (P, Q), (P0, Q0) = cache[key]
                f = self.F @ s3[n] + self.R @ (h3[n] * (air3[n] - T0))
                z = P @ z + Q @ f
                z0 = P0 @ z0 + Q0 @ f[:r0]
            else:   # film coefficients differ per case: one small solve per case and step
                A = self.K[None] + np.einsum("km,kij->mij", h3[n], self.H)
                f = self.F @ s3[n] + self.R @ (h3[n] * (air3[n] - T0))
                z = _batched_step(A, z, f, dt, theta)
                z0 = _batched_step(A[:, :r0, :r0], z0, f[:r0], dt, theta)
            if bound:
                zt = theta * z + (1 - theta) * z_old
                c = np.vstack([z - z_old, dt * zt] + [dt * h3[n, k] * zt for k in range(len(self.H))]
                              + [-dt * s3[n], -dt * h3[n] * (air3[n] - T0)])
                q = np.einsum("im,im->m", c, G @ c)
                rho_sum += np.sqrt(np.maximum(q, 0.0) + 64 * np.finfo(float).eps * (gdiag @ np.abs(c)) ** 2)
            y = base + W @ z
            out[n + 1] = y
            est = np.maximum(est, np.abs(y - base - W0 @ z0))
            if on_step is not None:
                on_step(n + 1, T0 + self.V @ (z[:, 0] if m == 1 else z))
            elif progress is not None:
                progress(n + 1, nsteps)
        bounds = self.output_norms[:, None] * rho_sum[None, :] if bound else np.full(est.shape, np.nan)
        if not batched:
            out, est, bounds = out[:, :, 0], est[:, 0], bounds[:, 0]
        info = {"solver_heat": "reduced model (block Krylov at s = 0, M-orthonormal, affine in the film coefficients)",
                "rom_order": r, "rom_estimate_order": r0, "rom_offline_s": self.offline_s}
        return out, {**info, "_estimate": est, "_bound": bounds}


def _step_matrices(A: np.ndarray, dt: float, theta: float, eye: np.ndarray):
    """(P, Q) with z+ = P z + Q f: P = (I + theta dt A)^-1 (I - (1 - theta) dt A), Q = dt (I + theta dt A)^-1."""
    lhs = eye + theta * dt * A
    return np.linalg.solve(lhs, eye - (1 - theta) * dt * A), dt * np.linalg.inv(lhs)


def _batched_step(A: np.ndarray, z: np.ndarray, f: np.ndarray, dt: float, theta: float) -> np.ndarray:
    """One theta step per case: A (m, r, r), z and f (r, m)."""
    eye = np.eye(A.shape[1])[None]
    lhs = eye + theta * dt * A
    rhs = np.einsum("mij,jm->mi", eye - (1 - theta) * dt * A, z) + dt * f.T
    return np.linalg.solve(lhs, rhs[:, :, None])[:, :, 0].T


def _reference_solver(A: sp.csr_matrix, rtol: float = BASIS_RTOL):
    """(solve, rtol): solve (X, V) -> A^-1 X for the SPD reference operator, by sparse LU on small
    layouts (V unused, rtol 0), by CG with a smoothed-aggregation AMG preconditioner (pyamg) on
    large ones.

    The CG starts from the Galerkin projection on the basis so far, x0 = V (V^T A V)^-1 V^T X, and
    stops when each column's residual has fallen to ``rtol`` (:data:`BASIS_RTOL`) of the
    start's, ||X - A x|| <= rtol ||X - A x0||: the part of the moment that is new to the basis, which
    is all the basis gains from it, is then resolved to ``rtol`` however small it has become (a
    tolerance relative to ||X|| would resolve it ever worse as the moments converge)."""
    if A.shape[0] <= DIRECT_LIMIT:
        lu = SymmetricLU(A)
        return (lambda X, V: lu.solve(X)), 0.0
    cycle = amg_cycle(smoothed_aggregation(A, symmetry="hermitian", max_coarse=500, coarse_solver="splu",
                                           strength=BASIS_STRENGTH))
    ones = np.ones(A.shape[0])
    AV = np.zeros((A.shape[0], 0))

    def solve(X, V):
        nonlocal AV
        m = X.shape[1]
        if kernels.compiled(m, None):
            X = kernels.as_block(X)     # zero columns to whole passes: CG's products and V-cycles copy nothing
        if V.shape[1] > AV.shape[1]:
            AV = np.hstack([AV, kernels.product(A, V[:, AV.shape[1]:])])
        AVk = AV[:, :V.shape[1]]
        c = np.linalg.solve(V.T @ AVk, V.T @ X) if V.shape[1] else np.zeros((0, X.shape[1]))
        start = np.linalg.norm(X - AVk @ c, axis=0)
        Y, _, _ = pcg(lambda U: kernels.product(A, U), X, V @ c, cycle, ones, rtol * start, max_iterations=500)
        return Y[:, :m]         # a zero column's start is zero and its tolerance zero: CG leaves it zero

    return solve, rtol


def _m_orthonormalise(X: np.ndarray, V: np.ndarray, M: sp.spmatrix, drop: float = DROP) -> np.ndarray:
    """Columns spanning X minus its M-projection on V (V^T M V = I), M-orthonormal, with directions
    whose M-norm fell below ``drop`` of the block's largest (already in V, or dependent) removed,
    and those the Gram matrix cannot tell from round-off: an eigenvalue of G = X^T M X is known to
    about 1e-16 of its largest, so one below :data:`GRAM_EPS` of it (a direction new by less than
    about 3e-7 of the block's largest) is dropped whatever ``drop`` says. A second pass (for the
    first block too) projects and normalises again; a direction that loses half its norm there was
    round-off and is dropped, so V^T M V = I holds to round-off and no column divides by zero."""
    scale = np.sqrt(np.max(np.einsum("ij,ij->j", X, M @ X)))
    for _ in range(2):                       # twice is enough (Kahan-Parlett)
        if V.shape[1]:
            X = X - V @ (V.T @ (M @ X))
    G = X.T @ (M @ X)
    lam, U = np.linalg.eigh(0.5 * (G + G.T))
    keep = lam > max((drop * scale) ** 2, GRAM_EPS * lam.max(initial=0.0))
    Y = X @ (U[:, keep] / np.sqrt(lam[keep]))
    if Y.shape[1]:                           # one more pass against round-off
        if V.shape[1]:
            Y = Y - V @ (V.T @ (M @ Y))
        G = Y.T @ (M @ Y)
        lam, U = np.linalg.eigh(0.5 * (G + G.T))
        keep = lam > 0.5
        Y = Y @ (U[:, keep] / np.sqrt(lam[keep]))
    return Y


def reference_operator(system, h, M: sp.csr_matrix) -> sp.csr_matrix:
    """A_ref = K + sum_k h_k H_k + sigma_0 M (module docstring) in CSR, the boundary terms summed
    first: the films' and contacts' matrices hold a few percent of K's entries, so two passes
    over K's pattern instead of one per term (0.03 s instead of 0.3 s at 200 k nodes)."""
    boundary = sum((hk * Hk for hk, Hk in zip(h, system.H)), sp.csr_matrix(system.K.shape))
    return (system.K + (boundary + SIGMA0 * M)).tocsr()


def build_reduced(system, h_refs: list, order: int = 48, gram: bool = True, rtol: float = BASIS_RTOL,
                  blocks: int = 3) -> ReducedModel:
    """Reduce ``system`` (:class:`twin.physics.heat.HeatSystem`) to about ``order`` basis vectors:
    whole blocks of moments at s = 0 of each reference operator A(h) for h in ``h_refs`` (film
    coefficient vectors; the extremes of a run's films when they vary, so that both the spindle
    turning and standing are spanned), taken in turn (module docstring), and at least ``blocks``
    blocks (3: the error estimate compares the basis with its leading blocks less the last two),
    even where they pass ``order`` (a travelling source's path basis gives a block dozens of
    columns wide: seed003-exp1's screws 61 on the coarse mesh). ``gram``: also the residual Gram
    matrix of the verified bound (:func:`residual_gram`; a basis that only starts full-order steps
    does without, and needs no estimate: ``blocks`` 1). ``rtol``: the iterative solves' residual
    reduction on large layouts (:data:`BASIS_RTOL`; :data:`START_BASIS_RTOL` for a basis that only
    starts steps)."""
    import time

    t0 = time.perf_counter()
    M = system.M.tocsr()
    solvers = [_reference_solver(reference_operator(system, h, M), rtol) for h in h_refs]
    solves = [solve for solve, _ in solvers]
    drop = max(DROP, 10.0 * max(rtol for _, rtol in solvers))     # a direction new by less is mostly solver error
    B = np.column_stack([system.F, system.r])
    B = B[:, np.any(B != 0, axis=0)]
    V = np.zeros((M.shape[0], 0))
    starts = [0]
    pending = [B for _ in solves]           # each operator's next right-hand sides, solved when used

    def wanted() -> bool:
        return V.shape[1] < order or len(starts) <= blocks

    while wanted():
        for i, solve in enumerate(solves):
            if pending[i] is None:
                continue
            Y = _m_orthonormalise(solve(pending[i], V), V, M, drop)
            if Y.shape[1] == 0:
                pending[i] = None
                continue
            V = np.hstack([V, Y])
            starts.append(V.shape[1])
            pending[i] = M @ Y if wanted() else None
        if all(x is None for x in pending):
            break
    if len(starts) <= blocks:
        raise InputError("command line", "--rom-order", f"the reduced model needs at least {blocks} blocks of "
                         f"moments to estimate its error; the Krylov space was exhausted at order {V.shape[1]} "
                         f"({len(starts) - 1} blocks): this load set needs no reduction (run the full model)")
    K = V.T @ (system.K @ V)
    H = np.stack([V.T @ (Hk @ V) for Hk in system.H]) if system.H else np.zeros((0, V.shape[1], V.shape[1]))
    gram = residual_gram(system, V) if gram else None
    return ReducedModel(V, 0.5 * (K + K.T), 0.5 * (H + np.transpose(H, (0, 2, 1))), V.T @ system.F,
                        V.T @ system.r, starts[-3] if len(starts) >= 3 else 0, time.perf_counter() - t0, gram)


GRAM_ROWS = 8192     # rows of Y per pass of :func:`residual_gram` (a 16 MB block at 250 columns)


def residual_gram(system, V: np.ndarray) -> np.ndarray:
    """G = Y^T (27 M_L^-1) Y for Y = [M V, K V, H_1 V .. H_m V, F, r_1 .. r_m]: the full-space
    residual of a reduced step is R = Y c (:meth:`ReducedModel.integrate`), so its bounding norm
    rho = (27 R^T M_L^-1 R)^(1/2) (:mod:`twin.physics.solvers`) is (c^T G c)^(1/2).

    Summed over blocks of :data:`GRAM_ROWS` rows in row order, G = sum_b Z_b^T Z_b with
    Z_b = (W^(1/2) Y)_b, each a symmetric rank-k update (exactly symmetric): Y and W Y are never
    formed whole (at 200 k nodes 0.4 GB each, whose first touch cost more than the product), and
    one reused block holds each pass."""
    w = mass_weights(system.M)
    blocks = [A @ V for A in (system.M, system.K, *system.H)] + [system.F, system.r]
    edges = np.cumsum([0] + [b.shape[1] for b in blocks])
    n = V.shape[0]
    root = np.sqrt(w)[:, None]
    G = np.zeros((edges[-1], edges[-1]))
    buffer = np.empty((min(n, GRAM_ROWS), edges[-1]))
    for a in range(0, n, GRAM_ROWS):
        b = min(a + GRAM_ROWS, n)
        Z = buffer[:b - a]
        for k, Yk in enumerate(blocks):
            np.multiply(root[a:b], Yk[a:b], out=Z[:, edges[k]:edges[k + 1]])
        G += Z.T @ Z
    return G


def reduced_basis(twin, loads, h: np.ndarray, rtol: float = BASIS_RTOL, blocks: int = 3) -> ReducedModel:
    """The reduction of ``loads`` on ``twin``, observing nothing yet: built on first use from the
    extremes of the film coefficients ``h`` (nsteps, ncv[, m]), or their value when constant,
    and cached per operator, source patterns and solve tolerance ``rtol`` (:func:`build_reduced`;
    its order the options' ``rom_order``, by default :data:`twin.physics.options.ROM_ORDER` per
    reference operator),
    so later runs with other films reuse it (their error reported). Any layout works, contact
    splits included: the contact matrices are H_k like the films (with r_k = 0). The full-order
    iterative heat steps start from such a basis built to :data:`START_BASIS_RTOL`
    (:func:`start_basis`)."""
    key = (loads.operator_key, hash(np.ascontiguousarray(loads.system.F).tobytes()), rtol, blocks)
    if key not in twin.reduced:
        hh = np.moveaxis(np.asarray(h, float).reshape(len(h), len(loads.convections), -1), 1, 2).reshape(-1, len(loads.convections))
        lo, hi = (hh.min(axis=0), hh.max(axis=0)) if len(hh) else (np.zeros(0), np.zeros(0))
        refs = [lo, hi] if np.any(hi > lo * (1 + 1e-9)) else [hh.mean(axis=0) if len(hh) else lo]
        order = twin.options.rom_order or ROM_ORDER * len(refs)     # the default: 48 per reference operator
        twin.reduced[key] = build_reduced(loads.system, refs, order, gram=False, rtol=rtol, blocks=blocks)
    return twin.reduced[key]


def start_basis(twin, loads, h: np.ndarray) -> ReducedModel:
    """The basis the full-order iterative heat steps start from (:class:`twin.physics.steppers.
    ReducedStart`): :func:`reduced_basis` with its solves to :data:`START_BASIS_RTOL`, one block
    at least (no error estimate is made of it)."""
    return reduced_basis(twin, loads, h, START_BASIS_RTOL, blocks=1)


def bounded_basis(twin, loads, h: np.ndarray) -> ReducedModel:
    """:func:`reduced_basis` with its residual Gram matrix (the verified bound's), added on first
    use and its time counted in ``offline_s``: the whole offline phase of ``--solver rom``."""
    import time

    model = reduced_basis(twin, loads, h)
    if model.gram is None:
        t0 = time.perf_counter()
        model.gram = residual_gram(loads.system, model.V)
        model.offline_s += time.perf_counter() - t0
    return model


def run_basis(twin, loads, h: np.ndarray, bound: bool = True) -> ReducedModel:
    """The basis a ``--solver rom`` run needs: with the verified bound's Gram matrix
    (:func:`bounded_basis`) when ``bound``, else the basis alone (:func:`reduced_basis`)."""
    return bounded_basis(twin, loads, h) if bound else reduced_basis(twin, loads, h)


def reduced_model(twin, loads, outputs, h: np.ndarray, bound: bool = True) -> ReducedModel:
    """The reduced model of ``loads`` on ``twin`` (:func:`run_basis`) observing ``outputs``."""
    return run_basis(twin, loads, h, bound).project_outputs(outputs, mass_weights(loads.system.M))
