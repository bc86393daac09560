"""Thermoelasticity against closed-form answers, and the adjoint drift identity."""

from __future__ import annotations

import numpy as np
import pytest

from tests.conftest import box_body
from twin.physics.elastic import ElasticSolver
from geometries.materials import MATERIALS
from twin.fem.points import displacement_functional, interpolation_matrix


def _node(mm, xyz):
    return int(np.argmin(np.sum((mm.mesh.p.T - np.asarray(xyz)) ** 2, axis=1)))


def test_free_expansion_of_a_steel_bar():
    """Uniform rise dT of a free bar: dL = alpha L dT and the lateral growth alpha w dT, exactly
    (a uniform thermal strain lies in the element space: to round-off), and no constraint blocks
    it: the whole field is the affine alpha dT (x - x_0) plus a rigid motion."""
    L, w, dT = 0.5, 0.05, 10.0
    mm = box_body((L, w, w), 0.025)
    solver = ElasticSolver.build(mm)
    u = solver.displacement(np.full(mm.nnodes, dT))
    exact = MATERIALS["steel"].expansion * L * dT
    end0, end1 = _node(mm, (0, w / 2, w / 2)), _node(mm, (L, w / 2, w / 2))
    assert u[end1, 0] - u[end0, 0] == pytest.approx(exact, rel=1e-12)
    # lateral growth too: alpha w dT
    assert u[_node(mm, (L / 2, w, w / 2)), 1] - u[_node(mm, (L / 2, 0, w / 2)), 1] == pytest.approx(
        MATERIALS["steel"].expansion * w * dT, rel=1e-12)
    # the whole field: alpha dT x + a rigid motion (its least-squares fit leaves round-off only)
    p = mm.mesh.p.T
    A = np.column_stack([np.ones(len(p)), p])
    for d in range(3):
        coef, *_ = np.linalg.lstsq(A, u[:, d] - MATERIALS["steel"].expansion * dT * p[:, d], rcond=None)
        assert np.max(np.abs(A @ coef - (u[:, d] - MATERIALS["steel"].expansion * dT * p[:, d]))) < 1e-12 * exact


def test_free_beam_with_linear_gradient_bends_with_curvature_alpha_dT_over_h():
    """T linear through the depth h (dT from bottom to top): curvature kappa = alpha dT / h, so the
    mid-span rises kappa L^2 / 8 against the ends, exactly for the incompatible-mode brick (it
    represents pure bending: to round-off; plain trilinear bricks lock in shear and miss it by
    1.5e-3 on this mesh)."""
    L, b, h, dT = 1.0, 0.05, 0.1, 10.0
    mm = box_body((L, b, h), 0.025, material="grey_cast_iron")
    solver = ElasticSolver.build(mm)
    z = mm.mesh.p[2]
    u = solver.displacement(dT * (z / h - 0.5))
    kappa = MATERIALS["grey_cast_iron"].expansion * dT / h
    axis = [_node(mm, (x, b / 2, h / 2)) for x in (0.0, L / 2, L)]
    sag = u[axis[1], 2] - 0.5 * (u[axis[0], 2] + u[axis[2], 2])
    assert sag == pytest.approx(kappa * L**2 / 8, rel=1e-10)  # hot top is longer: convex upwards


def test_adjoint_drift_equals_full_displacement_solve(machine_coarse_run):
    """q = g^T K^-1 C dT computed as (C^T K^-1 g)^T dT equals g^T u of a full solve: to round-off
    with the direct solver (1e-11; measured 4e-13), to the adjoints' CG tolerance (1e-8) when the
    suite forces an iterative one."""
    import scipy.sparse as sp

    from twin.observe import FiveProbeTestBar, ToolDrift

    r = machine_coarse_run
    solver = ElasticSolver.build(r.mm)
    g = sp.vstack([ToolDrift().functionals(r.mm), FiveProbeTestBar().functionals(r.mm)]).tocsr()
    dT = r.hottest_field - r.scenario.start_temperature
    full = g @ solver.solve(solver.matrices.C @ dT)
    adjoint = solver.influence(g).T @ dT
    tol = 1e-11 if r.solver_info.get("solver_method") == "direct" else 1e-8
    assert np.max(np.abs(adjoint - full)) <= tol * np.max(np.abs(full))
    # and the run's own drift at the hottest instant is the same number
    i = int(np.argmin(np.abs(r.times - r.hottest_time)))
    assert np.allclose(r.drift[i], full[:3], rtol=1e-8, atol=1e-8 * np.max(np.abs(full)))


