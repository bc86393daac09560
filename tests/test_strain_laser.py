"""The FBG strain gauges and the laser triangulation sensors against closed forms.

* A free steel bar at a uniform temperature rise dT is strain-free in stress and expands freely:
  a gauge in any direction reads eps = alpha dT; the grating's raw reading adds the
  cross-sensitivity, eps_raw = (alpha + k_T) dT, and the compensated one takes it off again
  (eps_comp = eps when the compensating sensor sees the same dT).
* A free beam with a temperature linear through its thickness, T = T0 + g (z - z_c), bends
  without stress (the thermal strain alpha g (z - z_c) is compatible): a gauge along the beam on
  its top face reads the closed-form surface strain alpha g (h/2), on the neutral plane 0.
* A laser triangulation sensor reads d . t of a rigid translation t of the test bar (the table
  fixed), and the tilt pair reads a small rigid rotation theta about X as A = theta.
"""

from __future__ import annotations

import types

import numpy as np
import pytest

from geometries import build_machine
from geometries.base import Box, Machine, Part, Point, StrainGauge, Surface, material
from twin.fem.mesh import build_mesh, mesh_machine
from twin.model import ModelSpec
from twin.observe import LaserTriangulation, RunContext, StrainGauges
from twin.physics.prepared import PreparedTwin

STEEL = material("steel")
L, W, H = 1.0, 0.1, 0.1          # bar [m]
E = 1e-3                          # gauges 1 mm inside the face
QUIET = {"fbg": {"noise": 0.0, "quantisation": 0.0},
         "temperature_sensor": {"noise": 0.0, "quantisation": 0.0, "lag": 0.0}}


def _bar(gauges) -> Machine:
    s = Point("s", (0.5, 0.05, H - E), "bar")
    return Machine(name="bar", parts=[Part("bar", STEEL, (Box((0.0, 0.0, 0.0), (L, W, H)),))],
                   surfaces=[Surface("skin", ("bar",))], points=[s], probes=[], tool_point="s",
                   workpiece_point="s", sensor_sites=["s"], resolutions={"test": 0.025}, strain_gauges=gauges)


def _readings(machine, T):
    """Raw rows of the gauges applied to the fields T (n_t, n_nodes) and the packaged variables."""
    mm = build_mesh(machine, 0.025)
    twin = PreparedTwin(machine, mm)
    obs = StrainGauges(machine.strain_gauges)
    rows = obs.rows(twin, types.SimpleNamespace(mm=mm))
    raw = np.asarray([rows @ t for t in T])
    ctx = RunContext(np.arange(len(T)) * 60.0, types.SimpleNamespace(sample_interval=60.0), ModelSpec((), QUIET),
                     machine, None, np.random.default_rng(0))
    data, coords = obs.data(raw, ctx)
    return mm, {k: v[1] for k, v in data.items()}, coords


def test_free_bar_at_uniform_rise_reads_alpha_dT_and_the_cross_sensitivity():
    """eps = alpha dT in every direction; raw = (alpha + k_T) dT; compensated = alpha dT (exact)."""
    diag = (np.sqrt(0.5), np.sqrt(0.5), 0.0)
    gauges = [StrainGauge("along", (0.5, 0.05, H - E), (1.0, 0.0, 0.0), 0.05, "bar"),
              StrainGauge("across", (0.3, 0.05, H - E), (0.0, 1.0, 0.0), 0.05, "bar"),
              StrainGauge("slant", (0.61, 0.05, H - E), diag, 0.05, "bar"),
              StrainGauge("side", (0.2, E, 0.05), (0.0, 0.0, 1.0), 0.06, "bar")]
    machine = _bar(gauges)
    mm = build_mesh(machine, 0.025)
    dT = 7.0
    T = np.vstack([np.full(mm.nnodes, 20.0), np.full(mm.nnodes, 20.0 + dT)])
    _, r, coords = _readings(machine, T)
    alpha, kt = STEEL.expansion * 1e6, 8.64     # um/m/K
    np.testing.assert_allclose(r["strain_true"][1], alpha * dT, rtol=1e-10)
    np.testing.assert_allclose(r["strain_raw"][1], (alpha + kt) * dT, rtol=1e-10)
    np.testing.assert_allclose(r["strain"][1], alpha * dT, rtol=1e-10)
    assert list(coords["gauge_sensor"][1]) == ["s"] * 4
    assert coords["gauge_dx"][1][2] == pytest.approx(np.sqrt(0.5))


