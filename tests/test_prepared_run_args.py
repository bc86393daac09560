"""A prepared twin's runs and the objects a Python user puts into a scenario, checked before any
step (API audit): observers, specs and batch cases of the wrong kind, a spec beyond its bounds
or naming an effect twice, a custom effect of another machine, axis moves that jump, overspeed or
leave the travel inside a piece, C-axis steps with an impossible duty, probing and interferometer
instants that do not start at 0 s (their readings' slots were left unfilled: garbage in the
result), and room-air events whose extremes are checked where they happen."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from geometries import build_machine
from twin.ambient import AirEvent, Ambient, check_ambient
from twin.errors import InputError
from twin.model import ModelSpec, default_spec
from twin.motion import Motion
from twin.motion_checks import check_pieces
from twin.observe import ToolDrift
from twin.observe.interferometer import InterferometerConfig
from twin.observe.probing import ProbingConfig
from twin.physics.prepared import PreparedTwin
from twin.rotary import RotarySchedule
from twin.scenario import Scenario

SHORT = Scenario("short", ((600.0, 8000.0),), Ambient("constant", mean=20.0), 60.0)
CFRAME = build_machine("cframe-vmc")


@pytest.fixture(scope="module")
def twin():
    return PreparedTwin(CFRAME, resolution="coarse", solver="direct")


@pytest.fixture
def no_steps(monkeypatch, twin):
    """Fail the test if the loads are built: every check must come first."""
    def refuse(*args, **kwargs):
        raise AssertionError("the run started before its arguments were checked")
    monkeypatch.setattr(twin, "loads", refuse)


def refused(field: str, call, *args, **kwargs) -> InputError:
    with pytest.raises(InputError) as err:
        call(*args, **kwargs)
    assert err.value.field.startswith(field), str(err.value)
    return err.value


SPEC = default_spec(CFRAME)
BAD_RUNS = [
    ("observers-none", {"observers": None}, "observers"),
    ("observers-a-text", {"observers": "temperature"}, "observers"),
    ("observer-a-text", {"observers": ["temperature"]}, "observers[0]"),
    ("observers-twice", {"observers": [ToolDrift(), ToolDrift()]}, "observers"),
    ("spec-none", {"spec": None}, "spec"),
    ("spec-negative-power", {"spec": ModelSpec(SPEC.effects, {"spindle_bearings": {"front_power": -500.0}})},
     "spec spindle_bearings.front_power"),
    ("spec-negative-film", {"spec": ModelSpec(SPEC.effects, {"ambient_convection": {"h": -10.0}})},
     "spec ambient_convection.h"),
    ("spec-probe-noise", {"spec": ModelSpec(SPEC.effects, {"probe": {"noise": 1.0}})}, "spec probe.noise"),
    ("spec-of-another-machine", {"spec": ModelSpec(("belt_drive",))}, "--effects belt_drive"),
]


@pytest.mark.parametrize("case, change, field", BAD_RUNS, ids=[c for c, _, _ in BAD_RUNS])
def test_a_run_names_a_bad_argument_before_it_starts(twin, no_steps, case, change, field):
    args = {"scenario": SHORT, "spec": SPEC, "observers": [ToolDrift()], **change}
    refused(field, twin.run, args["scenario"], args["spec"], args["observers"])


def test_a_batch_names_bad_cases_and_observers(twin, no_steps):
    for cases, field in (([], "cases"), ("x", "cases"), ([SHORT], "cases[0]"), ([(SHORT, None)], "spec")):
        refused(field, twin.run_batch, cases, [ToolDrift()])
    refused("observers[0]", twin.run_batch, [(SHORT, SPEC)], ["drift"])


def test_a_spec_names_each_effect_once_and_a_study_may_go_beyond_the_bounds(twin):
    refused("--effects spindle_bearings", ModelSpec, ("spindle_bearings", "spindle_bearings"))
    refused("--effects", ModelSpec, "spindle_bearings")
    refused("--set", ModelSpec, ("ambient_convection",), {"ambient_convection": 5.0})
    beyond = ModelSpec(("ambient_convection",), {"ambient_convection": {"h": 0.0}})   # below its 0.5 W/m2K bound
    loads, raw = twin.run(SHORT, beyond, [ToolDrift()], plausible=False)
    assert np.all(np.isfinite(raw["drift"]))


def test_a_motion_built_in_python_moves_as_a_planned_one():
    """Each piece ends where the next starts, within the speed and acceleration limits; the travel
    is checked at the turning points inside pieces too (0.1 -> 1.1 m passed on a 0-0.4 m axis)."""
    ok = Motion("Y", [0.0, 100.0], [50.0, 50.0], [0.1, 0.2], [0.002, -0.002], [0.0, 0.0], 0.1)
    assert np.allclose(sorted(check_pieces(ok, "s", "axis[0]")), [0.1, 0.1, 0.2])
    turn = Motion("Y", [0.0], [20.0], [0.1], [0.02], [-0.002], 0.1)      # out and back: turns at 0.2 m
    assert check_pieces(turn, "s", "axis[0]").max() == pytest.approx(0.2)
    for bad in (Motion("Y", [0.0], [100.0], [0.1], [0.01], [0.0], 0.3),      # a jump into x_end
                Motion("Y", [0.0], [100.0], [0.1], [50.0], [0.0], 5000.1),    # 50 m/s
                Motion("Y", [0.0], [-100.0], [0.1], [0.0], [0.0], 0.1),       # a negative duration
                Motion("Y", [0.0, 1.0], [100.0], [0.1], [0.0], [0.0], 0.1),   # ragged pieces
                Motion("Y", [0.0], [100.0], [np.nan], [0.0], [0.0], 0.1)):
        refused("axis[0]", check_pieces, bad, "s", "axis[0]")
    # a half-millimetre jump between pieces (0.1 -> 0.2 m, then on from 0.2005 m) is a jump too
    step = Motion("Y", [0.0, 100.0], [50.0, 50.0], [0.1, 0.2005], [0.002, -0.002], [0.0, 0.0], 0.1005)
    assert "jumps by 0.5 mm after piece 0" in str(refused("axis[0]", check_pieces, step, "s", "axis[0]"))


def test_a_c_axis_schedule_built_in_python_has_a_duty_from_0_to_1():
    gantry = replace(SHORT, steps=((600.0, 1000.0),))
    for steps, field in ((((600.0, 1000.0, 2.0),), "c_axis[0].duty"), (((600.0, 1000.0, -1.0),), "c_axis[0].duty"),
                         (((600.0, 1000.0, np.nan),), "c_axis[0].duty"), (((-600.0, 1000.0, 1.0),), "c_axis[0].duration"),
                         (((600.0, 1000.0),), "c_axis[0]"), ((), "c_axis")):
        refused(field, replace(gantry, c_axis=RotarySchedule(steps)).check)


def test_a_motion_built_in_python_has_positive_pieces_in_order_without_overlap():
    """``check_pieces``: positive durations, from 0 s on, in order without overlap (its
    docstring): a piece of 0 s, or a second piece starting at 50 s inside a first one of 100 s
    (each continuous with the one before, so only the timing is wrong) is refused; the same pieces
    one after the other are taken."""
    zero = Motion("Y", [0.0, 0.0], [0.0, 100.0], [0.1, 0.1], [0.0, 0.0], [0.0, 0.0], 0.1)
    overlap = Motion("Y", [0.0, 50.0], [100.0, 100.0], [0.1, 0.1], [0.0, 0.0], [0.0, 0.0], 0.1)
    for bad in (zero, overlap):
        err = refused("axis[0]", check_pieces, bad, "s", "axis[0]")
        assert "positive durations" in str(err)
    check_pieces(Motion("Y", [0.0, 100.0], [100.0, 100.0], [0.1, 0.1], [0.0, 0.0], [0.0, 0.0], 0.1), "s", "axis[0]")


def test_a_motion_built_in_python_is_within_the_feed_limit_at_each_pieces_end_too():
    """A piece's speed is checked at both ends, |v0| and |v0 + a dur| (``check_pieces``, within
    MAX_FEED = 2 m/s): from rest at 0.03 m/s2 for 100 s the axis reaches 3 m/s (and 150 m), which
    is refused though it starts at 0 and accelerates gently; for 60 s (1.8 m/s) it is taken."""
    fast = Motion("Y", [0.0], [100.0], [0.0], [0.0], [0.03], 150.0)
    err = refused("axis[0]", check_pieces, fast, "s", "axis[0]")
    assert "3 m/s" in str(err)
    check_pieces(Motion("Y", [0.0], [60.0], [0.0], [0.0], [0.03], 54.0), "s", "axis[0]")


def test_an_axis_commanded_twice_in_python_is_refused():
    """One command per axis (``check_motions``; the loader refuses a second ``[[axis]]`` of one
    name, and a scenario built in Python meets the same rule): two motions of Y are refused
    naming the axis."""
    from twin.motion_checks import check_motions

    m = Motion("Y", [0.0], [600.0], [0.1], [0.0], [0.0], 0.1)
    check_motions(replace(SHORT, axes=(m,)), CFRAME)
    err = refused("axis", check_motions, replace(SHORT, axes=(m, m)), CFRAME)
    assert "commanded twice" in str(err)


def test_a_c_axis_schedule_is_at_rest_after_its_last_step():
    """``RotarySchedule.speed`` / ``duty``: piecewise constant, each step on [start, end), and 0
    after the last step (the C axis is at rest; ``twin.rotary``), not the last step held on."""
    s = RotarySchedule(((600.0, 2500.0, 0.5), (600.0, 1000.0, 1.0)))
    t = np.array([0.0, 599.0, 600.0, 1199.0, 1200.0, 1e5])
    assert s.speed(t).tolist() == [2500.0, 2500.0, 1000.0, 1000.0, 0.0, 0.0]
    assert s.duty(t).tolist() == [0.5, 0.5, 1.0, 1.0, 0.0, 0.0]


def _c_axis(step: dict, run: str = "10 min"):
    from twin.scenario import scenario_from_dict
    return scenario_from_dict({"name": "s", "sample_interval": "10 s", "ambient": {"temperature": "20 degC"},
                               "spindle": [{"speed": "0 rpm", "duration": run}], "c_axis": [step]}, "s.toml")


def test_a_c_axis_rhythm_turns_for_its_duty_on_over_on_plus_dwell():
    """A ``[[c_axis]]`` on/dwell rhythm enters as its duty d = on / (on + dwell) (``twin.rotary``):
    on 10 s, dwell 30 s turns a quarter of the time; a dwell of 0 s is allowed (not negative) and
    turns throughout, d = 1, as a step without a rhythm does."""
    step = {"speed": "2500 rpm", "duration": "10 min"}
    assert _c_axis({**step, "on": "10 s", "dwell": "30 s"}).c_axis.steps == ((600.0, 2500.0, 0.25),)
    assert _c_axis({**step, "on": "10 s", "dwell": "0 s"}).c_axis.steps == ((600.0, 2500.0, 1.0),)
    assert _c_axis(step).c_axis.steps == ((600.0, 2500.0, 1.0),)


def test_a_c_axis_schedule_may_not_outlast_the_run():
    """The C-axis steps may not outlast the ``[[spindle]]`` steps (``twin.rotary.check_duration``),
    by however little: 11 min on a 10 min run is refused naming ``c_axis``, before any machine is
    asked; 10 min is taken."""
    with pytest.raises(InputError) as err:
        _c_axis({"speed": "2500 rpm", "duration": "11 min"})
    assert err.value.field == "c_axis" and "longer than the run" in str(err.value)
    assert _c_axis({"speed": "2500 rpm", "duration": "10 min"}).c_axis.duration == 600.0


def test_a_c_axis_schedule_built_in_python_has_positive_durations_and_no_negative_speed():
    """``check_schedule`` (``Scenario.check``): each step's duration > 0 and speed >= 0, however
    small the offence (a -0.5 rpm step, a step of 0 s), naming the step's key."""
    gantry = replace(SHORT, steps=((600.0, 1000.0),))
    for steps, field in ((((600.0, -0.5, 1.0),), "c_axis[0].speed"),
                         (((0.0, 1000.0, 1.0), (600.0, 1000.0, 1.0)), "c_axis[0].duration")):
        refused(field, replace(gantry, c_axis=RotarySchedule(steps)).check)
    replace(gantry, c_axis=RotarySchedule(((600.0, 0.0, 0.0),))).check()