def test_point_interpolation_is_exact_for_trilinear_fields():
    """Trilinear interpolation reproduces any field a + b x + c y + d z + e xyz exactly."""
    mm = box_body((0.3, 0.2, 0.1), 0.05)
    x, y, z = mm.mesh.p
    field = 1 + 2 * x - 3 * y + 4 * z + 5 * x * y * z
    pts = np.array([[0.013, 0.17, 0.05], [0.29, 0.01, 0.099]])
    P = interpolation_matrix(mm, pts)
    exact = 1 + 2 * pts[:, 0] - 3 * pts[:, 1] + 4 * pts[:, 2] + 5 * pts.prod(axis=1)
    assert np.allclose(P @ field, exact, rtol=1e-12)
    D = displacement_functional(interpolation_matrix(mm, pts, field="mesh"), [0, 0, 1])
    u = np.zeros(3 * mm.nnodes)
    u[2::3] = field
    assert np.allclose(D @ u, exact, rtol=1e-12)


def test_uniaxial_strain_and_thermal_forces_give_the_elastic_moduli():
    """Hooke's law in the element: a uniaxial strain u = e x e_x gives the constrained (P-wave)
    modulus sigma_xx = E (1 - nu) / ((1 + nu)(1 - 2 nu)) e on the face x = L and the lateral stress
    sigma_yy = E nu / ((1 + nu)(1 - 2 nu)) e on the face y = w, and no force inside (uniform stress);
    a uniform rise dT pushes the face x = L with 3 K alpha dT A, the bulk modulus K = E / (3 (1 - 2 nu)).
    All exact for trilinear elements on these linear fields: to round-off. (The stress-free
    thermal tests above cannot see E or nu.)"""
    from twin.fem.assembly import assemble_elastic
    L, w, e, dT = 0.3, 0.1, 1e-4, 1.0
    mm = box_body((L, w, w), 0.05)
    steel = MATERIALS["steel"]
    E, nu = steel.youngs_modulus, steel.poisson_ratio
    el = assemble_elastic(mm)
    p = mm.mesh.p.T
    u = np.zeros((mm.nnodes, 3))
    u[:, 0] = e * p[:, 0]
    f = (el.K @ u.ravel()).reshape(-1, 3)
    right, top = np.isclose(p[:, 0], L), np.isclose(p[:, 1], w)
    sigma_xx = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) * e
    assert f[right, 0].sum() == pytest.approx(sigma_xx * w * w, rel=1e-12)
    assert f[top, 1].sum() == pytest.approx(E * nu / ((1 + nu) * (1 - 2 * nu)) * e * L * w, rel=1e-12)
    inside = np.all((p > 1e-9) & (p < np.array([L, w, w]) - 1e-9), axis=1)
    assert inside.any() and np.abs(f[inside]).max() < 1e-12 * sigma_xx * w * w
    thermal = (el.C @ np.full(mm.nheat, dT)).reshape(-1, 3)
    assert thermal[right, 0].sum() == pytest.approx(E / (1 - 2 * nu) * steel.expansion * dT * w * w, rel=1e-12)