def test_gauge_on_a_thermally_bent_beam_reads_the_surface_strain():
    """T = T0 + g (z - H/2): eps_xx = alpha g (z - H/2), on the top face alpha g (H/2 - 1 mm),
    on the neutral plane 0 (Wilson-Taylor bricks bend exactly: round-off)."""
    g = 40.0   # K/m through the 0.1 m thickness: 4 K top to bottom
    gauges = [StrainGauge("top", (0.5, 0.05, H - E), (1.0, 0.0, 0.0), 0.05, "bar"),
              StrainGauge("bottom", (0.37, 0.05, E), (1.0, 0.0, 0.0), 0.05, "bar"),
              StrainGauge("neutral", (0.5, E, H / 2), (1.0, 0.0, 0.0), 0.05, "bar")]
    machine = _bar(gauges)
    mm = build_mesh(machine, 0.025)
    z = mm.mesh.p[2]
    T = np.vstack([np.full(mm.nnodes, 20.0), 20.0 + g * (z - H / 2)])
    _, r, _ = _readings(machine, T)
    alpha = STEEL.expansion * 1e6
    expected = alpha * g * np.array([H / 2 - E, E - H / 2, 0.0])
    np.testing.assert_allclose(r["strain_true"][1], expected, atol=1e-9 * abs(expected[0]))


def test_the_grating_reads_its_mean_temperature_along_its_length():
    """T = T0 + g x along the bar: a grating from x_c - l/2 to x_c + l/2 along x has the mean
    temperature rise g x_c (five-point Gauss quadrature and trilinear interpolation are exact for a
    linear field), so its raw reading exceeds the true strain by k_T g x_c, and the reading
    compensated with sensor s (at x = 0.5 m, rise g 0.5 m) by k_T g (x_c - 0.5 m); gauges across
    x see the rise at their centre alike. To round-off."""
    g = 30.0      # K/m along the bar: 30 K end to end
    gauges = [StrainGauge("near", (0.1, 0.05, H - E), (1.0, 0.0, 0.0), 0.08, "bar"),
              StrainGauge("far", (0.83, 0.05, H - E), (-1.0, 0.0, 0.0), 0.12, "bar"),
              StrainGauge("across", (0.37, 0.05, H - E), (0.0, 1.0, 0.0), 0.05, "bar")]
    machine = _bar(gauges)
    mm = build_mesh(machine, 0.025)
    x = mm.mesh.p[0]
    T = np.vstack([np.full(mm.nnodes, 20.0), 20.0 + g * x])
    _, r, _ = _readings(machine, T)
    kt, xc = 8.64, np.array([0.1, 0.83, 0.37])     # um/m/K; the gauges' centres [m]
    np.testing.assert_allclose(r["strain_raw"][1] - r["strain_true"][1], kt * g * xc, rtol=1e-11)
    np.testing.assert_allclose(r["strain"][1] - r["strain_true"][1], kt * g * (xc - 0.5), rtol=1e-11)


