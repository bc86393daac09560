"""The gantry's linear axes and its Z ball-screw drive on the ram (issue 13): the drive's heat
against closed forms, the nut running the other way along a screw that rides on the ram, and the
seed's Z-axis and helical tests on the coarse mesh.

Bands (README "The gantry with a ram", `python -m validate.studies.gantry_tests`): the helical
test's peak |Z| 65-125 um (seed: about 95 um). The Z-axis test does not reach the seed's over
100 um (README says why); what is tested of it here is what the model claims: where its heat goes,
that the path basis delivers it exactly at 60 s steps, and that the tool moves towards the table.
"""

from __future__ import annotations

import numpy as np
import pytest

from geometries import build_machine
from geometries.gantry_ram import Z_DRIVE_DEFAULTS, Z_DRIVE_EFFECTS
from twin.effects.base import EFFECTS, HeatSource
from twin.effects.moving import REFERENCE_ACCELERATION, REFERENCE_FEED, travelling_sources
from twin.fem.mesh import mesh_machine
from twin.model import default_spec, model_spec
from twin.motion import machine_for, stroke_time
from twin.physics.loads import source_pattern
from twin.scenario import load_scenario, scenario_from_dict
from twin.simulate import run
from validate.studies.gantry_tests import early_slope, lag_minutes

FEED, ACCEL, DWELL, STROKE = 70.0 / 60.0, 3.0, 1.0, 0.7   # the scenario's 70 m/min, 3 m/s2, 1 s, 0.7 m


def inertia_heat(inertia_power: float, strokes: int) -> float:
    """The Z motor's inertia losses [J] over whole strokes, closed form: P_a n 2 a v / a_ref^2
    (each stroke's integral of a^2 is two ramps of v / a at a)."""
    return inertia_power * strokes * 2 * ACCEL * FEED / REFERENCE_ACCELERATION ** 2


@pytest.fixture(scope="module")
def z_test():
    """gantry-z-axis: the machine with its Z drive and the coarse mesh."""
    sc = load_scenario("gantry-z-axis")
    machine = machine_for(build_machine("gantry-ram"), sc)
    return machine, mesh_machine(machine, "coarse"), sc


@pytest.fixture(scope="module")
def z_run(z_test):
    machine, mm, sc = z_test
    return run(machine, sc, default_spec(machine), mm=mm)


def test_the_gantry_declares_x_y_z_closed_loop_and_the_z_drive_on_the_ram(z_test):
    """X 2.5, Y 1.2, Z 0.7 m, linear scales on all three (seed 000); only Z has a drive, whose
    screw rides on the ram; its four feed effects join the defaults only when a scenario moves Z,
    at the machine's own powers (a --set wins)."""
    base = build_machine("gantry-ram")
    assert [(a.name, a.direction, a.travel, a.feedback) for a in base.axes] == [
        ("X", "x", (0.0, 2.5), "closed"), ("Y", "y", (0.0, 1.2), "closed"), ("Z", "z", (0.0, 0.7), "closed")]
    assert [a.drive is not None for a in base.axes] == [False, False, True] and base.axis("Z").screw_on_body
    c_test = machine_for(base, load_scenario("gantry-c-axis"))
    assert c_test is base and not set(Z_DRIVE_EFFECTS) & set(c_test.default_effects)
    machine = z_test[0]
    assert set(Z_DRIVE_EFFECTS) <= set(machine.default_effects) and "feed_screw_gap_z" not in machine.default_effects
    assert all(EFFECTS[e].applies_to(machine) for e in Z_DRIVE_EFFECTS)
    spec = default_spec(machine)
    for effect, values in Z_DRIVE_DEFAULTS.items():
        assert {k: spec.params[effect][k] for k in values} == values
    assert model_spec(machine, settings=["feed_nut_z.power=9W"]).params["feed_nut_z"]["power"] == 9.0
    from geometries.base import Machine
    for bad in ({"feed_nut_z": {"power": 1e6}}, {"feed_nut_z": {"torque": 1.0}}):
        with pytest.raises(ValueError, match="effect_defaults feed_nut_z"):
            default_spec(Machine(**{**machine.__dict__, "effect_defaults": bad}))
    cframe_z = scenario_from_dict({"sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
                                   "spindle": [{"speed": "0 rpm", "duration": "5 min"}],
                                   "axis": [{"name": "Z", "move": [{"kind": "hold", "position": "0 mm",
                                                                    "duration": "5 min"}]}]}, "z.toml")
    cframe = default_spec(machine_for(build_machine("cframe-vmc"), cframe_z))   # the registry's powers there
    assert cframe.params["feed_nut_z"] == EFFECTS["feed_nut_z"].defaults()