def test_simple_shear_gives_the_shear_modulus():
    """Hooke's law in shear: u_x = gamma y gives sigma_xy = mu gamma, mu = E / (2 (1 + nu)), so the
    face y = w carries the force mu gamma L w along x (and the face y = 0 the opposite), with no
    force inside: exact for trilinear elements on a linear field, to round-off. (The uniaxial test
    sees only lambda and lambda + 2 mu.)"""
    from twin.fem.assembly import assemble_elastic
    L, w, gamma = 0.3, 0.1, 1e-4
    mm = box_body((L, w, w), 0.05)
    steel = MATERIALS["steel"]
    mu = steel.youngs_modulus / (2 * (1 + steel.poisson_ratio))
    p = mm.mesh.p.T
    u = np.zeros((mm.nnodes, 3))
    u[:, 0] = gamma * p[:, 1]
    f = (assemble_elastic(mm).K @ u.ravel()).reshape(-1, 3)
    top, bottom = np.isclose(p[:, 1], w), np.isclose(p[:, 1], 0.0)
    assert f[top, 0].sum() == pytest.approx(mu * gamma * L * w, rel=1e-12)
    assert f[bottom, 0].sum() == pytest.approx(-mu * gamma * L * w, rel=1e-12)
    inside = np.all((p > 1e-9) & (p < np.array([L, w, w]) - 1e-9), axis=1)
    assert inside.any() and np.abs(f[inside]).max() < 1e-12 * mu * gamma * L * w


def test_rigid_body_modes_store_no_strain_energy():
    """The AMG's near-null space: the three translations and the three rotations about the
    centroid, u = t + omega x (x - c), strain nothing, so the unsupported stiffness maps each of the
    six modes to zero (K B = 0, to round-off relative to |K| |B|), and the six are independent."""
    from twin.fem.assembly import assemble_elastic
    from twin.physics.solvers import rigid_body_modes
    mm = box_body((0.3, 0.1, 0.05), 0.025)
    K = assemble_elastic(mm).K
    B = rigid_body_modes(mm.mesh.p.T)
    assert B.shape == (3 * mm.nnodes, 6) and np.linalg.matrix_rank(B) == 6
    assert np.abs(K @ B).max() <= 1e-12 * abs(K).max() * np.abs(B).max()


def test_amg_solves_each_column_of_a_block_to_its_own_relative_residual():
    """A block of loads goes through one AMG-CG run with each column held to its own tolerance,
    ||K u_j - f_j|| <= rtol ||f_j|| (twin.physics.solvers.AmgElastic): a load a million times
    smaller beside a large one (a bending next to a uniform expansion) is solved as accurately,
    relative to itself, as when it is alone, and agrees with the direct solution to that accuracy."""
    mm = box_body((0.25, 0.05, 0.05), 0.0125)
    amg = ElasticSolver.build(mm, method="amg", rtol=1e-8)
    direct = ElasticSolver.build(mm)
    x = mm.mesh.p[0]
    loads = np.column_stack([amg.matrices.C @ np.full(mm.nnodes, 10.0), 1e-6 * (amg.matrices.C @ (x / 0.25))])
    loads[amg.fixed] = 0.0
    u = amg.solve(loads)
    for j in range(2):
        f = loads[:, j]
        assert np.linalg.norm(amg.matrices.K @ u[:, j] - f) <= 1e-8 * np.linalg.norm(f) * (1 + 1e-9), j
        ref = direct.solve(direct.matrices.C @ ([np.full(mm.nnodes, 10.0), 1e-6 * x / 0.25][j]))
        assert np.abs(u[:, j] - ref).max() <= 1e-5 * np.abs(ref).max(), j


def test_each_materials_expansion_and_band_are_the_span_its_source_states():
    """Every material's alpha lies in the span of alpha its band's source states ("span about
    a-b e-6 /K"), and its band (the diagnosis's plausible relative spread) is that span's half width
    over alpha, rounded to within 0.02: grey iron 9.5-11.5 on 10.5 (0.095 -> 0.10), steel
    10.6-12.4 on 11.5 (0.078 -> 0.08), granite 5.5-8.5 on 7.0 (0.214 -> 0.20), polymer concrete
    12-16 on 14 (0.143 -> 0.15), aluminium 22-24 on 23 (0.043 -> 0.05);
    including the materials no bundled machine uses, which nothing else pins."""
    import re

    from geometries.materials import MATERIALS

    for m in MATERIALS.values():
        lo, hi = (float(v) * 1e-6 for v in re.search(r"span about ([\d.]+)-([\d.]+)e-6", m.expansion_band_source).groups())
        assert lo < m.expansion < hi, m.name
        assert m.expansion_band == pytest.approx(0.5 * (hi - lo) / m.expansion, abs=0.02), m.name

