"""Iterative heat steps, verified on a small slab against the direct factorisation and against
exact answers: PCG within its verified bound, each step within its share of the run's tolerance,
and the starts CG is given (extrapolation, Fischer's projection, the reduced basis's Galerkin start)
as good as their definitions promise. The machine-sized runs are in ``tests/test_scale.py``."""

from __future__ import annotations

import numpy as np
import pytest

from tests.conftest import box_body, face
from twin.fem.assembly import assemble_facets, assemble_heat
from twin.physics.heat import HeatSystem, integrate
from twin.physics.options import SolverOptions
from twin.physics.solvers import Projection, mass_weights, output_bounds
from twin.physics.steppers import DirectStepper, IterativeStepper


def _cooled_slab(steps: int):
    """A steel slab heated through one face at 50 W and cooled there by h = 300 W/(m2 K) to 15 degC
    air, from 20 degC: (heat matrices, system, n, the integrate arguments for ``steps`` 30 s steps,
    observing every 7th node)."""
    mm = box_body((0.2, 0.05, 0.05), 0.01, surfaces=[("cooled", face(0, 0.2))])
    heat = assemble_heat(mm)
    fm = assemble_facets(mm, mm.facets["cooled"])
    system = HeatSystem(heat.M, heat.K, [fm.H], fm.r[:, None], (fm.r / fm.area)[:, None])
    n = mm.nnodes
    args = (np.full(n, 20.0), 30.0, steps, np.full((steps, 1), 300.0), np.full((steps, 1), 15.0),
            np.full((steps, 1), 50.0), np.eye(n)[::7])
    return heat, system, n, args


def test_pcg_steps_equal_direct_ones_within_the_verified_bound():
    """A slab cooled on one face: PCG with extrapolated start vs sparse LU, 200 CN steps. Each output
    errs by at most (27 w^T M_L^-1 w)^(1/2) sum_n rho_n (||A^-1 r||_M <= (r^T M^-1 r)^(1/2), M-contraction
    of the theta-scheme), and that bound is below ``heat_tol`` sqrt(C) times the row norm."""
    heat, system, n, args = _cooled_slab(200)
    direct = integrate(system, *args, stepper=DirectStepper())
    it = IterativeStepper(heat_tol=1e-4)
    iterative = integrate(system, *args, stepper=it)
    bound = output_bounds(np.eye(n)[::7], mass_weights(heat.M), float(it.rho_sum))
    err = np.abs(iterative - direct).max(axis=0)
    assert np.all(err <= bound) and err.max() > 0
    assert float(it.rho_sum) <= 1e-4 * np.sqrt(heat.M.sum()) * (1 + 1e-12)
    assert 0 < np.mean(it.iterations) < 30


def test_projected_start_is_no_worse_than_extrapolation_and_saves_iterations():
    """Fischer's projection: x0 = Q Q^T b with Q A-orthonormal over the recent solutions is the
    A-norm best point of a span that holds x_n and x_(n-1), so ||x0 - x||_A <= ||2 x_n - x_(n-1) - x||_A
    at every step (restarts included); on the slab's 200 steps it needs fewer PCG iterations."""
    heat, system, n, args = _cooled_slab(200)
    lhs = (system.M + 0.5 * 30.0 * (system.K + 300.0 * system.H[0])).tocsr()
    rng = np.random.default_rng(3)
    exact = np.cumsum(rng.standard_normal((12, lhs.shape[0])) * 0.1, axis=0) + 1.0   # a smooth sequence
    proj = Projection(lambda v: lhs @ v, 4)
    proj.add(exact[0])
    proj.add(exact[1])
    energy = lambda e: float(e @ (lhs @ e))
    for k in range(2, len(exact)):
        x = exact[k]
        x0 = proj.guess(lhs @ x)
        assert energy(x0 - x) <= energy(2 * exact[k - 1] - exact[k - 2] - x) * (1 + 1e-10)
        proj.add(x)
    plain, projected = IterativeStepper(heat_tol=1e-4, projection_size=0), IterativeStepper(heat_tol=1e-4)
    a, b = integrate(system, *args, stepper=plain), integrate(system, *args, stepper=projected)
    bound = output_bounds(np.eye(n)[::7], mass_weights(heat.M), float(plain.rho_sum + projected.rho_sum))
    assert np.all(np.abs(a - b).max(axis=0) <= bound)
    assert sum(projected.iterations) < sum(plain.iterations)