def test_probing_and_interferometer_instants_start_at_zero_and_increase():
    """A negative or late first instant left the readings' first slot unfilled: the result held
    uninitialised memory (-40834 um) without an error."""
    from twin.observe.instants import check_on_grid
    for times in ((0.0, -60.0), (300.0, 600.0), (0.0, np.nan), (0.0, 60.0, 60.0), ()):
        refused("probing.times", check_on_grid, times, SHORT, "s", "probing.times")
    check_on_grid((0.0, 300.0, 600.0), SHORT, "s", "probing.times")
    # on the sample grid but after the run's end (600 s): no output instant holds it
    for late in ((0.0, 660.0), (0.0, 600.0, 1200.0)):
        refused("probing.times", check_on_grid, late, SHORT, "s", "probing.times")
    refused("probing.times", check_on_grid, (0.0, 330.0), SHORT, "s", "probing.times")   # between samples
    assert ProbingConfig((0.0, 60.0), ((0.1, 0.1, 0.1),)).times == (0.0, 60.0)
    assert InterferometerConfig("Y", (0.0, 60.0), spacing=0.01).spacing == 0.01


def test_separate_air_events_are_not_added_up_but_overlapping_ones_are():
    cold = lambda start, hold: AirEvent(start, -35.0, 1.0, hold, 60.0)
    check_ambient(Ambient("constant", mean=20.0, events=(cold(0.0, 0.0), cold(300.0, 0.0))), "s")
    refused("ambient.events", check_ambient, Ambient("constant", mean=20.0, events=(cold(0.0, 100.0), cold(50.0, 0.0))),
            "s")