def test_twin_list_effects_shows_the_machines_own_powers(capsys):
    """`twin list effects --machine gantry-ram` prints the Z drive at the gantry's powers."""
    from twin.cli import main
    assert main(["list", "effects", "--machine", "gantry-ram"]) == 0
    out = capsys.readouterr().out
    block = out.split("feed_nut_z (", 1)[1].split("\nfeed_", 1)[0]
    assert f"power = {Z_DRIVE_DEFAULTS['feed_nut_z']['power']:g} W" in block


def test_a_screw_on_the_ram_meets_its_fixed_nut_the_other_way(z_test):
    """The nut stands in the carriage, so in the mesh (the ram at p_ref) the screw point under it
    is s(p) = s_0 - (p - p_ref): with the ram at its lowest (Z 0) the nut is near the screw's top,
    at Z 700 mm near its bottom. A nut holding there heats exactly that slab of the screw (as the
    C-frame's standing nut, tests/test_feed_drive.py), to round-off."""
    machine, mm, _ = z_test
    axis = machine.axis("Z")
    np.testing.assert_allclose(axis.nut_coordinate(np.array([0.0, 0.15, 0.7])), axis.nut_at_zero - np.array(
        [-0.15, 0.0, 0.55]), rtol=0, atol=1e-15)
    cells = mm.cells_of("z_screw")
    z = mm.mesh.p[2, mm.mesh.t[:, cells]]
    for p in (0.0, 0.7):
        sc = scenario_from_dict({"sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
                                 "spindle": [{"speed": "0 rpm", "duration": "5 min"}],
                                 "axis": [{"name": "Z", "move": [{"kind": "hold", "position": f"{p * 1e3:g} mm",
                                                                  "duration": "5 min"}]}]}, "hold.toml")
        srcs = travelling_sources("nut", mm, "feed_drive.z.screw", axis, sc.axes[0], sc, 3.0, "time")
        t = sc.times()[1:]
        moving = sum(np.outer(s.power(t), source_pattern(mm, s)) for s in srcs)
        s = axis.nut_coordinate(p)
        slab = cells[(z.min(axis=0) < s) & (z.max(axis=0) > s)]
        still = HeatSource("still", slab, lambda t: np.full(np.shape(t), 3.0))
        assert np.abs(moving - np.outer(still.power(t), source_pattern(mm, still))).max() < 1e-12


def test_the_z_drive_delivers_its_power_times_the_distance_at_60_s_steps(z_test):
    """Energy balance of the Z-axis test, 0.6 s strokes on 60 s steps: each feed effect delivers
    E = P_ref d / v_ref, d = n x 0.7 m, n = floor(2 h / (stroke_time + dwell)) whole strokes
    (exact); and every step's energy is P_ref / v_ref times that step's travelled distance, the
    integral of |v| (the trapezoid's closed form per piece, checked by 1 ms midpoint sums, 1e-6).
    The motor's inertia losses deliver P_a n 2 a v / a_ref^2 (each stroke's two ramps of v / a)."""
    machine, mm, sc = z_test
    period = stroke_time(STROKE, FEED, ACCEL) + DWELL
    n = int(np.floor(7200.0 / period + 1e-9))
    t, dt = sc.times(), sc.sample_interval
    spec = default_spec(machine)
    motion = sc.axes[0]
    fine = np.arange(0.0, t[-1], 1e-3) + 5e-4
    per_step = np.add.reduceat(np.abs(motion.velocity(fine)) * 1e-3, np.searchsorted(fine, t[:-1]))
    for name in Z_DRIVE_EFFECTS:
        p = spec.params[name]
        loads = EFFECTS[name].loads(mm, sc, p)
        inertia = [s for s in loads if s.label.endswith(".inertia")]
        steps = sum(s.power(t[:-1] + 0.5 * dt) for s in loads if s not in inertia) * dt
        assert steps.sum() == pytest.approx(p["power"] * n * STROKE / REFERENCE_FEED, rel=1e-12)
        np.testing.assert_allclose(steps, p["power"] / REFERENCE_FEED * per_step, rtol=0,
                                   atol=1e-6 * steps.max())
        if inertia:
            e = sum(np.sum(s.power(t[:-1] + 0.5 * dt)) * dt for s in inertia)
            assert p["inertia_power"] > 0
            assert e == pytest.approx(inertia_heat(p["inertia_power"], n), rel=1e-12)


