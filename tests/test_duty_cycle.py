"""Probing datum points (twin.observe.probing) and the thesis's duty cycle Test-I on the C-frame
with its three drives (issue 11, item 7)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from geometries import build_machine
from geometries.base import material
from twin.fem.mesh import mesh_machine
from twin.motion import machine_for
from twin.observe.interferometer import screw_line_rows
from twin.observe.probing import DatumProbing, ProbingConfig
from twin.scenario import load_scenario

SEED_PEAK = {"X": 27.0, "Y": 32.0, "Z": 74.0}   # um, seed 000 Test-I (thesis L6622-6626)


@pytest.fixture(scope="module")
def duty():
    """Test-I on the coarse mesh at 60 s steps (the path basis is exact over steps, so the heat is
    that of the bundled 30 s scenario)."""
    from twin.api import simulate
    sc = load_scenario("thesis-duty-test1")
    return simulate("cframe-vmc", replace(sc, sample_interval=60.0), resolution="coarse")[0]


def test_probing_screw_share_at_a_uniform_rise_is_alpha_dT_times_the_nut_distance():
    """With the structure still and every screw at a uniform rise dT, datum j reads, along each
    axis, s_a alpha dT (nut_a(p_aj) - fixed_a): s = -1 for X and Y (they carry the workpiece: the
    tool moves the other way relative to it), +1 for Z (it carries the tool); exact."""
    sc = load_scenario("thesis-duty-test1")
    machine = machine_for(build_machine("cframe-vmc"), sc)
    mm = mesh_machine(machine, "coarse")
    obs = DatumProbing(ProbingConfig((0.0, 60.0), ((0.10, 0.05, 0.02), (0.45, 0.35, 0.30))), machine)
    carry, _ = obs._carry(machine)
    alpha, dT = material("steel").expansion, 2.5
    T = np.stack([np.full(mm.nheat, 20.0), np.full(mm.nheat, 20.0 + dT)])
    screws = np.hstack([T @ screw_line_rows(mm, a, obs.datums[:, "XYZ".index(a.name)], alpha).T.toarray()
                        for a in obs.screws])
    raw = np.hstack([np.zeros((2, 3 + carry.nrows)), screws])
    err = obs.errors(raw, machine)
    assert [a.name for a in obs.screws] == ["X", "Y", "Z"]
    for k, a in enumerate(obs.screws):
        nut = a.nut_coordinate(obs.datums[:, k])
        expect = (1.0 if a.name == "Z" else -1.0) * alpha * dT * (nut - a.drive.fixed_end)
        assert err[1, :, k] == pytest.approx(expect, rel=1e-12)
    assert np.all(err[0] == 0.0)


def test_probing_reads_the_drift_at_each_datums_pose_for_an_affine_field():
    """The structure in a free uniform expansion u(x) = g (x - x0) and every screw still: datum j
    at pose p reads, from the baseline (u = 0), the tool-minus-workpiece drift at the mesh's pose,
    g (x_tool - x_workpiece), plus each axis's carry to the datum's pose, g (p_a - p_ref,a) along
    its direction, with the sign of what it carries: -1 for X and Y (the workpiece), +1 for Z
    (the tool). Exact to round-off (trilinear interpolation and the pose's hats reproduce affine
    fields; a uniform expansion has no rotation)."""
    sc = load_scenario("thesis-duty-test1")
    machine = machine_for(build_machine("cframe-vmc"), sc)
    mm = mesh_machine(machine, "coarse")
    datums = ((0.10, 0.05, 0.02), (0.45, 0.35, 0.30), (0.30, 0.20, 0.15))
    obs = DatumProbing(ProbingConfig((0.0, 60.0), datums), machine)
    g, x0 = 24e-6, np.array([0.1, -0.2, 0.3])
    u = (g * (mm.mesh.p.T - x0)).ravel()
    rows = obs.all_functionals(mm)
    raw = np.vstack([np.zeros(rows.shape[0]), rows @ u])
    raw = np.hstack([raw, np.zeros((2, len(obs.screws) * len(datums)))])
    err = obs.errors(raw, machine)
    xyz = {n: np.array(machine.point(n).xyz) for n in (machine.tool_point, machine.workpiece_point)}
    drift = g * (xyz[machine.tool_point] - xyz[machine.workpiece_point])
    sign = {"X": -1.0, "Y": -1.0, "Z": 1.0}
    for j, p in enumerate(np.array(datums)):
        expect = drift + np.array([sign[a.name] * g * (p[k] - a.p_ref) for k, a in enumerate(machine.axes[:3])])
        assert err[1, j] == pytest.approx(expect, rel=1e-9, abs=1e-18)
    assert np.all(err[0] == 0.0)


def test_duty_cycle_peaks_lie_within_30_percent_of_the_thesis(duty):
    """Test-I: the largest probed error per axis over the datums and probings lies within +-30 %
    of the thesis's X 27, Y 32, Z 74 um (plausible, not a measured machine), the screw nuts and
    feed motors warm, and the probing's baseline is zero."""
    e = duty.probing_error
    assert e.attrs["units"] == "um" and np.all(e.values[0] == 0.0)
    peak = np.abs(e.values).max(axis=(0, 1))
    for k, ax in enumerate("XYZ"):
        assert 0.7 * SEED_PEAK[ax] <= peak[k] <= 1.3 * SEED_PEAK[ax], (ax, peak[k])
    t = duty.temperature_true
    for site in ("X_nut", "Y_nut", "Z_nut", "X_motor", "Y_motor", "Z_motor"):
        rise = float(t.sel(sensor=site).max() - t.sel(sensor=site)[0])
        assert 1.0 < rise < 10.0, (site, rise)


def test_instruments_read_at_the_nearest_output_step_of_their_instant():
    """4.1 h is 14759.999999999998 s in floating point: at 10 s steps the probing (and an
    interferometer run) reads step 1476, not 1475."""
    from twin.observe.probing import DatumProbing, ProbingConfig
    from twin.observe.instants import baseline_instants
    times = baseline_instants(["0 h", "4.1 h"], "s.toml", "probing.times", "the datum baseline")
    assert times[1] < 14760.0
    obs = DatumProbing(ProbingConfig(times, ((0.1, 0.1, 0.1),)), build_machine("cframe-vmc"))
    assert obs.sample_steps(np.arange(0.0, 15000.0, 10.0)).tolist() == [0, 1476]
