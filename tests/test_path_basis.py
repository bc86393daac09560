"""The axis motion and the path basis that carries a travelling heat source, against closed forms:
trapezoidal strokes, the energy a reciprocating nut delivers, the time weights while the axis
accelerates, the motor's inertia losses, a standing nut and the basis's convergence. The feed
drive's structure, loops and calibration are in ``tests/test_feed_drive.py``, whose rod machine and
scenarios these share."""

from __future__ import annotations

import numpy as np
import pytest

from tests.test_feed_drive import RECIP, rod_machine, scenario
from twin.effects.base import HeatSource
from twin.effects.moving import travelling_sources
from twin.errors import InputError
from twin.fem.mesh import build_mesh
from twin.motion import path_nodes, path_weights, stroke_time
from twin.physics.loads import source_pattern


def test_trapezoid_stroke_time_and_positions():
    """A trapezoidal stroke lasts d/v + v/a (feed reached) or 2 sqrt(d/a) (triangular)."""
    sc = scenario([{**RECIP, "count": 3}])
    m = sc.axes[0]
    t1 = 0.4 / 0.02 + 0.02 / 0.01
    assert stroke_time(0.4, 0.02, 0.01) == pytest.approx(t1, rel=1e-15)
    assert stroke_time(0.001, 0.02, 0.01) == pytest.approx(2 * np.sqrt(0.1), rel=1e-15)
    assert m.duration == pytest.approx(3 * t1, rel=1e-12)
    assert m.position(np.array([0.0, t1, 2 * t1, 3 * t1, 1e6])) == pytest.approx([0, 0.4, 0, 0.4, 0.4], abs=1e-15)
    # constant feed in mid-stroke, accelerating at 10 mm/s2 from rest
    assert m.velocity(np.array([1.0, t1 / 2])) == pytest.approx([0.01, 0.02], rel=1e-12)
    # a move to 100 mm (a trapezoid: 0.1 m >= v^2 / a = 0.04 m), then holding there to 1 min
    mv = scenario([{"kind": "move", "to": "100 mm", "feed": "20 mm/s", "acceleration": "10 mm/s2",
                    "duration": "1 min"}], duration="20 min", dt="10 s", start="0 mm").axes[0]
    t_move = 0.1 / 0.02 + 0.02 / 0.01
    assert mv.position(np.array([t_move, 60.0, 600.0])) == pytest.approx([0.1] * 3, abs=1e-15)
    assert mv.duration == pytest.approx(60.0)
    with pytest.raises(InputError, match="longer than the duration"):
        scenario([{"kind": "move", "to": "100 mm", "feed": "20 mm/s", "acceleration": "10 mm/s2",
                   "duration": "5 s"}], duration="20 min", start="0 mm")
    with pytest.raises(InputError, match="needs the axis's start"):
        scenario([{"kind": "move", "to": "100 mm", "feed": "20 mm/s", "acceleration": "10 mm/s2"}])


def test_an_axis_stands_still_from_the_end_of_its_last_piece():
    """``Motion.velocity`` / ``acceleration``: each piece holds on [t0, t0 + dur), and after the
    last piece the axis holds x_end (``Motion``'s docstring: 0 outside the pieces), so a motion
    that ends moving - a table from 0 to 100 mm in 10 s, 10 mm/s, or accelerating at 2 mm/s2 for
    10 s - has velocity and acceleration 0 from its end on, and its own within."""
    from twin.motion import Motion

    table = Motion("Y", [0.0], [10.0], [0.0], [0.01], [0.0], 0.1)
    t = np.array([0.0, 9.999, 10.0, 60.0])
    assert table.velocity(t).tolist() == [0.01, 0.01, 0.0, 0.0]
    assert table.position(t) == pytest.approx([0.0, 0.09999, 0.1, 0.1], rel=1e-12)
    ramp = Motion("Y", [0.0], [10.0], [0.0], [0.0], [0.002], 0.1)
    assert ramp.acceleration(t).tolist() == [0.002, 0.002, 0.0, 0.0]
    assert ramp.velocity(t) == pytest.approx([0.0, 0.019998, 0.0, 0.0], rel=1e-12)