def test_z_axis_test_heats_the_drive_and_moves_the_tool_towards_the_table(z_run):
    """What the model claims of the seed's Z-axis test: T2 (the screw's lower bearing, a source
    here) warms most of the ram's sensors T1..T4, the Z motor (T5, T6) warms, the tool moves down
    (Z < 0), and all of it stops growing at the end of the 2 h of motion."""
    names = [p.name for p in z_run.sensors]
    rise = dict(zip(names, (z_run.sensor_true - z_run.sensor_true[0]).max(axis=0)))
    assert rise["T2"] > max(rise["T1"], rise["T3"], rise["T4"]) and rise["T2"] > 1.0
    assert rise["T5"] > 1.0 and rise["T6"] > 1.0
    z = z_run.drift[:, 2]
    assert z.min() < 0 and abs(z.min()) == np.abs(z).max()
    assert z_run.times[np.argmin(z)] == pytest.approx(7200.0, abs=120.0)
    # the study's row reads the same run (python -m validate.studies.gantry_tests)
    from twin.io.results import to_dataset
    from validate.studies.gantry_tests import markdown, summary
    row = summary(to_dataset(z_run), "gantry-z-axis")
    assert row["peak_z"] == pytest.approx(z.min() * 1e6, rel=1e-12) and row["rise_T2"] == pytest.approx(rise["T2"])
    assert "over 100 um" in markdown([row], "cmd", "coarse")


def test_time_step_does_not_change_the_z_axis_test(z_test, z_run):
    """The path basis's exact per-step energy: 20 s steps give the 60 s steps' peak Z and X within 0.5 %."""
    from dataclasses import replace
    machine, mm, sc = z_test
    fine = run(machine, replace(sc, sample_interval=20.0), default_spec(machine), mm=mm)
    for k in (0, 2):
        a, b = np.abs(z_run.drift[:, k]).max(), np.abs(fine.drift[:, k]).max()
        assert b == pytest.approx(a, rel=5e-3)


def test_helical_test_lies_in_the_seeds_band():
    """gantry-helical (C at 2500 rpm, 10 s on / 10 s off, with the ram's Z strokes, 2 h / 2 h):
    peak |Z| 65-125 um (seed: about 95 um), the tool towards the table."""
    sc = load_scenario("gantry-helical")
    machine = machine_for(build_machine("gantry-ram"), sc)
    r = run(machine, sc, default_spec(machine), resolution="coarse")
    z = r.drift[:, 2] * 1e6
    assert 65.0 <= np.abs(z).max() <= 125.0 and z.min() < 0


def test_lag_and_early_slope_read_their_closed_forms():
    """lag_minutes of a copy delayed by k samples is k x step (either sign); early_slope of
    z = -2.7 T is -2.7 (exact), and undefined for a sensor that has not warmed."""
    t = np.arange(0.0, 4 * 3600.0 + 1, 60.0)
    lead = np.where(t < 7200, 1 - np.exp(-t / 1800), (1 - np.exp(-4)) * np.exp(-(t - 7200) / 1800))
    for k in (0, 10, 25):
        follower = np.concatenate([np.zeros(k), lead[:len(lead) - k]])
        assert lag_minutes(lead, follower, 60.0) == k
        assert lag_minutes(follower, lead, 60.0) == -k
    temp = 0.01 * t[:30]
    assert early_slope(-2.7 * temp, temp, t[:30]) == pytest.approx(-2.7, rel=1e-12)
    assert np.isnan(early_slope(-2.7 * temp, 1e-3 * temp, t[:30]))   # 0.006 K in 10 min: no slope


