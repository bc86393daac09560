"""PSO finds the known minima of standard test functions (both variants) and is seeded."""

import numpy as np
import pytest

from learners.pso import PSOResult, pso_minimize


def sphere(x):
    return float(np.sum(x**2))


def rosenbrock(x):
    return float(100.0 * (x[1] - x[0] ** 2) ** 2 + (1.0 - x[0]) ** 2)


def rastrigin(x):
    return float(10.0 * x.size + np.sum(x**2 - 10.0 * np.cos(2.0 * np.pi * x)))


# (function, half-width of the box, known minimiser, tolerance on |x - x*|, tolerance on f)
CASES = [
    (sphere, 5.12, np.zeros(2), 1e-4, 1e-8),  # min 0 at the origin
    (rosenbrock, 2.048, np.ones(2), 1e-2, 1e-4),  # min 0 at (1, 1)
    (rastrigin, 5.12, np.zeros(2), 1e-4, 1e-6),  # global min 0 at the origin
]


@pytest.mark.parametrize("variant", ["inertia", "constriction"])
@pytest.mark.parametrize("fun,half,xstar,xtol,ftol", CASES, ids=["sphere", "rosenbrock", "rastrigin"])
def test_known_minima(variant, fun, half, xstar, xtol, ftol):
    res = pso_minimize(fun, [-half] * 2, [half] * 2, n_iterations=200, variant=variant, random_state=0)
    assert isinstance(res, PSOResult)
    assert res.fun <= ftol
    np.testing.assert_allclose(res.x, xstar, atol=xtol)


def test_result_bookkeeping_and_bounds():
    res = pso_minimize(sphere, [1.0, 2.0], [3.0, 4.0], n_particles=10, n_iterations=25, random_state=3)
    assert res.n_evaluations == 10 * 26
    assert res.history.shape == (25,)
    assert np.all(np.diff(res.history) <= 0)
    assert res.history[-1] == res.fun
    # constrained minimum of the sphere on the box is the corner (1, 2), value 5
    np.testing.assert_allclose(res.x, [1.0, 2.0], atol=1e-6)


def test_deterministic_for_seed_and_varies_otherwise():
    a = pso_minimize(rastrigin, [-5.12] * 3, [5.12] * 3, n_iterations=20, random_state=7)
    b = pso_minimize(rastrigin, [-5.12] * 3, [5.12] * 3, n_iterations=20, random_state=7)
    c = pso_minimize(rastrigin, [-5.12] * 3, [5.12] * 3, n_iterations=20, random_state=8)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.history, b.history)
    assert not np.array_equal(a.history, c.history)


def test_x0_seeds_a_particle():
    # With no iterations the best is the best of the initial swarm, which includes x0 (the optimum).
    res = pso_minimize(sphere, [-5] * 4, [5] * 4, n_iterations=0, x0=np.zeros(4), random_state=1)
    assert res.fun == 0.0


def test_bad_arguments():
    with pytest.raises(ValueError):
        pso_minimize(sphere, [0.0], [1.0], variant="nope")
    with pytest.raises(ValueError):
        pso_minimize(sphere, [0.0], [1.0], variant="constriction", c1=1.0, c2=1.0)
    with pytest.raises(ValueError):
        pso_minimize(sphere, [1.0], [0.0])