def test_reciprocating_source_delivers_power_times_duty():
    """Energy balance over whole strokes: a nut heat P_ref |v|/v_ref delivers P_ref d / v_ref, d the
    travelled distance (= P_ref x duty x T); summed over the path basis on the time steps, exact."""
    sc = scenario([{**RECIP, "count": 20, "dwell": "4 s"}], duration="20 min")
    machine = rod_machine()
    mm = build_mesh(machine, 0.02)
    P, v = 12.0, 0.02
    srcs = travelling_sources("nut", mm, "feed_drive.y.screw", machine.axes[0], sc.axes[0], sc, P / v, "distance")
    t = sc.times()
    energy = sum(np.sum(s.power(t[:-1] + 0.5 * sc.sample_interval)) * sc.sample_interval for s in srcs)
    assert energy == pytest.approx(P * 20 * 0.4 / v, rel=1e-12)
    # every basis weight integrates phi_i exactly: interior nodes receive h per pass, end nodes h / 2
    nodes = path_nodes(0.0, 0.4, 0.01)
    w = path_weights(sc.axes[0], nodes, t, "distance").sum(axis=0) * sc.sample_interval
    assert w[1:-1] == pytest.approx(20 * 0.01, rel=1e-12)
    assert w[[0, -1]] == pytest.approx(20 * 0.005, rel=1e-12)
    # through the heat integrator (Crank-Nicolson, the run's own energy balance): the same joules,
    # and the stored heat gains them all (the rod has no convection here)
    from twin.model import ModelSpec
    from twin.observe import HeatBalance
    from twin.simulate import run
    r = run(machine, sc, ModelSpec(("feed_nut_y",), {"feed_nut_y": {"power": P}}), resolution="coarse",
            observers=[HeatBalance()])
    into, convected, stored = r.step_energy()
    assert into == pytest.approx(P * 20 * 0.4 / v, rel=1e-12)
    assert convected == 0.0 and stored == pytest.approx(into, rel=1e-9)


def test_time_weights_are_a_partition_of_unity_and_average_the_position_exactly():
    """per="time": w_i = (1/dt) int phi_i(x(t)) dt over each sample interval. The hats are a
    partition of unity and reproduce linear functions (sum_i phi_i = 1, sum_i s_i phi_i(x) = x on
    the nodes' range), so sum_i w_i = 1 and sum_i s_i w_i = (1/dt) int x dt, which on a piece
    x0 + v0 tau + a tau^2 / 2 is x0 T + v0 T^2 / 2 + a T^3 / 6: exact where the axis stands, moves
    at constant speed and, with the 24-point Gauss rule on a quadratic, while it accelerates
    (here 2 s ramps inside 10 s samples, and a slow ramp over whole samples)."""
    for move in ({**RECIP, "count": 3}, {**RECIP, "acceleration": "0.5 mm/s2", "count": 1}):
        sc = scenario([move], duration="20 min")
        m = sc.axes[0]
        nodes = path_nodes(0.0, 0.4, 0.01)
        edges = sc.times()
        w = path_weights(m, nodes, edges, "time")
        np.testing.assert_allclose(w.sum(axis=1), 1.0, rtol=0, atol=1e-12)
        exact = np.zeros(len(edges) - 1)
        for t0, dur, x0, v0, a in zip(m.t0, m.dur, m.x0, m.v0, m.a):
            for k in range(len(edges) - 1):        # the piece's share of each sample interval
                lo, hi = max(edges[k], t0), min(edges[k + 1], t0 + dur)
                if hi > lo:
                    ta, tb = lo - t0, hi - t0
                    exact[k] += (x0 * (tb - ta) + v0 * (tb ** 2 - ta ** 2) / 2 + a * (tb ** 3 - ta ** 3) / 6)
        end = m.t0[-1] + m.dur[-1]
        exact += m.x_end * np.clip(edges[1:] - np.maximum(edges[:-1], end), 0.0, None)   # standing at its end
        np.testing.assert_allclose(w @ nodes, exact / np.diff(edges), rtol=0, atol=1e-12)


@pytest.mark.parametrize("feed, accel, stroke", [("20 mm/s", "10 mm/s2", 0.4), ("200 mm/s", "50 mm/s2", 0.4)])
def test_motor_inertia_losses_integrate_the_squared_acceleration(feed, accel, stroke):
    """Copper losses of the inertia torque, P_a (a / a_ref)^2: per whole stroke the integral of
    a^2 is 2 a v when the stroke reaches its feed (two ramps of v / a) and 2 a^(3/2) d^(1/2) when
    it does not (two ramps of (d / a)^(1/2)); the step averages (held on each 10 s step, ramps
    crossing the step edges) deliver P_a n int a^2 / a_ref^2 to round-off, and each step's energy
    equals a 1 ms midpoint sum of a(t)^2 (to that sum's own error: a 1 ms sample on the wrong
    side of each of the at most four ramp ends in a step)."""
    from twin.effects.moving import acceleration_signal
    sc = scenario([{**RECIP, "feed": feed, "acceleration": accel, "count": 6, "dwell": "3 s"}], duration="20 min")
    v, a = float(feed.split()[0]) * 1e-3, float(accel.split()[0]) * 1e-3
    per_stroke = 2 * a * v if v * v / a <= stroke else 2 * a ** 1.5 * stroke ** 0.5
    P_a, t, dt = 12.0, sc.times(), sc.sample_interval
    signal = acceleration_signal(sc, sc.axes[0], P_a)
    steps = signal(t[:-1] + 0.5 * dt) * dt
    assert steps.sum() == pytest.approx(P_a * 6 * per_stroke, rel=1e-12)
    fine = np.arange(0.0, t[-1], 1e-3) + 5e-4
    a_fine = sc.axes[0].acceleration(fine)
    np.testing.assert_allclose(steps, P_a * np.add.reduceat(a_fine ** 2 * 1e-3, np.searchsorted(fine, t[:-1])),
                               rtol=0, atol=4 * 1e-3 * P_a * a ** 2)


