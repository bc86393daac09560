"""Heat conduction against closed-form answers: slab series solution, fin equation, time order."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from tests.conftest import box_body, face
from twin.fem.assembly import assemble_facets, assemble_heat
from geometries.materials import MATERIALS
from twin.physics.heat import HeatSystem, integrate, steady_state

STEEL = MATERIALS["steel"]


def slab_series(x, t, L, h, k, diffusivity, terms=60):
    """Plane wall, insulated at x = 0, convecting at x = L, initial excess 1:
    theta/theta_0 = sum_n C_n exp(-zeta_n^2 Fo) cos(zeta_n x/L), zeta_n tan zeta_n = Bi,
    C_n = 4 sin zeta_n / (2 zeta_n + sin 2 zeta_n), Fo = a t / L^2, Bi = h L / k (Incropera eq. 5.39)."""
    bi = h * L / k
    zetas = [brentq(lambda z: z * np.tan(z) - bi, n * np.pi + 1e-9, n * np.pi + np.pi / 2 - 1e-9) for n in range(terms)]
    fo = diffusivity * t / L**2
    return sum(4 * np.sin(z) / (2 * z + np.sin(2 * z)) * np.exp(-z * z * fo) * np.cos(z * x / L) for z in zetas)


def _slab(h=450.0, L=0.1, spacing=0.0025):
    mm = box_body((L, spacing, spacing), spacing, surfaces=[("cooled", face(0, L))])
    heat = assemble_heat(mm)
    fm = assemble_facets(mm, mm.facets["cooled"])
    system = HeatSystem(heat.M, heat.K, [fm.H], fm.r[:, None], np.zeros((mm.nnodes, 0)))
    return mm, system


def _run_slab(system, n, dt, nsteps, h, theta, start=None):
    x = np.ones(n) if start is None else start  # initial excess temperature over air at 0
    on = np.full((nsteps, 1), h)
    return integrate(system, x, dt, nsteps, on, np.zeros((nsteps, 1)), np.zeros((nsteps, 0)),
                     np.eye(n), theta=theta)


@pytest.mark.parametrize("theta", [0.5, 1.0])
def test_slab_transient_matches_series_solution(theta):
    """1-D transient conduction, convective face (Incropera 5.39 series): within 1e-3 of the
    initial excess at Fo = 0.1, 0.3, 1 (measured 3.6e-4 with Crank-Nicolson at 1 s, 1.3e-4 implicit
    at 0.25 s, on 2.5 mm cells; h or the heat capacity 2-3 % off would miss it by 8e-3)."""
    h, L = 450.0, 0.1
    mm, system = _slab(h, L)
    a = STEEL.conductivity / STEEL.volumetric_heat_capacity
    dt = 1.0 if theta == 0.5 else 0.25
    times = np.array([0.1, 0.3, 1.0]) * L**2 / a
    nsteps = int(round(times[-1] / dt))
    out = _run_slab(system, mm.nnodes, dt, nsteps, h, theta)
    x = mm.mesh.p[0]
    for t in times:
        exact = slab_series(x, t, L, h, STEEL.conductivity, a)
        got = out[int(round(t / dt))]
        assert np.max(np.abs(got - exact)) < 1e-3, (theta, t, np.max(np.abs(got - exact)))


@pytest.mark.parametrize("theta,order", [(0.5, 2.0), (1.0, 1.0)])
def test_theta_scheme_order_in_time(theta, order):
    """Error against a very fine step falls by 2^order when dt halves (CN: 2, implicit Euler: 1).

    Starts from a smooth state (the slab after 100 s, by fine implicit-Euler steps), as the
    asymptotic order needs a smooth solution."""
    h = 450.0
    mm, system = _slab(h, spacing=0.005)
    start = _run_slab(system, mm.nnodes, 0.1, 1000, h, 1.0)[-1]
    t_end = 200.0
    ref = _run_slab(system, mm.nnodes, 0.05, 4000, h, 0.5, start)[-1]
    errors = []
    for dt in (20.0, 10.0, 5.0):
        got = _run_slab(system, mm.nnodes, dt, int(t_end / dt), h, theta, start)[-1]
        errors.append(np.max(np.abs(got - ref)))
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(rates - order) < 0.15), rates


def _steady_fin(L, w, h, P, spacing, refine=1.0):
    """Steady square steel fin L x w x w [m], heat P [W] into the base x = 0, film h [W/(m2 K)]
    on the sides, adiabatic tip, air 20 degC, meshed at ``spacing`` x ``refine``: returns
    (mesh, nodal T [degC], side facet matrices)."""
    mm = box_body((L, w, w), spacing, surfaces=[("base", face(0, 0.0)), ("y0", face(1, 0.0)), ("y1", face(1, w)),
                                                ("z0", face(2, 0.0)), ("z1", face(2, w))], refine=refine)
    heat = assemble_heat(mm)
    sides = np.unique(np.concatenate([mm.facets[n] for n in ("y0", "y1", "z0", "z1")]))
    conv = assemble_facets(mm, sides)
    base = assemble_facets(mm, mm.facets["base"])
    system = HeatSystem(heat.M, heat.K, [conv.H], conv.r[:, None], (base.r / base.area)[:, None])
    return mm, steady_state(system, np.array([h]), np.array([20.0]), np.array([P])), conv


def _fin_base_excess(L, w, h, P, spacing, refine=1.0):
    """Mean base excess temperature [K] of :func:`_steady_fin`."""
    mm, T, _ = _steady_fin(L, w, h, P, spacing, refine)
    return float(np.mean(T[np.isclose(mm.mesh.p[0], 0.0)]) - 20.0)


def test_test_bar_refinement_resolves_its_fin_length():
    """The rotating test bar is a fin: theta_base = P coth(m L) / (k A m), m = sqrt(h p / (k A))
    (Incropera Table 3.4 case B). For the 40 mm bar at Becker's h = 150 W/(m2 K), 1/m is 5.5 cm,
    about one default cell (6 cm): the bar's refine = 1/3 (2 cm cells) brings the base
    conductance within 1 %, as a finite contact of 20 W/K changes it by about 6 %; the plain
    6 cm cells miss it by more than the refined mesh."""
    from geometries import build_machine
    bar = next(p for p in build_machine("cframe-vmc").parts if p.name == "test_bar")
    L, w, h, P = 0.27, 0.04, 150.0, 5.0
    k, A = STEEL.conductivity, w * w
    m = np.sqrt(h * 4 * w / (k * A))
    exact = P / (k * A * m * np.tanh(m * L))
    refined = _fin_base_excess(L, w, h, P, 0.06, bar.refine)
    plain = _fin_base_excess(L, w, h, P, 0.06)
    assert bar.refine <= 1 / 3
    assert abs(refined / exact - 1) < 0.01, (refined, exact)
    assert abs(plain / exact - 1) > abs(refined / exact - 1)


def test_fin_with_end_flux_matches_fin_equation():
    """Steady fin, heat P into the base, convection along the sides, adiabatic tip:
    theta(x) = P cosh(m (L - x)) / (k A m sinh(m L)), m = sqrt(h p / (k A)) (Incropera Table 3.4 case B
    with a prescribed base flux). Within 0.5 % of the base excess: the 3-D bar against the 1-D fin
    equation leaves 0.22-0.24 % at 10, 5 and 2.5 mm cells alike (the model's floor, not the
    mesh's: the section is not isothermal)."""
    L, w, h, P = 0.3, 0.02, 20.0, 5.0
    mm, T, conv = _steady_fin(L, w, h, P, 0.005)
    k, A, perim = STEEL.conductivity, w * w, 4 * w
    m = np.sqrt(h * perim / (k * A))
    x = mm.mesh.p[0]
    exact = P * np.cosh(m * (L - x)) / (k * A * m * np.sinh(m * L))
    assert np.max(np.abs((T - 20.0) - exact)) < 0.005 * exact.max()
    # and the energy balance of the steady state: all of P leaves through the sides
    assert h * (conv.r @ T - 20.0 * conv.area) == pytest.approx(P, rel=1e-9)


def test_capacity_and_conduction_on_cells_that_are_not_cubes():
    """On bricks of three different edge lengths (0.05 x 0.05 x 0.035 m here): the capacity matrix
    holds the body's whole heat capacity, 1^T M 1 = rho c V, and a linear field T = g . x drives
    the conduction flux k g_d A_d out of the faces normal to each axis d (K T summed over the face
    x_d = L_d's nodes; the faces at 0 take the opposite), exactly for trilinear elements on a linear
    field: to round-off. (Every other closed-form heat test meshes cubes.)"""
    size = np.array([0.3, 0.2, 0.07])
    mm = box_body(tuple(size), 0.05)
    steel = MATERIALS["steel"]
    heat = assemble_heat(mm)
    assert set(np.round(np.ptp(mm.mesh.p[:, mm.mesh.t[:, 0]], axis=1), 9)) == {0.05, 0.035}
    assert heat.M.sum() == pytest.approx(steel.density * steel.specific_heat * size.prod(), rel=1e-12)
    p = mm.mesh.p.T
    g = np.array([3.0, -2.0, 5.0])                       # [K/m]
    q = heat.K @ (p @ g)                                 # [W] heat leaving through each node
    for d in range(3):
        area = size.prod() / size[d]
        at_end = np.isclose(p[:, d], size[d])
        assert q[at_end].sum() == pytest.approx(steel.conductivity * g[d] * area, rel=1e-12)
        assert q[np.isclose(p[:, d], 0.0)].sum() == pytest.approx(-steel.conductivity * g[d] * area, rel=1e-12)


def test_consistent_capacity_and_film_matrices_integrate_a_squared_linear_field_exactly():
    """The consistent matrices, not their lumped row sums: for T = g . x on the 0.3 x 0.2 x 0.07 m
    brick, T^T M T = rho c int (g . x)^2 dV = rho c V (sum_d g_d^2 L_d^2 / 3 + 2 sum_{d<e} g_d g_e
    L_d L_e / 4), and on the face x = a the film matrix gives T^T H T = int (g . x)^2 dA =
    A (c0^2 + c0 (g_y b + g_z c) + g_y^2 b^2 / 3 + g_z^2 c^2 / 3 + g_y g_z b c / 2), c0 = g_x a
    (2-point Gauss is exact for the trilinear products): to round-off. A lumped matrix keeps
    1^T M 1 but not these."""
    size = np.array([0.3, 0.2, 0.07])
    a, b, c = size
    mm = box_body(tuple(size), 0.05, surfaces=[("end", face(0, a))])
    steel = MATERIALS["steel"]
    heat = assemble_heat(mm)
    g = np.array([3.0, -2.0, 5.0])                       # [K/m]
    T = mm.mesh.p.T @ g
    V = size.prod()
    cross = sum(g[d] * g[e] * size[d] * size[e] / 4 for d in range(3) for e in range(d + 1, 3))
    volume = V * (np.sum(g ** 2 * size ** 2) / 3 + 2 * cross)
    assert T @ (heat.M @ T) == pytest.approx(steel.density * steel.specific_heat * volume, rel=1e-12)
    film = assemble_facets(mm, mm.facets["end"])
    c0 = g[0] * a
    area = b * c * (c0 ** 2 + c0 * (g[1] * b + g[2] * c) + g[1] ** 2 * b ** 2 / 3 + g[2] ** 2 * c ** 2 / 3
                    + g[1] * g[2] * b * c / 2)
    assert film.area == pytest.approx(b * c, rel=1e-12)
    assert T @ (film.H @ T) == pytest.approx(area, rel=1e-12)


def test_a_cached_factorisation_serves_only_its_own_step_and_theta():
    """Factorisations kept across runs are keyed by the operator, dt, theta and the films
    (twin.physics.heat.integrate): M + theta dt A differs for another theta or dt, so runs sharing
    one cache at theta 1/2, then 1, then dt halved, each equal the same run on a fresh cache (to
    round-off), and the cache holds one factorisation per (dt, theta)."""
    mm, system = _slab(spacing=0.01)
    n = mm.nnodes
    cache = {}

    def run(dt, theta, factorisations):
        steps = int(round(600.0 / dt))
        return integrate(system, np.ones(n), dt, steps, np.full((steps, 1), 450.0), np.zeros((steps, 1)),
                         np.zeros((steps, 0)), np.eye(n)[::3], theta=theta, factorisations=factorisations,
                         operator_key=("slab",))[-1]

    for dt, theta in ((20.0, 0.5), (20.0, 1.0), (10.0, 1.0)):
        np.testing.assert_allclose(run(dt, theta, cache), run(dt, theta, {}), rtol=1e-12, atol=0)
    assert len(cache) == 3


@pytest.mark.parametrize("theta", [0.5, 1.0])
def test_a_spindle_step_delivers_its_power_times_its_duration_at_any_theta(theta):
    """A spindle step holds its speed on [start, end); the theta scheme reads a step's loads at
    t_n + theta dt (twin.signals.load_instants, at theta = 1 just inside the step), so the sources
    deliver sum P_step x duration exactly: the C-frame's bearings and motor, 150 + 130 + 60 = 340 W at
    9000 rpm for 600 s, then nothing, 204 000 J (1e-12). At theta = 1, t_(n+1) itself read the next
    step's 0 rpm: one 10 s step of 340 W went missing (200 600 J)."""
    from twin.api import simulate
    from twin.scenario import Ambient, Scenario

    sc = Scenario("step", ((600.0, 9000.0), (600.0, 0.0)), Ambient("constant", mean=20.0), 10.0)
    _, run = simulate("cframe-vmc", sc, resolution="coarse", theta=theta)
    source, convection, stored = run.step_energy()
    assert source == pytest.approx(340.0 * 600.0, rel=1e-12)
    assert source + convection == pytest.approx(stored, rel=1e-9)


def test_the_load_instants_lie_inside_each_step():
    """load_instants: t_n + theta dt, at theta = 1 the left limit t_(n+1) - 1e-9 dt: a spindle step
    on [0, 600) read at those instants gives its own speed in each of its steps, the next step's
    in the next; the feed drives' step_signal (value n on (n dt, (n+1) dt]) gives value n."""
    from twin.motion import step_signal
    from twin.scenario import Ambient, Scenario
    from twin.signals import load_instants

    times = np.arange(0.0, 1201.0, 60.0)
    sc = Scenario("step", ((600.0, 9000.0), (600.0, 0.0)), Ambient("constant", mean=20.0), 60.0)
    for theta in (0.5, 0.75, 1.0):
        t = load_instants(times, theta)
        assert np.all((t > times[:-1]) & (t < times[1:]))
        np.testing.assert_array_equal(sc.spindle_speed(t), [9000.0] * 10 + [0.0] * 10)
        np.testing.assert_array_equal(step_signal(np.arange(20.0), 60.0)(t), np.arange(20.0))
    # the schedule itself: a step's speed from its start, the next one's from its end
    np.testing.assert_array_equal(sc.spindle_speed(np.array([0.0, 595.0, 600.0, 605.0, 1200.0])),
                                  [9000.0, 9000.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(step_signal([1.0, 2.0, 3.0], 10.0)(np.array([5.0, 10.0, 15.0, 20.0, 25.0, 30.0])),
                                  [1.0, 1.0, 2.0, 2.0, 3.0, 3.0])

