"""Closed forms and exact identities that a mutation audit of twin/fem and twin/physics found
unguarded: each test here fails with one of the audit's surviving mutations and names the formula
it holds the code to. Tiny meshes; every identity to round-off unless the docstring says more.

* a composite bar: heat capacity sum rho_i c_i V_i, 1^T K = 0, series conduction k_1 g_1 = k_2 g_2,
  end forces 3 K_i alpha_i dT A of each material (element groups keyed by size *and* part);
* a machine with an overhang: the 3-2-1 support on its floor corners and a uniform rise
  u = alpha dT (p - p_A) in all three directions, no rigid rotation;
* a void carves only its own part's cells;
* point location on bricks that are not cubes: a linear field read exactly;
* the compiled assembly of 3 x 3 node blocks: the elastic stiffness symmetric, K B = 0, equal to
  the numpy passes;
* cached factorisations keyed by everything the operator depends on (the films' facets; theta of
  the responses) and cached couplings by material: a run on a shared cache equals it on a fresh one;
* the nested coupling's condensation per material (equal lambda, different mu): thermal bending
  alpha dT / h exact on the coarse elastic mesh of a two-material beam.
"""

from __future__ import annotations

import numpy as np
import pytest

from geometries.base import Box, Machine, Part
from geometries.materials import MATERIALS, Material
from tests.conftest import box_body, face
from twin.fem.assembly import assemble_elastic, assemble_facets, assemble_heat
from twin.fem.mesh import mesh_machine

STEEL, IRON = MATERIALS["steel"], MATERIALS["grey_cast_iron"]


def _machine(parts, spacing, name="parts"):
    """A machine of ``parts`` (no surfaces, points or roles), meshed at ``spacing`` [m]."""
    m = Machine(name, list(parts), [], [], [], "", "", [], {"test": spacing})
    return m, mesh_machine(m, "test")


def _composite_bar(spacing=0.05, L1=0.2, L2=0.2, w=0.05, first=STEEL, second=IRON):
    """A bar of ``first`` on [0, L1] and ``second`` on [L1, L1 + L2] along x, section w x w."""
    parts = [Part("first", first, (Box((0.0, 0.0, 0.0), (L1, w, w)),)),
             Part("second", second, (Box((L1, 0.0, 0.0), (L1 + L2, w, w)),))]
    return _machine(parts, spacing, "composite")


def _bulk(m: Material) -> float:
    """Bulk modulus K = E / (3 (1 - 2 nu)) [Pa]."""
    return m.youngs_modulus / (3 * (1 - 2 * m.poisson_ratio))


def test_a_composite_bar_keeps_each_materials_capacity_conduction_and_thermal_force():
    """Steel on [0, 0.2] and grey iron on [0.2, 0.4], 5 cm cubes in both (so the element groups
    differ by their part alone): 1^T M 1 = rho_s c_s V_s + rho_i c_i V_i and K 1 = 0 (energy
    conservation of the assembled conduction); the piecewise-linear T with k_s g_s = k_i g_i = q
    (series conduction through two slabs) is in the element space, so K T (the nodal heat input
    that holds it, K T = f) vanishes inside, and q A leaves at x = 0.4 and enters at x = 0; a
    uniform rise dT pushes the end x = 0 with -3 K_s alpha_s dT A and the end x = 0.4 with
    3 K_i alpha_i dT A (K = E / (3 (1 - 2 nu))), the interface with the difference. All to round-off."""
    L1, L2, w = 0.2, 0.2, 0.05
    _, mm = _composite_bar(0.05, L1, L2, w)
    assert len(np.unique(np.round(mm.cell_size, 12))) == 1     # one cell size everywhere (to 1e-12 m)
    heat = assemble_heat(mm)
    A = w * w
    capacity = STEEL.volumetric_heat_capacity * L1 * A + IRON.volumetric_heat_capacity * L2 * A
    assert heat.M.sum() == pytest.approx(capacity, rel=1e-12)
    assert np.abs(heat.K @ np.ones(mm.nnodes)).max() <= 1e-12 * abs(heat.K).max()
    q = 1e4                                            # [W/m2] through the bar
    x = mm.mesh.p[0]
    T = np.where(x <= L1, -q / STEEL.conductivity * x, -q / STEEL.conductivity * L1 - q / IRON.conductivity * (x - L1))
    flux = -(heat.K @ T)                               # [W] leaving the body at each node (K T = f)
    ends = np.isclose(x, 0.0) | np.isclose(x, L1 + L2)
    assert np.abs(flux[~ends]).max() <= 1e-12 * q * A
    assert flux[np.isclose(x, L1 + L2)].sum() == pytest.approx(q * A, rel=1e-12)
    assert flux[np.isclose(x, 0.0)].sum() == pytest.approx(-q * A, rel=1e-12)
    dT = 1.0
    force = (assemble_elastic(mm).C @ np.full(mm.nheat, dT)).reshape(-1, 3)[:, 0]
    s, i = 3 * _bulk(STEEL) * STEEL.expansion * dT * A, 3 * _bulk(IRON) * IRON.expansion * dT * A
    assert force[np.isclose(x, 0.0)].sum() == pytest.approx(-s, rel=1e-12)
    assert force[np.isclose(x, L1 + L2)].sum() == pytest.approx(i, rel=1e-12)
    assert force[np.isclose(x, L1)].sum() == pytest.approx(s - i, rel=1e-9)


