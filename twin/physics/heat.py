"""Transient heat conduction by the theta-scheme, one factorisation per distinct operator.

    M dT/dt + (K + sum_k h_k(t) H_k) T = sum_j b_j s_j(t) + sum_k h_k(t) T_air,k(t) r_k

Step n -> n+1 (length dt), with A_n = K + sum_k h_k(t_n+theta) H_k and f_n = f(t_n + theta dt):

    (M + theta dt A_n) T^(n+1) = (M - (1 - theta) dt A_n) T^n + dt f_n

theta = 1/2 is Crank-Nicolson (second order), theta = 1 implicit Euler (first order). Loads are
evaluated at t_n + theta dt, which is exact for piecewise-constant inputs whose changes fall on
the grid. Because 1^T K = 0 and 1^T H_k T = int T dA, the scheme conserves energy exactly:
1^T M (T^(n+1) - T^n) = dt (sum_j s_j 1^T b_j + sum_k h_k (T_air,k A_k - r_k^T T^(n+theta))).

Piecewise-constant spindle schedules give few distinct h vectors, so few factorisations; each
step is then one back-substitution and two sparse products.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


MAX_FACTORISATIONS = 12   # kept per cache; each is tens of MB on a default mesh


@dataclass
class HeatSystem:
    """Matrices of M dT/dt + (K + sum h_k H_k) T = F s(t) + sum h_k T_air,k r_k."""

    M: sp.csr_matrix
    K: sp.csr_matrix
    H: list            # convection matrices H_k [m2]
    r: np.ndarray      # (n, ncv) convection load vectors r_k [m2]
    F: np.ndarray      # (n, nsrc) source patterns, each integrating to 1 (so s_j is in W)


def integrate(system: HeatSystem, T0: np.ndarray, dt: float, nsteps: int, h: np.ndarray, air: np.ndarray,
              s: np.ndarray, outputs: sp.spmatrix, theta: float = 0.5,
              on_step: Callable[[int, np.ndarray], None] | None = None,
              factorisations: dict | None = None, operator_key: tuple = ()) -> np.ndarray:
    """Integrate ``nsteps`` steps of length ``dt`` [s] from ``T0`` [degC].

    h (nsteps, ncv) [W/(m2 K)], air (nsteps, ncv) [degC] and s (nsteps, nsrc) [W] hold the
    signals at t_n + theta dt. Returns ``outputs @ T`` at every step, shape (nsteps+1, nout).
    ``on_step(n, T)`` is called after each step with the new field (progress, snapshots).
    ``factorisations``: a dict kept by the caller across runs (:class:`twin.physics.prepared.
    PreparedTwin`), keyed by ``operator_key`` (which must identify M, K and the H_k: the layout
    and the convection loads), dt, theta and the film coefficients, so a factorised operator is
    reused by every later run with the same operator.
    """
    if not 0.5 <= theta <= 1.0:
        raise ValueError("theta must lie in [1/2, 1] (unconditionally stable range)")
    cache: dict[tuple, tuple] = {} if factorisations is None else factorisations
    T = np.array(T0, dtype=float)
    out = np.empty((nsteps + 1, outputs.shape[0]))
    out[0] = outputs @ T
    for n in range(nsteps):
        lu, rhs_op = _factorised(system, dt, theta, h[n], cache, operator_key)
        f = system.F @ s[n] + system.r @ (h[n] * air[n])
        T = lu.solve(rhs_op @ T + dt * f)
        out[n + 1] = outputs @ T
        if on_step is not None:
            on_step(n + 1, T)
    return out


def integrate_responses(system: HeatSystem, dt: float, nsteps: int, h: np.ndarray, patterns: np.ndarray,
                        signals: np.ndarray, outputs: sp.spmatrix, theta: float = 1.0,
                        factorisations: dict | None = None, operator_key: tuple = ()) -> np.ndarray:
    """Responses of ``outputs`` to extra heat inputs, all at once: J patterns b_j (columns of
    ``patterns`` (n, J), each integrating to 1) driven by signals s_j(t) [W] (``signals``
    (nsteps, J) at t_n + theta dt), on the operators of ``system`` with film coefficients ``h``.

    The heat equation is linear in its sources, so the response to an added source is the
    solution X_j of the same scheme with zero start, no air and that source alone:

        (M + theta dt A_n) X^(n+1) = (M - (1 - theta) dt A_n) X^n + dt b s_n,   X^0 = 0,

    solved for the J columns on one factorisation (J back-substitutions per step).
    Returns (nsteps+1, nout, J). Factorisations are shared with :func:`integrate` (same keys).
    """
    cache: dict[tuple, tuple] = {} if factorisations is None else factorisations
    X = np.zeros(patterns.shape)
    out = np.zeros((nsteps + 1, outputs.shape[0], patterns.shape[1]))
    for n in range(nsteps):
        lu, rhs_op = _factorised(system, dt, theta, h[n], cache, operator_key)
        rhs = rhs_op @ X + dt * patterns * signals[n]
        # column by column: SuperLU's multi-right-hand-side solve is about 10x slower here
        X = np.column_stack([lu.solve(rhs[:, j]) for j in range(rhs.shape[1])])
        out[n + 1] = outputs @ X
    return out


def _factorised(system: HeatSystem, dt: float, theta: float, h_n: np.ndarray, cache: dict, operator_key: tuple):
    """(LU of M + theta dt A, M - (1 - theta) dt A) for film coefficients ``h_n``, from ``cache``."""
    key = (operator_key, float(dt), float(theta), tuple(np.round(h_n, 12)))
    if key not in cache:
        while len(cache) >= MAX_FACTORISATIONS:   # oldest first: a fit that varies h makes many operators
            cache.pop(next(iter(cache)))
        A = system.K + sum((hk * Hk for hk, Hk in zip(h_n, system.H) if hk != 0), sp.csr_matrix(system.K.shape))
        lhs = (system.M + theta * dt * A).tocsc()
        rhs_op = (system.M - (1.0 - theta) * dt * A).tocsr()
        cache[key] = (spla.splu(lhs, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                options={"SymmetricMode": True}), rhs_op)
    return cache[key]


def steady_state(system: HeatSystem, h: np.ndarray, air: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Solve (K + sum h_k H_k) T = F s + sum h_k T_air,k r_k for constant signals."""
    A = system.K + sum((hk * Hk for hk, Hk in zip(h, system.H)), sp.csr_matrix(system.K.shape))
    return spla.spsolve(A.tocsc(), system.F @ s + system.r @ (h * air))
