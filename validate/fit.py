"""Bounded least squares of candidate responses and bounded nuisances to a weighted residual.

All vectors are flat: the residual r (N,) of every channel of every measurement, the weights
w (N,), a candidate's response g (N,). The nuisance is k response columns n_j (N,), e.g. the
response of every observable to a unit relative change of material j's expansion coefficient,
each with a plausible band [lo_j, hi_j] (the material's declared spread). For candidate
responses with parameters x (bounds [a, b]) the fit is

    min_{a <= x <= b, lo <= c <= hi}  || w * (r - G x - N c) ||^2

by ``scipy.optimize.lsq_linear`` (bounded-variable least squares): the nuisance is fitted
jointly with every candidate, never freely, so it cannot absorb an error that the materials'
plausible spread does not cover. A nuisance at its bound says exactly that.

Nonlinear responses (film coefficients, conductances) are fitted by bounded Gauss-Newton: at
p_k, with g_k = g(p_k) and J_k = dg/dp by forward differences (step 2 % of the parameter),
solve the bounded linear problem above for the step d (a - p_k <= d <= b - p_k), keep p_k + d
if it lowers the weighted sum of squares, else halve d (twice at most); stop when the step is
below 0.1 % of the parameter or after ``iterations``.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import lsq_linear

BOUND_TOL = 1e-3   # a fitted value within this fraction of its range's width of a bound is at it


class BoundedFitter:
    """Weighted residual ``r`` (N,), weights ``w`` (N,), nuisance columns ``nuisance`` (k, N) with
    bounds ``lower``/``upper`` (k,) (none: k = 0)."""

    def __init__(self, r: np.ndarray, w: np.ndarray, nuisance: np.ndarray | None = None,
                 lower=(), upper=()):
        self.r, self.w = np.asarray(r, float), np.asarray(w, float)
        self.N = (np.zeros((0, len(self.r))) if nuisance is None or len(nuisance) == 0
                  else np.asarray(nuisance, float))
        self.lo, self.hi = np.asarray(lower, float), np.asarray(upper, float)
        self._wN = (self.N * self.w).T   # (N, k)

    @property
    def k(self) -> int:
        return len(self.N)

    def solve(self, cols: np.ndarray, lower, upper, target: np.ndarray | None = None):
        """Bounded fit of ``cols`` (N, m) (bounds ``lower``/``upper``, m each) plus the nuisance to
        ``target`` (default r). Returns (x (m,), c (k,), weighted SSE)."""
        target = self.r if target is None else target
        cols = np.asarray(cols, float).reshape(len(self.r), -1)
        m = cols.shape[1]
        A = np.hstack([cols * self.w[:, None], self._wN])
        b = target * self.w
        if A.shape[1] == 0:
            return np.zeros(0), np.zeros(0), float(b @ b)
        lo = np.concatenate([np.asarray(lower, float).ravel(), self.lo])
        hi = np.concatenate([np.asarray(upper, float).ravel(), self.hi])
        fixed = lo >= hi   # a zero-width bound: the variable is pinned
        sol = np.clip(np.zeros(A.shape[1]), lo, hi)
        free = ~fixed
        if free.any() and np.any(A[:, free]):
            rhs = b - A[:, fixed] @ lo[fixed]
            sol[free] = lsq_linear(A[:, free], rhs, bounds=(lo[free], hi[free]), method="bvls").x
        sol[fixed] = lo[fixed]
        res = b - A @ sol
        return sol[:m], sol[m:], float(res @ res)

    def nuisance(self, g: np.ndarray) -> np.ndarray:
        """The nuisance amplitudes c fitted (within their bounds) to r - g."""
        return self.solve(np.zeros((len(self.r), 0)), [], [], self.r - g)[1]

    def sse(self, g: np.ndarray) -> float:
        """Weighted SSE of r - g with the nuisance fitted to it."""
        return self.solve(np.zeros((len(self.r), 0)), [], [], self.r - g)[2]

    def residual_after(self, g: np.ndarray) -> np.ndarray:
        """r - g - N c, c the nuisance fitted to r - g (native units)."""
        c = self.nuisance(g)
        return self.r - g - c @ self.N if self.k else self.r - g

    def at_bound(self, c: np.ndarray, tol: float = BOUND_TOL) -> np.ndarray:
        """Which nuisance amplitudes sit at a bound (within ``tol`` of the band's width)."""
        return at_bounds(c, self.lo, self.hi, tol)


def at_bounds(values, lower, upper, tol: float = BOUND_TOL) -> np.ndarray:
    """Which ``values`` sit at a bound of their range [``lower``, ``upper``]: within ``tol`` of
    the range's width of either end (the nuisance's bands and the candidates' ranges alike)."""
    values, lower, upper = (np.asarray(a, dtype=float) for a in (values, lower, upper))
    width = np.maximum(upper - lower, 1e-300)
    return (np.abs(values - lower) <= tol * width) | (np.abs(values - upper) <= tol * width)


def gauss_newton(fitter: BoundedFitter, evaluate, p0: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                 linear: np.ndarray, columns: dict, iterations: int = 6):
    """Bounded Gauss-Newton for parameters p (m,) whose response is ``evaluate(p)`` (N,).

    ``linear[i]``: the response is affine in p_i with the known column ``columns[i]`` (no finite
    difference needed); the others get forward differences. Returns (p, g, sse) of the best point
    seen, and the number of evaluations."""
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    p = np.clip(np.asarray(p0, float), lower, upper)
    g = evaluate(p)
    best = (fitter.sse(g), p.copy(), g)
    evals = 1
    span = upper - lower
    for _ in range(iterations):
        J = np.empty((len(g), len(p)))
        for i in range(len(p)):
            if linear[i]:
                J[:, i] = columns[i]
                continue
            dp = 0.02 * max(abs(p[i]), 1e-3 * span[i])
            if p[i] + dp > upper[i]:
                dp = -dp
            q = p.copy()
            q[i] += dp
            J[:, i] = (evaluate(q) - g) / dp
            evals += 1
        step = fitter.solve(J, lower - p, upper - p, fitter.r - g)[0]
        improved = False
        for _ in range(3):
            trial = np.clip(p + step, lower, upper)
            g_t = evaluate(trial)
            evals += 1
            s_t = fitter.sse(g_t)
            if s_t < best[0]:
                best = (s_t, trial.copy(), g_t)
                improved = True
                break
            step = step / 2
        if not improved:
            break
        moved = np.abs(trial - p) > 1e-3 * np.maximum(np.abs(p), 1e-6 * span)
        p, g = trial, g_t
        if not moved.any():
            break
    return best[1], best[2], best[0], evals