def test_the_support_stands_on_the_floor_corners_and_a_uniform_rise_expands_about_the_first():
    """A steel body whose upper block overhangs its foot by 0.1 m along -x: the 3-2-1 support is on
    the floor contact (z = 0), A at the footprint's (x_min, y_min) corner fixing x, y, z, B at
    (x_max, y_min) fixing y, z, C at (x_min, y_max) fixing z. It blocks no free expansion and adds
    no rigid rotation: a uniform rise dT gives u(p) = alpha dT (p - p_A) in every direction, to
    round-off (the free-expansion test in test_physics_elastic.py allows any rigid motion and reads
    x and y only)."""
    from twin.physics.elastic import ElasticSolver, support_dofs
    foot = Box((0.0, 0.0, 0.0), (0.4, 0.2, 0.1))
    overhang = Box((-0.1, 0.0, 0.1), (0.4, 0.2, 0.2))
    _, mm = _machine([Part("body", STEEL, (foot, overhang))], 0.05)
    fixed = support_dofs(mm)
    p = mm.mesh.p.T
    a, b, c = fixed[[0, 3, 5]] // 3
    np.testing.assert_array_equal(fixed, [3 * a, 3 * a + 1, 3 * a + 2, 3 * b + 1, 3 * b + 2, 3 * c + 2])
    np.testing.assert_allclose(p[[a, b, c]], [[0.0, 0.0, 0.0], [0.4, 0.0, 0.0], [0.0, 0.2, 0.0]], atol=1e-12)
    dT = 10.0
    u = ElasticSolver.build(mm).displacement(np.full(mm.nnodes, dT))
    exact = STEEL.expansion * dT * (p - p[a])
    assert np.abs(u - exact).max() <= 1e-12 * np.abs(exact).max()


def test_a_void_carves_only_its_own_parts_cells():
    """Voids are carved out of the part's own cells (geometries.base.Part): a column whose core
    reaches 0.1 m down into the bed below it (listed first) leaves the bed whole, V_bed = its box,
    and the column loses only the core's part inside it, V_col = box - (core within the box)."""
    bed = Part("bed", IRON, (Box((0.0, 0.0, 0.0), (0.6, 0.6, 0.2)),))
    column = Part("column", IRON, (Box((0.1, 0.1, 0.2), (0.5, 0.5, 0.8)),),
                  voids=(Box((0.2, 0.2, 0.1), (0.4, 0.4, 0.7)),))
    _, mm = _machine([bed, column], 0.05)
    assert mm.volume_of(mm.cells_of("bed")) == pytest.approx(0.6 * 0.6 * 0.2, rel=1e-12)
    assert mm.volume_of(mm.cells_of("column")) == pytest.approx(0.4 * 0.4 * 0.6 - 0.2 * 0.2 * 0.5, rel=1e-12)


