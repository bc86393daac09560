"""Seeded particle swarm optimiser (PSO) used by several learners.

Velocity / position update for particle ``i`` at iteration ``t`` (Kennedy & Eberhart 1995;
inertia weight after Shi & Eberhart 1998; constriction after Clerc & Kennedy 2002)::

    v_i <- w_t * v_i + c1 * r1 * (pbest_i - x_i) + c2 * r2 * (gbest - x_i)      variant="inertia"
    v_i <- chi * (v_i + c1 * r1 * (pbest_i - x_i) + c2 * r2 * (gbest - x_i))    variant="constriction"
    x_i <- clip(x_i + v_i, lower, upper)

with ``r1, r2 ~ U(0, 1)`` drawn per dimension, ``w_t`` decreasing linearly from ``w[0]`` (first
iteration) to ``w[1]`` (last iteration), and ``chi = 2 / |2 - phi - sqrt(phi^2 - 4 phi)|`` with
``phi = c1 + c2 > 4``. Velocities are clamped to ``+/- 0.2 (upper - lower)`` per dimension, and a
particle that hits a bound stops there (that velocity component is zeroed: "absorbing walls").

This is the thesis's Eqs. (3.15)-(3.16) / (A.7)-(A.8) (seed 000 L2551-2574, L7580-7657), which
print one random factor ``R`` for both terms; independent ``r1, r2`` per dimension are the standard
form and are used here.

The optimiser is minimising, box-bounded and fully deterministic for a given ``random_state``
(it draws from one :class:`numpy.random.Generator`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from learners._checks import check_seed

__all__ = ["PSOResult", "pso_minimize"]


@dataclass(frozen=True)
class PSOResult:
    """Outcome of :func:`pso_minimize`.

    ``x``: best position found (1-D array); ``fun``: objective at ``x``; ``n_evaluations``: number
    of objective calls; ``history``: best objective value after each iteration (length
    ``n_iterations``; non-increasing).
    """

    x: np.ndarray
    fun: float
    n_evaluations: int
    history: np.ndarray = field(repr=False)


def _evaluate(fun, x: np.ndarray) -> float:
    value = float(fun(x))
    # A non-finite objective (overflow in a model, say) is treated as the worst possible value.
    return value if np.isfinite(value) else np.inf


def pso_minimize(
    fun,
    lower,
    upper,
    *,
    n_particles=30,
    n_iterations=100,
    variant="inertia",
    w=(0.9, 0.4),
    c1=2.0,
    c2=2.0,
    random_state=None,
    x0=None,
) -> PSOResult:
    """Minimise ``fun`` over the box ``[lower, upper]`` with a particle swarm.

    Parameters
    ----------
    fun : callable
        Maps a 1-D array of length ``d`` to a float.
    lower, upper : array-like, shape (d,)
        Box bounds (``lower <= upper`` element-wise).
    n_particles, n_iterations : int
        Swarm size and number of update iterations (the initial swarm is evaluated first, so
        ``n_evaluations = n_particles * (n_iterations + 1)``).
    variant : {"inertia", "constriction"}
        ``"inertia"``: linearly decreasing inertia weight from ``w[0]`` to ``w[1]``.
        ``"constriction"``: Clerc-Kennedy factor ``chi`` (``w`` is ignored). Needs
        ``phi = c1 + c2 > 4``; when ``c1`` and ``c2`` are both left at their default 2.0 they
        become 2.05 each (the standard ``chi ~= 0.7298``).
    w : (float, float)
        Start and end inertia weights of the ``"inertia"`` variant.
    c1, c2 : float
        Cognitive and social acceleration coefficients.
    random_state : None, int or numpy.random.Generator
        Seed for the initial swarm and the random factors.
    x0 : array-like, shape (d,), optional
        Seeds particle 0 (clipped to the bounds) so that a known good guess is never lost.
    """
    lower = np.atleast_1d(np.asarray(lower, dtype=float)).ravel()
    upper = np.atleast_1d(np.asarray(upper, dtype=float)).ravel()
    if lower.shape != upper.shape:
        raise ValueError(f"lower and upper differ in shape: {lower.shape} vs {upper.shape}")
    if np.any(upper < lower) or not (np.all(np.isfinite(lower)) and np.all(np.isfinite(upper))):
        raise ValueError("bounds must be finite with lower <= upper")
    n_particles = int(n_particles)
    n_iterations = int(n_iterations)
    if n_particles < 1 or n_iterations < 0:
        raise ValueError("n_particles must be >= 1 and n_iterations >= 0")
    if variant == "constriction":
        if c1 == 2.0 and c2 == 2.0:
            c1 = c2 = 2.05
        phi = c1 + c2
        if phi <= 4.0:
            raise ValueError(f"constriction needs c1 + c2 > 4, got {phi}")
        chi = 2.0 / abs(2.0 - phi - np.sqrt(phi * phi - 4.0 * phi))
    elif variant != "inertia":
        raise ValueError(f"unknown PSO variant {variant!r}; use 'inertia' or 'constriction'")

    rng = random_state if isinstance(random_state, np.random.Generator) else \
        np.random.default_rng(check_seed("pso", random_state))
    d = lower.size
    span = upper - lower
    v_max = 0.2 * span
    pos = lower + rng.random((n_particles, d)) * span
    if x0 is not None:
        pos[0] = np.clip(np.asarray(x0, dtype=float).ravel(), lower, upper)
    vel = rng.uniform(-1.0, 1.0, (n_particles, d)) * 0.1 * span

    values = np.array([_evaluate(fun, p) for p in pos])
    n_eval = n_particles
    pbest = pos.copy()
    pbest_val = values.copy()
    g = int(np.argmin(pbest_val))
    gbest, gbest_val = pbest[g].copy(), pbest_val[g]
    history = np.empty(n_iterations)

    for t in range(n_iterations):
        r1 = rng.random((n_particles, d))
        r2 = rng.random((n_particles, d))
        pull = c1 * r1 * (pbest - pos) + c2 * r2 * (gbest - pos)
        if variant == "inertia":
            frac = t / (n_iterations - 1) if n_iterations > 1 else 0.0
            w_t = w[0] + (w[1] - w[0]) * frac
            vel = w_t * vel + pull
        else:
            vel = chi * (vel + pull)
        vel = np.clip(vel, -v_max, v_max)
        moved = pos + vel
        pos = np.clip(moved, lower, upper)
        vel[moved != pos] = 0.0  # absorbing walls: a particle that hits a bound stops there
        values = np.array([_evaluate(fun, p) for p in pos])
        n_eval += n_particles
        better = values < pbest_val
        pbest[better] = pos[better]
        pbest_val[better] = values[better]
        g = int(np.argmin(pbest_val))
        if pbest_val[g] < gbest_val:
            gbest, gbest_val = pbest[g].copy(), pbest_val[g]
        history[t] = gbest_val

    return PSOResult(x=gbest, fun=float(gbest_val), n_evaluations=n_eval, history=history)


def box_edges(x, lower, upper, names, free_lower=()) -> str:
    """Which components of a PSO solution ``x`` lie on the search box's edge (within 1e-9 of its
    width), as "sit at the search box's bound (a, b)"; "" when none: a component on the edge is
    where the search stopped, not a value the data chose. ``free_lower``: names whose lower end
    is a meaningful value (a zero weight), not counted there."""
    x, lower, upper = (np.asarray(v, dtype=float) for v in (x, lower, upper))
    tol = 1e-9 * (upper - lower)
    low = (x - lower <= tol) & ~np.isin(np.asarray(names), list(free_lower))
    hit = [n for n, e in zip(names, low | (upper - x <= tol)) if e]
    return f"sit at the search box's bound ({', '.join(hit)})" if hit else ""