def test_a_run_needs_the_feed_drives_of_the_axes_it_moves_and_its_machines_custom_effects(twin, no_steps, tmp_path):
    """A scenario moving Y on a twin prepared without the Y drive ran with the axis ignored; a
    custom effect read for the C-frame ran on another machine's part of the same name."""
    from tests.fuzz_files import EFFECTS_FILE
    from twin.effects.custom import load_effects_file
    from twin.model import check_applicable
    from twin.scenario import load_scenario

    moving = replace(load_scenario("seed003-exp1"), interferometer=None)
    refused("axis", twin.run, moving, SPEC, [ToolDrift()])
    (tmp_path / "fx.toml").write_text(EFFECTS_FILE)
    (name,) = load_effects_file(tmp_path / "fx.toml", CFRAME)
    check_applicable((name,), CFRAME)
    refused(f"--effects {name}", check_applicable, (name,), build_machine("belt-vmc"))


def test_a_field_and_a_plot_from_python_check_what_they_are_given(twin, tmp_path):
    """A field of 10 values for thousands of nodes wrote a corrupt XDMF, an all-NaN field and a
    NaN time were written, a folder given as the plot's path wrote ``out/.png``."""
    from tests.fuzz_files import result_dataset
    from twin.io.fields import save_temperature_field
    from twin.plotting import plot_result

    mm = twin.mm
    good = np.full(mm.nheat, 20.0)
    for field, time_s, name in ((good[:10], 600.0, "a.xdmf"), (np.full(mm.nheat, np.nan), 600.0, "b.vtu"),
                                (good, float("nan"), "c.vtu"), (good, "600 s", "d.vtu"), (None, 600.0, "e.vtu"),
                                (good, 600.0, "f.txt")):
        refused("--field", save_temperature_field, mm, field, tmp_path / name, time_s)
    assert list(tmp_path.iterdir()) == []
    assert [p.name for p in save_temperature_field(mm, good, tmp_path / "ok.vtu", 600.0)] == ["ok.vtu"]
    (tmp_path / "out").mkdir()
    refused("path", plot_result, result_dataset(), tmp_path / "out")
    refused("result", plot_result, None, tmp_path / "p.png")
    refused("drift", plot_result, result_dataset().drop_vars("drift"), tmp_path / "p.png")
    assert not (tmp_path / "p.png").exists() and list((tmp_path / "out").iterdir()) == []