def test_reduced_start_is_the_a_norm_best_point_of_its_span_and_exact_on_it():
    """ReducedStart: x0 = T + V (V^T A V)^-1 V^T (b - A T) is the Galerkin projection of the
    increment x - T on span(V), so ||x0 - x||_A <= ||T + V y - x||_A for every y, and x0 = x when
    the increment lies in span(V) (then CG needs no iteration). The passes over V run in single
    precision (a basis in single precision here, so that its span is the stored one): both hold to
    single precision's round-off of the correction, about 1e-7 of it."""
    from twin.physics.steppers import ReducedStart
    heat, system, n, args = _cooled_slab(3)
    lhs = (system.M + 0.5 * 30.0 * (system.K + 300.0 * system.H[0])).tocsr()
    rng = np.random.default_rng(5)
    V = rng.standard_normal((n, 9)).astype(np.float32).astype(float)
    start, op = ReducedStart(V), (lhs,)
    T, x = 20.0 + rng.standard_normal(n), 20.0 + rng.standard_normal(n)
    b = lhs @ x
    x0 = start.guess(op, lhs, b, T)
    energy = lambda e: float(e @ (lhs @ e))
    for y in rng.standard_normal((20, 9)):
        assert energy(x0 - x) <= energy(T + V @ y - x) * (1 + 1e-6)
    y = rng.standard_normal(9)
    inside = T + V @ y                                          # an increment the basis spans
    np.testing.assert_allclose(start.guess(op, lhs, lhs @ inside, T), inside, rtol=0, atol=1e-6 * np.abs(V @ y).max())
    X = np.column_stack([x, inside])                            # a block: the same, column by column
    np.testing.assert_allclose(start.guess(op, lhs, lhs @ X, np.column_stack([T, T]))[:, 0], x0, rtol=0,
                               atol=1e-6 * np.abs(x0 - T).max())


def test_heat_start_option_and_its_auto_rule():
    """auto starts from the reduced basis from REDUCED_START_STEPS steps on; the named starts
    always or never; an unknown name is refused naming the option."""
    from twin.errors import InputError
    from twin.physics.options import REDUCED_START_STEPS
    auto = SolverOptions("iterative")
    assert not auto.reduced_start(REDUCED_START_STEPS - 1) and auto.reduced_start(REDUCED_START_STEPS)
    assert SolverOptions("iterative", heat_start="reduced").reduced_start(1)
    assert not SolverOptions("iterative", heat_start="projection").reduced_start(10 ** 6)
    with pytest.raises(InputError, match="--heat-start"):
        SolverOptions("iterative", heat_start="fischer")


def _uniformly_heated_slab():
    """The slab of :func:`_cooled_slab` without its film, heated by P = 100 W spread as its
    capacity (F = M 1 / C): K 1 = 0, so T^n = T_0 + P t_n / C exactly, a field linear in time, at any
    theta: (system, n, C)."""
    heat, _, n, _ = _cooled_slab(1)
    capacity = float(heat.M.sum())
    uniform = HeatSystem(heat.M, heat.K, [], np.zeros((n, 0)), (np.asarray(heat.M.sum(axis=1)).ravel() / capacity)[:, None])
    return uniform, n, capacity


@pytest.mark.parametrize("start", ["extrapolation", "reduced"])
def test_the_starts_are_exact_for_a_field_linear_in_time(start, monkeypatch):
    """For a field linear in time the extrapolation E = 2 T^n - T^(n-1) is the next step's solution
    itself, and so is the reduced start E + V (V^T A V)^-1 V^T (b - A E), since b - A E = 0 there
    (b - A E formed from the images A T^n and A T^(n-1) kept from the last two solves). A slab heated
    uniformly (T = T_0 + P t / C): from the second step on, every start CG receives is the exact
    field to 1e-9 of a step's rise (the solves' own error, heat_tol 1e-10 K, is far below that)."""
    import twin.physics.steppers as steppers
    system, n, capacity = _uniformly_heated_slab()
    steps, dt, P = 8, 30.0, 100.0
    starts = []
    real = steppers.pcg
    monkeypatch.setattr(steppers, "pcg", lambda apply, b, x0, *a, **k: starts.append(np.array(x0)) or real(apply, b, x0, *a, **k))
    stepper = IterativeStepper(heat_tol=1e-10, projection_size=0)
    if start == "reduced":
        stepper.start = steppers.ReducedStart(np.random.default_rng(2).standard_normal((n, 5)))
    out = integrate(system, np.full(n, 20.0), dt, steps, np.zeros((steps, 0)), np.zeros((steps, 0)),
                    np.full((steps, 1), P), np.eye(n)[::7], stepper=stepper)
    rise = P * dt / capacity
    np.testing.assert_allclose(out[-1], 20.0 + steps * rise, rtol=0, atol=1e-9 * rise)
    assert len(starts) == steps
    for k in range(1, steps):
        assert np.abs(starts[k] - (20.0 + (k + 1) * rise)).max() <= 1e-9 * rise, k