def test_points_on_bricks_that_are_not_cubes_read_a_linear_field_exactly():
    """On 0.05 x 0.05 x 0.035 m bricks, the point operators (twin.fem.points) locate each point's
    reference coordinates per axis, xi_d = 2 (x_d - lo_d) / h_d - 1, so a field a + g . x is read
    exactly at any point, as a temperature and as a displacement component (to round-off; the test
    in test_physics_elastic.py uses cubes)."""
    from twin.fem.points import displacement_functional, interpolation_matrix
    mm = box_body((0.3, 0.2, 0.07), 0.05)
    assert len(np.unique(np.round(mm.cell_size, 12))) == 2
    rng = np.random.default_rng(11)
    pts = rng.random((20, 3)) * [0.3, 0.2, 0.07]
    g, a = np.array([3.0, -2.0, 5.0]), 1.5
    field = a + mm.mesh.p.T @ g
    exact = a + pts @ g
    np.testing.assert_allclose(interpolation_matrix(mm, pts) @ field, exact, rtol=0, atol=1e-12 * np.abs(exact).max())
    D = displacement_functional(interpolation_matrix(mm, pts, field="mesh"), [0.0, 1.0, 0.0])
    u = np.zeros((mm.nnodes, 3))
    u[:, 1] = field
    np.testing.assert_allclose(D @ u.ravel(), exact, rtol=0, atol=1e-12 * np.abs(exact).max())


def test_the_compiled_assembly_of_three_by_three_blocks_is_the_numpy_one(monkeypatch):
    """Large meshes (from twin.fem.scatter.COMPILED_FROM lookups) assemble by the compiled loop; the
    elastic stiffness is its only 3 x 3 node-block matrix. Compiled on a small brick: K is
    symmetric, stores no energy in the six rigid-body modes (K B = 0), and equals the numpy passes'
    matrix bit for bit (the same sums in the same order)."""
    from twin.fem import scatter
    from twin.physics.solvers import rigid_body_modes
    if not scatter.HAVE_NUMBA:
        pytest.skip("numba not installed: only the numpy passes run")
    mm = box_body((0.2, 0.1, 0.07), 0.05)
    plain = assemble_elastic(mm).K
    monkeypatch.setattr(scatter, "COMPILED_FROM", 0)
    compiled = assemble_elastic(mm).K
    assert abs(compiled - compiled.T).max() <= 1e-12 * abs(compiled).max()
    B = rigid_body_modes(mm.mesh.p.T)
    assert np.abs(compiled @ B).max() <= 1e-12 * abs(compiled).max() * np.abs(B).max()
    assert (compiled != plain).nnz == 0


def _cooled_bar(L=0.1, spacing=0.01):
    """A steel bar along x with both ends nameable ('left' x = 0, 'right' x = L)."""
    mm = box_body((L, spacing, spacing), spacing, surfaces=[("left", face(0, 0.0)), ("right", face(0, L))])
    return mm, assemble_heat(mm)


