"""The read-out at the axes' pose (twin.observe.pose): what a moving axis carries into the tool
point's drift and the probes' readings, and the body's rotation fitted to its support points,
each against a closed form on the C-frame moving X, Y and Z (coarse mesh)."""

from __future__ import annotations

import types

import numpy as np
import pytest

from geometries import build_machine
from twin.fem.mesh import mesh_machine

from tests.axis_cases import cframe_all_axes


@pytest.fixture(scope="module")
def cframe_all():
    """The C-frame with the three drives, coarse mesh, and a scenario moving all three axes."""
    return cframe_all_axes()


def test_pose_carry_of_an_affine_field_is_the_field_times_the_offset(cframe_all):
    """Read-out at the pose (twin.observe.pose): for an affine structure displacement
    u(x) = f(t) alpha dT (x - x0) (a free uniform expansion), the carry of each axis at pose p is
    c(p) = f(t) alpha dT (p - p_ref) e, exactly (trilinear interpolation reproduces affine fields,
    hats reproduce linear functions of p); a reading (u_a - u_b) . d gains (m_a - m_b) c . d, and
    nothing at the mesh's pose."""
    from twin.effects.moving import motion_of
    from twin.observe.pose import PoseCarry, support_points
    machine, mm, sc = cframe_all
    g = 12e-6 * 2.0
    x0 = np.array([0.1, -0.2, 0.3])
    u = (g * (mm.mesh.p.T - x0)).ravel()                     # interleaved (x, y, z) per node
    carry = PoseCarry(machine, [machine.tool_point, machine.workpiece_point])
    assert [a.name for a in carry.axes] == ["X", "Y", "Z"]
    for a in carry.axes:
        s = support_points(machine, a)
        assert len(s) == 4 and np.ptp(s[:, "xyz".index(a.direction)]) > 0
    G = carry.functionals(mm)
    f = np.linspace(0.0, 1.0, len(sc.times()))
    raw = f[:, None] * (G @ u)[None, :]
    c = carry.carry(raw, carry.positions(sc.times(), sc))
    for j, a in enumerate(carry.axes):
        p = motion_of(sc, a).position(sc.times())
        expect = f[:, None] * g * (p - a.p_ref)[:, None] * np.eye(3)["xyz".index(a.direction)]
        assert c[:, j] == pytest.approx(expect, rel=1e-9, abs=1e-17)
    # drift = tool - workpiece: the workpiece rides on X and Y, the tool on Z
    corr = carry.correction(raw, carry.positions(sc.times(), sc), [(0, 1, d) for d in np.eye(3)])
    assert corr == pytest.approx(c[:, 2] - c[:, 0] - c[:, 1], rel=1e-9, abs=1e-17)
    still = type(sc)(**{**sc.__dict__, "axes": ()})
    assert np.abs(carry.correction(raw, carry.positions(sc.times(), still), [(0, 1, d) for d in np.eye(3)])).max() < 1e-20


def test_pose_carry_rolls_the_body_with_a_bilinear_field(cframe_all):
    """Read-out at the pose with the body's rotation (twin.observe.pose): for a bilinear structure
    displacement u_z = k x y (the rails rising more along y the further out in x) the support
    points' change D_i = k Delta x_i e_z is a rigid motion, c = k Delta x_c e_z and
    theta = -k Delta e_y (a roll of the saddle as it moves along Y), which trilinear interpolation
    reproduces exactly; a point x of the body then moves by c + theta x (x - s_c) =
    (-k Delta (z - z_c), 0, k Delta x), so a reading between a point on the saddle (or table) and
    the tool or workpiece gains (-k Delta (z_a - z_b) m, 0, k Delta (x_a - x_b) m) with m the
    share of the pair riding on Y (exact to round-off)."""
    from twin.observe.pose import PoseCarry
    machine, mm, sc = cframe_all
    k = 3e-6   # [1/m]
    u = np.zeros((mm.nnodes, 3))
    u[:, 2] = k * mm.mesh.p[0] * mm.mesh.p[1]
    names = [machine.tool_point, machine.workpiece_point, "table", "saddle"]
    carry = PoseCarry(machine, names)
    raw = np.vstack([np.zeros(carry.nrows), carry.functionals(mm) @ u.ravel()])
    j = [a.name for a in carry.axes].index("Y")
    ref = np.array([a.p_ref for a in carry.axes])
    delta = 0.12
    pos = np.vstack([ref, ref + delta * (np.arange(len(ref)) == j)])
    theta = carry.motion(raw, pos)[1, j, 3:]
    assert theta == pytest.approx([0.0, -k * delta, 0.0], abs=1e-12 * k)
    xyz = {n: np.array(machine.point(n).xyz) for n in names}
    centre = carry.rotations[j][0]
    assert xyz["saddle"][0] - centre[0] > 0.3   # a long arm from the supports' centroid
    moved = lambda n: (-k * delta * (xyz[n][2] - centre[2]), 0.0, k * delta * xyz[n][0])
    for a, b in ((3, 0), (2, 1)):   # saddle - tool (the tool does not ride on Y), table - workpiece
        corr = carry.correction(raw, pos, [(a, b, d) for d in np.eye(3)])[1]
        expect = np.subtract(moved(names[a]), moved(names[b]) if b == 1 else 0.0)
        assert corr == pytest.approx(expect, abs=1e-9 * k * delta)