def test_effects_files_and_model_specs_take_a_built_machine(tmp_path):
    """``load_effects_file(path, "cframe-vmc")`` and ``model_spec("cframe-vmc")`` failed with an
    AttributeError deep in the region code; ``extra="floor"`` was read letter by letter."""
    from tests.fuzz_files import EFFECTS_FILE
    from twin.effects.custom import load_effects_file
    from twin.model import model_spec

    (tmp_path / "fx.toml").write_text(EFFECTS_FILE)
    for call, field in ((lambda: load_effects_file(tmp_path / "fx.toml", "cframe-vmc"), "machine"),
                        (lambda: load_effects_file(tmp_path / "fx.toml", None), "machine"),
                        (lambda: load_effects_file(None, CFRAME), "--effects-file"),
                        (lambda: model_spec("cframe-vmc"), "machine"), (lambda: model_spec(None), "machine"),
                        (lambda: model_spec(CFRAME, None, None, "floor"), "--effects-file"),
                        (lambda: model_spec(CFRAME, None, None, ("nosuch",)), "--effects-file")):
        with pytest.raises(InputError) as err:
            call()
        assert err.value.field == field, str(err.value)


def test_temperature_sensors_built_in_python_are_checked_on_their_twins_machine(twin):
    """``TemperatureSensors(["T1"])`` failed with an AttributeError, a wrong part, a name given twice
    and an air sensor 100 m away were accepted."""
    from geometries.base import Point
    from twin.observe.temperature import TemperatureSensors

    motor = CFRAME.point("motor")
    for points, field in (("T1", "points"), (["T1"], "points[0]"), ([Point("a", (0.0, 1.0), "motor")], "points[0] a"),
                          ([Point("a", motor.xyz, "nosuch")], "points[0] a"),
                          ([Point("a", motor.xyz, motor.part), Point("a", motor.xyz, motor.part)], "points[1] a"),
                          ([Point("a", (0.0, 0.0, 100.0), "air")], "points[0] a")):
        refused(field, lambda: TemperatureSensors(points).rows(twin, SimpleLoads(twin.mm)))