def test_a_shared_factorisation_cache_tells_films_on_different_faces_apart():
    """Factorisations are cached under the load set's operator_key: the layout and each film's
    label *and facets* (twin.physics.loads.LoadSet). Two load sets whose one film has the same label
    but cools the other end of a bar are different operators: on one cache, the bar cooled at
    x = L is the mirror image of the bar cooled at x = 0, T_right(x) = T_left(L - x) (the grid is
    mirror-symmetric), to round-off, and each run equals its run on a fresh cache."""
    from twin.effects import Convection
    from twin.physics.heat import HeatSystem, integrate
    from twin.physics.loads import LoadSet
    L = 0.1
    mm, heat = _cooled_bar(L)
    n, steps, dt = mm.nnodes, 40, 10.0
    x = mm.mesh.p[0]
    mirror = np.lexsort((mm.mesh.p[2], mm.mesh.p[1], np.round(L - x, 12)))     # node of p mirrored, in node order
    order = np.lexsort((mm.mesh.p[2], mm.mesh.p[1], np.round(x, 12)))
    cache, runs = {}, {}
    for side in ("left", "right"):
        film = Convection("film", mm.facets[side], lambda t: np.full(np.shape(t), 500.0),
                          lambda t: np.zeros(np.shape(t)))
        fm = assemble_facets(mm, film.facets)
        system = HeatSystem(heat.M, heat.K, [fm.H], fm.r[:, None], np.zeros((n, 0)))
        loads = LoadSet(system, [], [film], [], ["film"], np.array([fm.area]), mm, heat)
        args = (system, np.ones(n), dt, steps, np.full((steps, 1), 500.0), np.zeros((steps, 1)), np.zeros((steps, 0)),
                np.eye(n))
        runs[side] = integrate(*args, factorisations=cache, operator_key=loads.operator_key)
        fresh = integrate(*args, factorisations={}, operator_key=loads.operator_key)
        np.testing.assert_allclose(runs[side], fresh, rtol=0, atol=1e-13)
    assert len(cache) == 2
    left, right = runs["left"][-1], runs["right"][-1]
    assert np.ptp(left) > 0.01                                            # cooled unevenly
    np.testing.assert_allclose(right[order], left[mirror], rtol=0, atol=1e-12)


def test_responses_on_one_cache_at_two_thetas_are_each_the_difference_of_two_full_runs():
    """integrate_responses solves (M + theta dt A) X+ = (M - (1 - theta) dt A) X + dt b s_n from
    X = 0, the response to an added source; the heat equation is linear, so it equals the full
    theta-scheme run with that source minus the run without it, from the same start and air: to
    round-off, at theta 1/2 and then 1 on one factorisation cache (whose keys must tell the two
    thetas apart: M + dt A / 2 and M + dt A are different operators)."""
    from twin.physics.heat import HeatSystem, integrate, integrate_responses
    from twin.physics.steppers import DirectStepper
    L = 0.1
    mm, heat = _cooled_bar(L)
    n, steps, dt = mm.nnodes, 30, 20.0
    film, base = assemble_facets(mm, mm.facets["right"]), assemble_facets(mm, mm.facets["left"])
    b = base.r / base.r.sum()
    system = HeatSystem(heat.M, heat.K, [film.H], film.r[:, None], b[:, None])
    h, air = np.full((steps, 1), 300.0), np.full((steps, 1), 15.0)
    power = 5.0 + 3.0 * np.sin(np.arange(steps))[:, None]                       # [W]
    rows = np.eye(n)[::2]
    cache = {}
    for theta in (0.5, 1.0):
        got = integrate_responses(system, dt, steps, h, b[:, None], power, rows, theta,
                                  DirectStepper(cache), operator_key=("bar",))[:, :, 0]
        on = integrate(system, np.full(n, 20.0), dt, steps, h, air, power, rows, theta)
        off = integrate(system, np.full(n, 20.0), dt, steps, h, air, np.zeros((steps, 1)), rows, theta)
        assert np.abs(on - off).max() > 0.1
        np.testing.assert_allclose(got, on - off, rtol=0, atol=1e-10 * np.abs(on - off).max())
    assert len(cache) == 2


def test_a_materials_own_coupling_is_cached_apart_from_the_whole_one():
    """PreparedTwin.coupling(layout, material): the thermal coupling of that material's cells alone
    (every other expansion set to 0), cached per layout *and* material. The coupling is linear in
    alpha, so C = C_steel + C_iron exactly; on the composite bar a uniform rise dT loads, through
    C_steel, the end x = 0 with -3 K_s alpha_s dT A and the iron end x = 0.4 with nothing (round-off),
    whichever coupling the twin was asked for first."""
    from twin.physics.prepared import PreparedTwin
    machine, mm = _composite_bar()
    twin = PreparedTwin(machine, mm, solver="direct")
    whole = twin.coupling(mm)
    steel, iron = twin.coupling(mm, "steel"), twin.coupling(mm, "grey_cast_iron")
    assert abs(steel + iron - whole).max() <= 1e-12 * abs(whole).max()
    x, A = mm.mesh.p[0], 0.05 * 0.05
    force = (steel @ np.ones(mm.nheat)).reshape(-1, 3)[:, 0]
    s = 3 * _bulk(STEEL) * STEEL.expansion * A
    assert force[np.isclose(x, 0.0)].sum() == pytest.approx(-s, rel=1e-12)
    assert abs(force[np.isclose(x, 0.4)].sum()) <= 1e-12 * s