def test_a_machine_at_a_constant_uniform_temperature_does_not_drift_however_its_axes_move(cframe_all):
    """Conservation of the zero state: with no heat source the machine stays at the ambient's
    uniform 20 degC, and however X, Y and Z travel, the tool-point drift and every probe reading
    stay 0 to round-off (a pose's carry is each node's change since the first instant, not its
    displacement at absolute temperature, which would read alpha T (p - p_ref), some 80 um); the
    run's drift is the dataset's, both read at the pose."""
    from twin.io.results import to_dataset
    from twin.model import ModelSpec
    from twin.simulate import run
    machine, mm, sc = cframe_all
    r = run(machine, sc, ModelSpec(()), mm=mm)
    assert r.drift.shape == (len(r.times), 3)
    assert np.abs(r.drift).max() < 1e-15 and np.abs(r.probe).max() < 1e-15
    np.testing.assert_allclose(to_dataset(r).drift.values, r.drift * 1e6, rtol=0, atol=1e-12)


def test_no_pose_rows_without_a_moving_axis():
    """A spindle-only machine has no carried axis: the drift and probes' functionals are the
    plain ones (the gold results unchanged)."""
    from twin.observe import FiveProbeTestBar, ToolDrift
    base = build_machine("cframe-vmc")
    mm = mesh_machine(base, "coarse")
    for o in (ToolDrift(), FiveProbeTestBar()):
        assert (o.all_functionals(mm) != o.functionals(mm)).nnz == 0


def test_the_pose_rotation_is_the_least_squares_fit_of_any_support_displacement():
    """The body's small rotation theta = M^-1 sum_i r_i x D_i (twin.observe.pose, r_i about the
    centroid, M = sum |r|^2 I - r r^T) minimises sum_i |D_i - c - theta x r_i|^2: against numpy's
    least squares on random, non-rigid displacements to round-off (the earlier tests moved the
    supports rigidly, which any consistent fit recovers); points on a line give no rotation
    about that line (the pseudo-inverse)."""
    from twin.observe.pose import rotation_weights

    rng = np.random.default_rng(0)
    points, moved = rng.normal(size=(6, 3)), rng.normal(size=(6, 3)) * 1e-6
    centre, weights = rotation_weights(points)
    theta = np.einsum("abi,ib->a", weights, moved)
    skew = [np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]) for v in points - centre]
    design = np.vstack([-s for s in skew])               # theta x r = -[r]x theta
    fit = np.linalg.lstsq(design, (moved - moved.mean(axis=0)).ravel(), rcond=None)[0]
    assert np.max(np.abs(theta - fit)) <= 1e-10 * np.max(np.abs(fit))
    direction = np.array([1.0, 2.0, 0.5])
    _, on_line = rotation_weights(np.outer(np.arange(4.0), direction))
    assert abs(np.einsum("abi,ib->a", on_line, rng.normal(size=(4, 3))) @ direction) < 1e-12


def test_probe_readings_gain_the_pose_carry_of_a_free_expansion(cframe_all):
    """u = g (x - x0) (free uniform expansion, g = alpha dT): each probe (target on the test bar,
    riding Z; fixture the workpiece on the table, riding X and Y) reads
    g (x_target - x_fixture) . d + g sum_axes (m_target - m_fixture) (p_a - p_ref,a) e_a . d, exactly."""
    from twin.effects.moving import motion_of
    from twin.observe import FiveProbeTestBar
    from twin.observe.pose import carried_axes
    machine, mm, sc = cframe_all
    g, x0 = 24e-6, np.array([0.1, -0.2, 0.3])
    u = (g * (mm.mesh.p.T - x0)).ravel()
    obs = FiveProbeTestBar()
    t = sc.times()
    f = np.linspace(0.0, 1.0, len(t))
    q = obs.readings(f[:, None] * (obs.all_functionals(mm) @ u)[None, :],
                     types.SimpleNamespace(machine=machine, times=t, scenario=sc))
    parts = {p.name: p.part for p in machine.points}
    expect = np.zeros_like(q)
    for i, p in enumerate(machine.probes):
        d = np.asarray(p.direction, float)
        expect[:, i] = f * g * float(np.subtract(machine.point(p.target).xyz, machine.point(p.fixture).xyz) @ d)
        for a in carried_axes(machine):
            m = float(parts[p.target] in a.moving) - float(parts[p.fixture] in a.moving)
            e = np.eye(3)["xyz".index(a.direction)]
            expect[:, i] += f * g * m * (motion_of(sc, a).position(t) - a.p_ref) * float(e @ d)
    assert np.abs(expect - f[:, None] * (obs.functionals(mm) @ u)).max() > 1e-6     # the carry is microns here
    np.testing.assert_allclose(q, expect, rtol=0, atol=1e-15)


def test_support_points_sit_at_a_quarter_and_three_quarters_of_each_carriage(cframe_all):
    """cframe-vmc's Y carriages span y -0.35..0.25 m on rails whose top is z 0.35 m, at x -0.25 and 0.25:
    supports at y -0.2 and 0.1 (1/4, 3/4), x the carriage's centre, 1 mm below the common face."""
    from twin.observe.pose import support_points
    m = cframe_all[0]
    np.testing.assert_allclose(support_points(m, m.axis("Y")),
                               [[-0.25, -0.2, 0.349], [-0.25, 0.1, 0.349], [0.25, -0.2, 0.349], [0.25, 0.1, 0.349]],
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(support_points(m, m.axis("Z"))[:, 2], [1.2125, 1.4375, 1.2125, 1.4375], atol=1e-12)