def test_each_operator_gets_its_own_galerkin_start(monkeypatch):
    """The starts are Galerkin projections in the energy norm of the step's own operator: after a
    film changes A (a new operator), the reduced start uses (V^T A V)^-1 of the new A, not the one
    formed for the first, so an increment that V spans is again reproduced exactly; and the
    projection start (Fischer) rebuilds its A-orthonormal basis from the last two solutions, so a
    solution in their span, 2 T^n - T^(n-1), is its start exactly. (A start built on the old
    operator would be a worse start, not a wrong answer: CG would still converge.)"""
    import twin.physics.steppers as steppers
    _, system, n, _ = _cooled_slab(1)
    rng = np.random.default_rng(6)
    V = rng.standard_normal((n, 9)).astype(np.float32).astype(float)
    start = steppers.ReducedStart(V)
    T = 20.0 + rng.standard_normal(n)
    for h in (300.0, 30.0, 300.0):
        lhs = (system.M + 0.5 * 30.0 * (system.K + h * system.H[0])).tocsr()
        inside = T + V @ rng.standard_normal(9)
        np.testing.assert_allclose(start.guess((lhs,), lhs, lhs @ inside, T), inside, rtol=0,
                                   atol=1e-6 * np.abs(inside - T).max())
    # the projection start across an operator change
    starts = []
    real = steppers.pcg
    monkeypatch.setattr(steppers, "pcg", lambda apply, b, x0, *a, **k: starts.append(np.array(x0)) or real(apply, b, x0, *a, **k))
    stepper = IterativeStepper(heat_tol=1e-10)
    stepper.begin(10, system)
    first, second = (stepper.operator(("slab", h), system, 30.0, 0.5, np.array([h])) for h in (300.0, 30.0))
    solutions = [np.full(n, 20.0)]
    for k in range(1, 4):                                  # three steps on the first operator
        x = 20.0 + 0.01 * k * np.cumsum(rng.standard_normal(n))
        solutions.append(stepper.solve(first, first[0] @ x, solutions[-1]))
    target = 2.0 * solutions[-1] - solutions[-2]           # in the span of the last two solutions
    stepper.solve(second, second[0] @ target, solutions[-1])
    np.testing.assert_allclose(starts[-1], target, rtol=0, atol=1e-9 * np.abs(target - solutions[-1]).max())


@pytest.mark.parametrize("heat_tol", [1e-4, 1e-3])
def test_each_step_stops_within_its_share_of_the_run_tolerance(heat_tol):
    """The verified tolerance is split evenly over the run: CG stops step n once its residual norm
    rho_n = (27 r^T M_L^-1 r)^(1/2) <= heat_tol sqrt(C) / N (N the run's steps, C = 1^T M 1), so
    that sum_n rho_n <= heat_tol sqrt(C) (twin.physics.solvers). Each step's rho_n, read from the
    stepper's running sum after the step, is within that share on two-step runs of the cooled slab
    (where one share more, heat_tol sqrt(C) / (N - 1), would let the final iterate stop above it)."""
    heat, system, n, (T0, dt, _, h, air, s, rows) = _cooled_slab(2)
    share = heat_tol * np.sqrt(float(heat.M.sum())) / 2
    stepper = IterativeStepper(heat_tol=heat_tol, projection_size=0)
    rho = []
    integrate(system, T0, dt, 2, h[:2], air[:2], s[:2], rows, stepper=stepper,
              on_step=lambda k, T: rho.append(float(stepper.rho_sum) - sum(rho)))
    assert len(rho) == 2 and max(rho) > 0.3 * share
    assert all(r <= share * (1 + 1e-12) for r in rho), np.array(rho) / share


def test_an_outputs_bound_is_its_rows_weighted_norm_times_the_residual_sum():
    """output_bounds: (w^T W w)^(1/2) sum_n rho_n per output row w, W the diagonal weights: rows
    (1, 1, 0) and (0.5, 0, 0) with W = (9, 16, 1) and sum rho = 2 give sqrt(9 + 16) x 2 = 10 and
    sqrt(0.25 x 9) x 2 = 3 (a sum of |w| sqrt(W) would give 14 for the first)."""
    bound = output_bounds(np.array([[1.0, 1.0, 0.0], [0.5, 0.0, 0.0]]), np.array([9.0, 16.0, 1.0]), 2.0)
    np.testing.assert_allclose(bound, [10.0, 3.0], rtol=1e-15)