def _same_lambda(m: Material, nu: float) -> Material:
    """A material with ``m``'s Lame lambda (to the bit) and expansion but Poisson's ratio ``nu``, so
    another mu."""
    lam = m.lame[0]
    E = lam * (1 + nu) * (1 - 2 * nu) / nu
    for _ in range(64):                                 # the float E whose lambda is m's to the bit
        other = Material("stiff_twin", m.conductivity, m.density, m.specific_heat, E, nu, m.expansion, "test")
        if other.lame[0] == lam:
            return other
        E = np.nextafter(E, np.inf if other.lame[0] < lam else -np.inf)
    raise AssertionError("no float E gives the same lambda")


def test_a_two_material_body_on_a_coarser_elastic_mesh_loads_and_bends_as_on_its_own_grid():
    """A beam of two materials along its length with one alpha (grey iron, and a material of the
    same Lame lambda but nu 0.2 instead of 0.26, so another mu), its elasticity on every second line
    of the temperature grid (twin.fem.nesting), the thermal load integrated on the fine cells
    (twin.fem.elements.nested_coupling), each coarse brick's incompatible modes condensed with its
    own material's stiffness:

    * a temperature the coarse grid represents, T_fine = P T_coarse (P the trilinear prolongation),
      loads the coarse nodes exactly as the coarse grid's own coupling does, C_nested P = C_coarse
      (the fine cells tile each coarse brick and the integrand is the same): to round-off;
    * T linear through the depth h is stress-free in both materials, so the beam bends with
      curvature alpha dT / h, mid-span rising kappa L^2 / 8 against its ends, whatever E and nu
      are: to round-off."""
    from twin.fem.assembly import assemble_coupling, assemble_nested_coupling
    from twin.fem.nesting import coarsen, prolongation
    from twin.physics.elastic import ElasticSolver
    L, b, h, dT = 1.0, 0.125, 0.25, 10.0               # binary fractions: both halves' cells the same to the bit
    other = _same_lambda(IRON, 0.2)
    assert other.lame[0] == IRON.lame[0] and other.lame[1] != pytest.approx(IRON.lame[1])
    parts = [Part("a", IRON, (Box((0.0, 0.0, 0.0), (L / 2, b, h)),)),
             Part("b", other, (Box((L / 2, 0.0, 0.0), (L, b, h)),))]
    _, mm = _machine(parts, 0.0625)
    nested = coarsen(mm, 2)
    coarse = nested.coarse
    assert coarse.nnodes < mm.nnodes / 3 and len(np.unique(coarse.cell_size)) == 1
    C = assemble_nested_coupling(nested, mm)
    own = assemble_coupling(coarse)
    assert abs(C @ prolongation(nested, mm) - own).max() <= 1e-12 * abs(own).max()
    u = ElasticSolver.build(coarse).solve(C @ (dT * (mm.mesh.p[2] / h - 0.5))).reshape(-1, 3)
    kappa = IRON.expansion * dT / h
    node = lambda xyz: int(np.argmin(np.sum((coarse.mesh.p.T - np.asarray(xyz)) ** 2, axis=1)))
    ends, mid = [node((0.0, 0.0, 0.0)), node((L, 0.0, 0.0))], node((L / 2, 0.0, 0.0))
    assert np.allclose(coarse.mesh.p[:, [*ends, mid]].T, [[0, 0, 0], [L, 0, 0], [L / 2, 0, 0]])
    sag = u[mid, 2] - 0.5 * (u[ends[0], 2] + u[ends[1], 2])
    assert sag == pytest.approx(kappa * L ** 2 / 8, rel=1e-10)
