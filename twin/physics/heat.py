"""Transient heat conduction by the theta-scheme, one factorisation per distinct operator.

    M dT/dt + (K + sum_k h_k(t) H_k) T = sum_j b_j s_j(t) + sum_k h_k(t) T_air,k(t) r_k

Step n -> n+1 (length dt), with A_n = K + sum_k h_k(t_n+theta) H_k and f_n = f(t_n + theta dt):

    (M + theta dt A_n) T^(n+1) = (M - (1 - theta) dt A_n) T^n + dt f_n

theta = 1/2 is Crank-Nicolson (second order), theta = 1 implicit Euler (first order). Loads are
evaluated at t_n + theta dt (:func:`twin.signals.load_instants`; at theta = 1 just inside the
step, since an input step holds its value on [start, end) and t_(n+1) would read the next one),
which is exact for piecewise-constant inputs whose changes fall on the grid. Because 1^T K = 0
and 1^T H_k T = int T dA, the scheme conserves energy exactly:
1^T M (T^(n+1) - T^n) = dt (sum_j s_j 1^T b_j + sum_k h_k (T_air,k A_k - r_k^T T^(n+theta))).

Piecewise-constant spindle schedules give few distinct h vectors, so few factorisations; each
step is then one back-substitution and two sparse products. Large meshes solve each step by
warm-started PCG instead (:mod:`twin.physics.steppers`, with a verified bound on the error it adds).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from twin.physics import parallel
from twin.physics.solvers import to_host
from twin.physics.steppers import DirectStepper


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
              factorisations: dict | None = None, operator_key: tuple = (), stepper=None) -> np.ndarray:
    """Integrate ``nsteps`` steps of length ``dt`` [s] from ``T0`` [degC].

    h (nsteps, ncv) [W/(m2 K)], air (nsteps, ncv) [degC] and s (nsteps, nsrc) [W] hold the
    signals at t_n + theta dt. Returns ``outputs @ T`` at every step, shape (nsteps+1, nout).
    ``on_step(n, T)`` is called after each step with the new field (progress, snapshots).

    Batched cases (multiple right-hand sides, one operator): ``T0`` (n, m), ``air`` (nsteps,
    ncv, m) and ``s`` (nsteps, nsrc, m) give outputs (nsteps+1, nout, m); the film coefficients
    ``h`` are shared by all cases.

    ``stepper`` solves each step (:mod:`twin.physics.steppers`: direct LU or warm-started PCG on
    the CPU or a GPU); by default a direct stepper whose factorisations live in
    ``factorisations``: a dict kept by the caller across runs (:class:`twin.physics.prepared.
    PreparedTwin`), keyed by ``operator_key`` (which must identify M, K and the H_k: the layout
    and the convection loads), dt, theta and the film coefficients, so a factorised operator is
    reused by every later run with the same operator.
    """
    if not 0.5 <= theta <= 1.0:
        raise ValueError("theta must lie in [1/2, 1] (unconditionally stable range)")
    stepper = stepper if stepper is not None else DirectStepper(factorisations)
    xp = stepper.xp
    stepper.begin(nsteps, system)
    to_dev = (lambda a: a) if xp is np else xp.asarray
    T = to_dev(np.array(T0, dtype=float))
    batched = T.ndim == 2
    F, r = to_dev(system.F), to_dev(system.r)
    W = parallel.split_matrix(outputs) if xp is np else stepper._matrix(sp.csr_matrix(outputs))
    out = np.empty((nsteps + 1, outputs.shape[0]) + ((T.shape[1],) if batched else ()))
    out[0] = to_host(xp, W @ T)
    # BLAS on one thread on the CPU, whatever the model's size: the same numbers on any machine,
    # and SuperLU's back-substitution, a chain of small supernode BLAS calls, runs faster without
    # OpenBLAS's threads (default mesh: 6 against 11 ms a solve, several right-hand sides 7x faster);
    # a large model's products run in row blocks on two threads (:mod:`twin.physics.parallel`)
    with parallel.single_blas(xp is np):
        for n in range(nsteps):
            key = (operator_key, float(dt), float(theta), tuple(np.round(h[n], 12)))
            op = stepper.operator(key, system, dt, theta, h[n])
            if batched:
                f = F @ to_dev(s[n]) + r @ to_dev(h[n][:, None] * air[n])
            else:
                f = F @ to_dev(s[n]) + r @ to_dev(h[n] * air[n])
            T = stepper.solve(op, stepper.rhs_operator(op) @ T + dt * f, T)
            out[n + 1] = to_host(xp, W @ T)
            if on_step is not None:
                on_step(n + 1, to_host(xp, T))
    return out


def integrate_responses(system: HeatSystem, dt: float, nsteps: int, h: np.ndarray, patterns: np.ndarray,
                        signals: np.ndarray, outputs: sp.spmatrix, theta: float = 1.0, stepper=None,
                        operator_key: tuple = ()) -> np.ndarray:
    """Responses of ``outputs`` to extra heat inputs, all at once: J patterns b_j (columns of
    ``patterns`` (n, J), each integrating to 1) driven by signals s_j(t) [W] (``signals``
    (nsteps, J) at t_n + theta dt), on the operators of ``system`` with film coefficients ``h``.

    The heat equation is linear in its sources, so the response to an added source is the
    solution X_j of the same scheme with zero start, no air and that source alone:

        (M + theta dt A_n) X^(n+1) = (M - (1 - theta) dt A_n) X^n + dt b s_n,   X^0 = 0,

    solved for the J columns with one operator per step from ``stepper`` (a CPU stepper of
    :mod:`twin.physics.steppers`; default a direct one), whose cache :func:`integrate` shares
    (same keys). Returns (nsteps+1, nout, J).
    """
    stepper = stepper if stepper is not None else DirectStepper()
    if stepper.xp is not np:
        raise ValueError("integrate_responses runs on the CPU")
    stepper.begin(nsteps, system)
    X = np.zeros(patterns.shape)
    out = np.zeros((nsteps + 1, outputs.shape[0], patterns.shape[1]))
    with parallel.single_blas():     # as in :func:`integrate`
        for n in range(nsteps):
            key = (operator_key, float(dt), float(theta), tuple(np.round(h[n], 12)))
            op = stepper.operator(key, system, dt, theta, h[n])
            rhs = stepper.rhs_operator(op) @ X + dt * patterns * signals[n]
            X = stepper.solve(op, rhs, X)   # direct: SuperLU's multi-right-hand side, BLAS on one thread
            out[n + 1] = outputs @ X
    return out


def steady_state(system: HeatSystem, h: np.ndarray, air: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Solve (K + sum h_k H_k) T = F s + sum h_k T_air,k r_k for constant signals."""
    A = system.K + sum((hk * Hk for hk, Hk in zip(h, system.H)), sp.csr_matrix(system.K.shape))
    return spla.spsolve(A.tocsc(), system.F @ s + system.r @ (h * air))