class SimpleLoads:
    def __init__(self, mm):
        self.mm = mm


def test_an_ambient_field_its_kind_does_not_read_is_refused_not_ignored():
    check_ambient(Ambient("daily", mean=20.0, amplitude=2.0), "s")
    for air, field in ((Ambient("constant", 20.0, amplitude=5.0), "ambient.amplitude"),
                       (Ambient("constant", 20.0, times=(0.0, 60.0), temperatures=(20.0, 21.0)), "ambient.times"),
                       (Ambient("table", mean=25.0, times=(0.0, 600.0), temperatures=(20.0, 21.0)), "ambient.mean"),
                       (Ambient("daily", mean=20.0, amplitude=2.0, file="room.csv"), "ambient.file")):
        refused(field, check_ambient, air, "s")


def test_a_batch_of_other_grids_a_renamed_material_and_a_sensitivity_of_nothing_are_named(twin):
    from geometries.materials import MATERIALS
    from twin.observe.displacement import ExpansionSensitivity

    longer = replace(SHORT, steps=((1200.0, 8000.0),))
    refused("cases[1]", twin.run_batch, [(SHORT, SPEC), (longer, SPEC)], [ToolDrift()])
    refused("materials['grey_cast_iron']", PreparedTwin, CFRAME, resolution="coarse",
            materials={"grey_cast_iron": replace(MATERIALS["grey_cast_iron"], name="granite")})
    refused("material", twin.run, SHORT, SPEC, [ExpansionSensitivity("unobtainium", ToolDrift())])
    refused("of", ExpansionSensitivity, "steel", "drift")