def test_the_grating_weighs_its_length_by_gauss_quadrature():
    """T = T0 + q (x - x_c)^2 about a 120 mm grating's centre x_c: its mean rise is q l^2 / 12
    (1.2 K at q = 1000 K/m2). The grating reads the five-point Gauss mean of the interpolated
    field; the weights are positive and sum to one and Gauss is exact for the quadratic, so the
    reading is off only by the interpolant's error, at most q h^2 / 4 (f'' h^2 / 8 on cells of h =
    25 mm): k_T (mean rise) within k_T q h^2 / 4. Equal weights on the same points would read
    q l^2 / 9 (0.4 K more, beyond that bound)."""
    q, l, xc, h = 1000.0, 0.12, 0.4, 0.025
    machine = _bar([StrainGauge("mid", (xc, 0.05, H - E), (1.0, 0.0, 0.0), l, "bar")])
    mm = build_mesh(machine, h)
    assert np.allclose(np.diff(np.unique(mm.mesh.p[0])), h)
    T = np.vstack([np.full(mm.nnodes, 20.0), 20.0 + q * (mm.mesh.p[0] - xc) ** 2])
    _, r, _ = _readings(machine, T)
    kt = 8.64                                     # um/m/K
    mean_rise = (r["strain_raw"][1] - r["strain_true"][1])[0] / kt
    assert abs(mean_rise - q * l ** 2 / 12) <= q * h ** 2 / 4
    assert abs(q * l ** 2 / 9 - q * l ** 2 / 12) > 2 * q * h ** 2 / 4


@pytest.fixture(scope="module")
def gantry():
    m = build_machine("gantry-ram")
    mm = mesh_machine(m, "coarse")
    return m, mm, LaserTriangulation().functionals(mm)


def _chain_nodes(m, mm, parts):
    return np.unique(mm.mesh.t[:, mm.cells_of(*parts)])


def test_laser_reads_a_rigid_translation_of_the_test_bar(gantry):
    """Tool side translated by t, table at rest: each sensor reads d . t."""
    m, mm, G = gantry
    t = np.array([3e-6, -5e-6, 7e-6])
    u = np.zeros((mm.nnodes, 3))
    u[_chain_nodes(m, mm, ("test_bar", "spindle", "head"))] = t
    reading = G @ u.ravel()
    np.testing.assert_allclose(reading, [p_dir @ t for p_dir in (np.asarray(p.direction) for p in m.lasers)],
                               rtol=1e-12)


def test_laser_tilt_pair_reads_a_small_rotation_about_x(gantry):
    """u = theta e_x x (r - r0) on the tool side: A1 - A2 = theta * spacing, A = theta."""
    m, mm, G = gantry
    theta, r0 = 20e-6, np.array([0.0, 0.0, 1.0])
    nodes = _chain_nodes(m, mm, ("test_bar", "spindle", "head"))
    u = np.zeros((mm.nnodes, 3))
    u[nodes] = np.cross([theta, 0.0, 0.0], mm.mesh.p[:, nodes].T - r0)
    raw = np.vstack([np.zeros(len(m.lasers)), G @ u.ravel()])
    ctx = RunContext(np.array([0.0, 60.0]), None, ModelSpec((), {"laser_triangulation": {"noise": 0.0, "resolution": 0.0}}),
                     m, None, np.random.default_rng(0))
    data, _ = LaserTriangulation().data(raw, ctx)
    assert data["laser_tilt"][1][1] == pytest.approx(theta * 1e6, rel=1e-10)
    assert data["laser_tilt_true"][1][1] == pytest.approx(theta * 1e6, rel=1e-10)


def test_each_gauge_is_compensated_by_its_nearest_glued_sensor():
    """gantry-ram: FBG-1, -2 on the ram by T1, FBG-3 by T3 (its own site), FBG-4..7 on the beam by
    T2, T4, T5, T6; no sensor site lies closer to a gauge than the one chosen."""
    from twin.observe.strain import nearest_sensor
    m = build_machine("gantry-ram")
    chosen = [nearest_sensor(m, g.xyz) for g in m.strain_gauges]
    assert chosen == ["T1", "T1", "T3", "T2", "T4", "T5", "T6"]
    for g, n in zip(m.strain_gauges, chosen):
        d = {s: np.linalg.norm(np.subtract(m.point(s).xyz, g.xyz)) for s in m.sensor_sites}
        assert d[n] == min(d.values())