def test_standing_nut_equals_a_stationary_source():
    """A nut holding at p releases its heat where a stationary source on that slab of the screw
    would: sum_j pattern_j s_j(t) = pattern(slab) P at every step (phi sums to 1)."""
    sc = scenario([{"kind": "hold", "position": "130 mm", "duration": "20 min"}])
    machine = rod_machine()
    mm = build_mesh(machine, 0.02)
    srcs = travelling_sources("nut", mm, "feed_drive.y.screw", machine.axes[0], sc.axes[0], sc, 5.0, "time")
    t = sc.times()[1:]
    moving = sum(np.outer(s.power(t), source_pattern(mm, s)) for s in srcs)
    cells = mm.cells_of("rod")
    y = mm.mesh.p[1, mm.mesh.t[:, cells]].mean(axis=0)
    still = HeatSource("still", cells[np.abs(y - 0.13) < 0.0100001], lambda t: np.full(np.shape(t), 5.0))
    assert np.abs(moving - np.outer(still.power(t), source_pattern(mm, still))).max() < 1e-12


def test_path_basis_converges_as_its_spacing_shrinks():
    """A nut standing at y = 137 mm (between nodes) puts its heat into the slab of the screw that
    holds it (exact: all of it); the path basis spreads it over hats of half-width h, so the heat
    outside that slab falls as h shrinks and vanishes once the hats fit inside the slab. At constant
    speed the basis is exact at every spacing (each slab gets its length's share)."""
    machine = rod_machine()
    mm = build_mesh(machine, 0.03)   # 14 slabs of 28.6 mm: nodes and slab faces do not coincide
    cells = mm.cells_of("rod")
    y = mm.mesh.p[1, mm.mesh.t[:, cells]].mean(axis=0)
    for moves, exact in (([{"kind": "hold", "position": "137 mm", "duration": "80 s"}],
                          source_pattern(mm, HeatSource("slab", cells[np.abs(y - 0.1286) < 0.0143], None))),
                         ([{"kind": "table", "times": ["0 s", "80 s"], "positions": ["0 mm", "400 mm"]}],
                          source_pattern(mm, HeatSource("all", cells, None)))):
        sc = scenario(moves, duration="80 s", dt="80 s")
        errors = []
        for h in (0.1, 0.05, 0.025, 0.0125, 0.003125):
            srcs = travelling_sources("nut", mm, "feed_drive.y.screw", machine.axes[0], sc.axes[0], sc, 1.0, "time",
                                      spacing=h)
            share = sum(s.power(np.array([40.0]))[0] * source_pattern(mm, s) for s in srcs)
            errors.append(np.abs(share - exact).sum())
        if moves[0]["kind"] == "hold":
            assert all(b < a for a, b in zip(errors[:-1], errors[1:-1])) and errors[0] > 0.3
            assert errors[-1] < 1e-12
        else:
            assert max(errors) < 1e-10   # round-off of (Phi(x_b) - Phi(x_a)) / v


def test_seed003_at_60_s_steps_reads_the_slope_of_10_s_steps():
    """The path basis's step averages lose nothing of a stroke shorter than the step: the seed 003
    Y axis (16 s strokes) run at 60 s steps gives the interferometer's slope change k - k0 of the
    same run at 10 s steps within 0.1 % at every run (measured 0.03 % on the coarse mesh), and
    the same drift at the shared instants within 0.1 % of its peak (measured 0.02 %)."""
    from dataclasses import replace

    from twin.api import simulate
    from twin.scenario import load_scenario

    sc = load_scenario("seed003-exp1")
    runs = {dt: simulate("cframe-vmc", replace(sc, sample_interval=dt), resolution="coarse")[0] for dt in (60.0, 10.0)}
    k60, k10 = (runs[dt].positioning_slope.values for dt in (60.0, 10.0))
    np.testing.assert_allclose(k60[1:] - k60[0], k10[1:] - k10[0], rtol=1e-3)
    drift60, drift10 = runs[60.0].drift.values, runs[10.0].drift.values[::6]
    assert np.max(np.abs(drift60 - drift10)) <= 1e-3 * np.max(np.abs(drift10))


def test_path_nodes_are_no_further_apart_than_the_spacing():
    """path_nodes(lo, hi, h): n = ceil((hi - lo) / h) equal intervals: 0.25 m at 0.1 m is 3
    intervals of 0.0833 m (4 nodes), never 2 of 0.125 m; an exact multiple keeps its count."""
    nodes = path_nodes(0.0, 0.25, 0.1)
    assert len(nodes) == 4 and np.max(np.diff(nodes)) == pytest.approx(0.25 / 3, rel=1e-12)
    assert len(path_nodes(0.0, 0.3, 0.1)) == 4