def test_instruments_a_machine_lacks_or_gauges_off_their_part_are_named(twin):
    """``LaserTriangulation()`` on the C-frame (no lasers) and ``StrainGauges([])`` failed with
    scipy's 'blocks must be 2-D'; a gauge on a part the machine lacks was accepted."""
    from geometries.base import StrainGauge
    from twin.observe.strain import StrainGauges
    from twin.observe.triangulation import LaserTriangulation

    refused("observers", twin.run, SHORT, SPEC, [LaserTriangulation()])
    for gauges in ([], "abc", ["FBG-1"]):
        refused("gauges", StrainGauges, gauges)
    motor = CFRAME.point("motor")
    gauge = StrainGauge("g", motor.xyz, (1.0, 0.0, 0.0), 0.01, "nosuch")
    refused("gauges[0] g", twin.run, SHORT, SPEC, [StrainGauges([gauge])])


def test_an_instrument_built_with_its_own_instants_is_checked_against_the_run():
    """helper-29: a LaserInterferometer or DatumProbing built in Python with a negative first
    instant bypassed the scenario's checks and returned uninitialised memory (6.9e-304)."""
    from twin.motion import machine_for
    from twin.observe.interferometer import LaserInterferometer
    from twin.observe.probing import DatumProbing
    from twin.scenario import load_scenario

    sc = load_scenario("seed003-exp2")
    m = machine_for(CFRAME, sc)
    moving = PreparedTwin(m, resolution="coarse", solver="direct")
    moving.loads = lambda *a, **k: (_ for _ in ()).throw(AssertionError("run started"))
    for runs in ((-60.0, 2400.0), (0.0, 9600.0, 2400.0), (0.0, 123.4)):
        observer = LaserInterferometer(replace(sc.interferometer, runs=runs), m)
        refused("interferometer.runs", moving.run, sc, default_spec(m), [observer])
    probing = DatumProbing(ProbingConfig((-60.0, 600.0), ((0.1, 0.1, 0.1),)), m)
    refused("probing.times", moving.run, sc, default_spec(m), [probing])
    refused("interferometer", LaserInterferometer, "Y", m)


def test_a_mesh_and_a_resolution_or_a_prepared_twin_and_its_arguments_must_agree(twin):
    """A value that would be ignored is refused: PreparedTwin(mm=..., resolution=...) must name
    the mesh's own resolution; twin.simulate.run beside a prepared twin takes no other mesh,
    resolution, materials or solver than the twin's own (equal ones pass)."""
    from geometries.materials import MATERIALS
    from twin.simulate import run

    refused("resolution", PreparedTwin, CFRAME, twin.mm, "fine")
    refused("resolution", PreparedTwin, CFRAME, twin.mm, "ultra")
    assert PreparedTwin(CFRAME, twin.mm, "coarse").resolution == "coarse"
    stiffer = {"grey_cast_iron": MATERIALS["grey_cast_iron"].scaled(youngs_modulus=1.1)}
    for field, kwargs in (("mm", {"mm": PreparedTwin(CFRAME, resolution="coarse").mm}),
                          ("resolution", {"resolution": "default"}), ("materials", {"materials": stiffer}),
                          ("solver", {"solver": "iterative"})):
        err = refused(field, run, CFRAME, SHORT, prepared=twin, **kwargs)
        assert "leave it out, the prepared twin's is used" in str(err)
    refused("prepared", run, build_machine("belt-vmc"), SHORT, prepared=twin)
    same = run(CFRAME, SHORT, prepared=twin, mm=twin.mm, resolution="coarse", solver="direct")
    assert np.isfinite(same.readings["temperature"]).all()
