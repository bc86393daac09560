"""PSO velocity/position update pinned by closed forms on swarms whose pull is zero or known.

A one-particle swarm whose objective improves at every evaluation has pbest = gbest = x after each
move, so the pull c1 r1 (pbest - x) + c2 r2 (gbest - x) is exactly 0 and v_t = w_t v_{t-1}."""

import itertools

import numpy as np
import pytest

from learners.pso import pso_minimize


def _recording(value):
    seen = []

    def fun(x):
        seen.append(np.array(x, dtype=float))
        return value()

    return fun, seen


def _always_better():
    c = itertools.count()
    return lambda: -float(next(c))


@pytest.mark.parametrize("w,n_it,expected", [((0.9, 0.4), 3, [0.65, 0.4]),
                                             ((0.8, 0.2), 4, [0.6, 0.4, 0.2])])
def test_inertia_weight_decreases_linearly_from_first_to_last_iteration(w, n_it, expected):
    """Zero pull: displacement d_t = w_t d_{t-1}, w_t = w[0] + (w[1] - w[0]) t / (T - 1), t = 0..T-1, so
    successive displacement ratios are w_1, .., w_{T-1} (w[0] on the first iteration, w[1] on the last)."""
    fun, seen = _recording(_always_better())
    pso_minimize(fun, [-1e3] * 3, [1e3] * 3, n_particles=1, n_iterations=n_it, w=w, random_state=5,
                 x0=np.zeros(3))
    d = np.diff(np.array(seen), axis=0)            # (n_it, 3) displacements, no wall reached
    assert np.all(np.abs(d[0]) > 1.0)
    np.testing.assert_allclose(d[1:] / d[:-1], np.repeat(np.array(expected)[:, None], 3, axis=1), rtol=1e-10)


def test_constriction_scales_each_displacement_by_clercs_chi():
    """Zero pull, variant "constriction": v_t = chi v_(t-1) with Clerc and Kennedy's
    chi = 2 / |2 - phi - sqrt(phi^2 - 4 phi)|, phi = c1 + c2 = 4.1 (the defaults 2.0 become 2.05),
    chi = 0.7298437881...; every displacement ratio is chi."""
    fun, seen = _recording(_always_better())
    pso_minimize(fun, [-1e3] * 3, [1e3] * 3, n_particles=1, n_iterations=4, variant="constriction",
                 random_state=5, x0=np.zeros(3))
    d = np.diff(np.array(seen), axis=0)
    assert np.all(np.abs(d[0]) > 1.0)
    chi = 2.0 / abs(2.0 - 4.1 - np.sqrt(4.1 ** 2 - 4 * 4.1))
    assert chi == pytest.approx(0.7298437881, rel=1e-9)
    np.testing.assert_allclose(d[1:] / d[:-1], chi, rtol=1e-10)


def test_absorbing_walls_stop_the_particle():
    """w = 1 and zero pull: x_t = clip(x_0 + t v_0, lower, upper); a component that reaches a bound stays
    there (its velocity is zeroed), it does not bounce back."""
    fun, seen = _recording(_always_better())
    pso_minimize(fun, [0.0] * 3, [1.0] * 3, n_particles=1, n_iterations=80, w=(1.0, 1.0), random_state=3,
                 x0=np.full(3, 0.5))
    x = np.array(seen)
    v0 = x[1] - x[0]
    t = np.arange(len(x))[:, None]
    expected = np.clip(x[0] + t * v0, 0.0, 1.0)
    assert np.any((expected[-1] == 0.0) | (expected[-1] == 1.0))    # premise: some wall is hit
    np.testing.assert_allclose(x, expected, rtol=0, atol=1e-12)


def test_velocity_clamped_to_a_fifth_of_the_box():
    """|v| <= 0.2 (upper - lower) per dimension: no step of any particle moves further, and the clamp binds."""
    fun, seen = _recording(lambda: 0.0)       # no improvement: pbest stays at the start, pulls are large
    lower, upper = np.array([0.0, -5.0]), np.array([1.0, 5.0])
    n_p, n_it = 40, 10
    pso_minimize(fun, lower, upper, n_particles=n_p, n_iterations=n_it, random_state=1)
    x = np.array(seen).reshape(n_it + 1, n_p, 2)
    step = np.abs(np.diff(x, axis=0)) / (upper - lower)
    assert step.max() <= 0.2 + 1e-12
    assert np.isclose(step.max(), 0.2, rtol=0, atol=1e-12)