def test_holding_loss_is_the_torque_that_stops_the_load_back_driving_the_screw():
    """A vertical axis without counterbalance, at rest: the load may only not back-drive the screw.
    Screw as a wedge of lead angle beta, tan beta = l / (pi d), and friction angle rho: forward
    eta = tan beta / tan(beta + rho), backward eta' = tan(beta - rho) / tan beta, and the back-driving
    power balance M omega = eta' m g v, v = l omega / (2 pi), gives M = m g l eta' / (2 pi); the
    copper losses P = (M / k_t)^2 R (1.1 t, 20 mm lead on a 50 mm screw, eta 0.9, k_t 2 N m/A,
    R 1.05 ohm: 244 W). The study's eta' = 2 - 1/eta is the small-rho form of the wedge's (9e-4 of P here)."""
    from validate.studies.gantry_z_variants import G, HOLD, holding_loss
    beta = np.arctan(HOLD["lead"] / (np.pi * 0.050))
    rho = np.arctan(np.tan(beta) / HOLD["efficiency"]) - beta
    eta_back = np.tan(beta - rho) / np.tan(beta)
    omega = 123.0                                              # any speed: the balance fixes M
    torque = eta_back * HOLD["mass"] * G * (HOLD["lead"] * omega / (2 * np.pi)) / omega
    expect = (torque / HOLD["torque_constant"]) ** 2 * HOLD["resistance"]
    assert holding_loss(**HOLD) == pytest.approx(expect, rel=2e-3) and 235.0 < expect < 255.0
    assert holding_loss(**{**HOLD, "mass": 2 * HOLD["mass"]}) == pytest.approx(4 * holding_loss(**HOLD), rel=1e-12)


def test_z_drive_variants_build_as_declared():
    """The variants of validate.studies.gantry_z_variants: the defaults are the registered machine;
    a moved nut moves the Z axis's nut and the screw point under it; the lower bearing and T2 move
    together; a screw at x 0.16 touches the ram's rear face."""
    from geometries.gantry_ram import build
    from validate.studies.gantry_z_variants import variants
    base = build_machine("gantry-ram")
    assert [(p.name, p.boxes) for p in build().parts] == [(p.name, p.boxes) for p in base.parts]
    assert build().axis("Z").nut_at_zero == base.axis("Z").nut_at_zero == pytest.approx(2.95)
    low = build(**variants()[3]["build"])
    assert low.axis("Z").nut_at_zero == pytest.approx(2.55)
    bearing = next(p for p in low.parts if p.name == "z_bearing_lower").boxes[0]
    t2 = next(p for p in low.points if p.name == "T2").xyz
    assert bearing.lo[2] < t2[2] < bearing.hi[2] == pytest.approx(1.92)
    touching = build(**variants()[4]["build"])
    assert next(p for p in touching.parts if p.name == "z_screw").boxes[0].lo[0] == pytest.approx(0.16)


def test_variant_study_row_reads_the_z_axis_test(z_test, z_run):
    """validate.studies.gantry_z_variants, as built, coarse: the same peak Z as the Z-axis test's
    run (its extra ram sites read, they do not heat), and the mean drive power over the heating is
    the drive's energy in closed form, (sum P_ref x n x 0.7 m / v_ref + P_a n 2 a v / a_ref^2) over
    2 h (1e-9)."""
    from validate.studies.gantry_z_variants import markdown, row, variants
    r = row(variants()[0], "coarse")
    assert r["peak_z"] == pytest.approx(z_run.drift[:, 2].min() * 1e6, rel=1e-9)
    n = int(np.floor(7200.0 / (stroke_time(STROKE, FEED, ACCEL) + DWELL) + 1e-9))
    spec = default_spec(z_test[0])
    expect = (sum(spec.params[e]["power"] for e in Z_DRIVE_EFFECTS) * n * STROKE / REFERENCE_FEED
              + inertia_heat(spec.params["feed_motor_z"]["inertia_power"], n)) / 7200.0
    assert r["drive_w"] == pytest.approx(expect, rel=1e-9)
    assert r["w_for_100um"] == pytest.approx(expect * 100.0 / abs(r["peak_z"]), rel=1e-12)
    assert "as built" in markdown([r], "cmd", "coarse")


def test_twin_list_effects_says_which_axis_brings_a_drive_effect(capsys):
    """A feed-drive effect is on by default only when a scenario moves the axis whose drive
    brings it: `twin list effects` names that axis (z_axis_holding joins with the Z drive)."""
    from twin.cli import main
    assert main(["list", "effects", "--machine", "cframe-vmc"]) == 0
    out = capsys.readouterr().out
    assert "z_axis_holding (default when a scenario moves its Z axis)" in out
    assert "feed_nut_y (default when a scenario moves its Y axis)" in out
