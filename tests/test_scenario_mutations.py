"""Mutation audit of the scenario and model layer (twin.scenario, twin.motion, twin.motion_checks,
twin.rotary, twin.limits, twin.model, twin.camera_config, twin.simulate): each test pins one rule
that a small change of the code (a comparison flipped, a check dropped, a formula slipped) left
unnoticed by the rest of the suite. Small and fast: closed forms, the loader's refusals and one
run of a box of eight cells; the audit's table is in its report."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from twin.ambient import Ambient
from twin.errors import InputError
from twin.motion import Motion
from twin.scenario import Scenario, scenario_from_dict

BASE = {"name": "s", "sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
        "spindle": [{"speed": "6000 rpm", "duration": "10 min"}]}
SHORT = Scenario("short", ((600.0, 8000.0),), Ambient("constant", mean=20.0), 60.0, source="short.toml")


def axis(*moves, start=None) -> dict:
    """BASE with one Y axis making ``moves``."""
    table = {"name": "Y", "move": list(moves)}
    if start is not None:
        table["start"] = start
    return {**BASE, "axis": [table]}


def reciprocate(**kw) -> dict:
    move = {"kind": "reciprocate", "between": ["0 mm", "280 mm"], "feed": "20 mm/s", "acceleration": "10 mm/s2",
            "duration": "5 min"}
    move.update(kw)
    return move


def refused(data: dict, field: str, phrase: str) -> InputError:
    """The scenario ``data`` is refused with one InputError naming the file, ``field`` and ``phrase``."""
    with pytest.raises(InputError) as err:
        scenario_from_dict(data, "s.toml")
    assert err.value.source == "s.toml" and err.value.field == field, str(err.value)
    assert phrase in err.value.message, str(err.value)
    return err.value


def cframe():
    from geometries import build_machine
    return build_machine("cframe-vmc")


# ------------------------------------------------------------------------ twin.motion: reading

def test_a_negative_dwell_is_refused():
    """A reciprocation's ``dwell`` is a wait at each end: not negative (a negative dwell shortened
    the closed-form period below the stroke time, so the planned duration and the built strokes
    disagreed)."""
    refused(axis(reciprocate(dwell="-2 s")), "axis[0].move[0].dwell", "must not be negative")
    m = scenario_from_dict(axis(reciprocate(dwell="0 s")), "s.toml").axes[0]
    assert m.duration == pytest.approx(300.0)


def test_a_count_of_zero_strokes_is_refused():
    """``count`` is a positive whole number of strokes: 0 would be a reciprocation that never moves."""
    move = reciprocate(count=0)
    del move["duration"]
    refused(axis(move), "axis[0].move[0].count", "positive whole number")


def test_a_reciprocation_between_one_position_twice_is_refused():
    """The two ends of ``between`` must differ (0 mm to 0 mm has no stroke: its period is the dwell
    alone, and without a dwell the number of strokes is duration / 0)."""
    refused(axis(reciprocate(between=["100 mm", "0.1 m"])), "axis[0].move[0].between", "must differ")
    refused(axis(reciprocate(between=["100 mm", "100 mm"], dwell="2 s")), "axis[0].move[0].between", "must differ")


def test_a_table_move_too_fast_backwards_is_refused_as_forwards():
    """A table move's speed |dx/dt| is limited to MAX_FEED = 2 m/s whichever way it goes: 280 mm
    back to 0 in 1 ms (280 m/s) is refused naming its positions, like the same move forwards."""
    move = {"kind": "table", "times": ["0 s", "1 ms"], "positions": ["280 mm", "0 mm"]}
    refused(axis(move), "axis[0].move[0].positions", "280 m/s")


def test_the_first_move_starts_at_the_axis_start():
    """An axis's ``start`` is where its first move begins: a hold at 100 mm after ``start = 0 mm``
    does not start where the axis is and is refused (the start was silently replaced by the
    hold's position); at ``start = 100 mm`` it is taken and holds there."""
    hold = {"kind": "hold", "position": "100 mm", "duration": "1 min"}
    err = refused(axis(hold, start="0 mm"), "axis[0].move[0]", "starts at 100 mm")
    assert "at 0 mm there" in err.message
    m = scenario_from_dict(axis(hold, start="100 mm"), "s.toml").axes[0]
    assert m.position(np.array([0.0, 60.0])) == pytest.approx([0.1, 0.1])


def test_a_reciprocation_given_a_duration_dwells_at_its_last_end_for_the_rest():
    """A reciprocation given a duration runs the whole strokes that fit, n = floor(T / (L/v + v/a
    + dwell)), and then dwells at its last end for the rest: 280 mm at 20 mm/s and 10 mm/s2 is
    16 s a stroke, so 5 min are 18 strokes (288 s, ending at 0 mm after an even count) and 12 s at
    rest; the move lasts the 300 s it was given, and a hold after it starts at 300 s."""
    hold = {"kind": "hold", "position": "0 mm", "duration": "1 min"}
    m = scenario_from_dict(axis(reciprocate(), hold), "s.toml").axes[0]
    assert m.duration == pytest.approx(360.0)
    t0, dur = m.t0, m.dur                                   # built
    assert t0[-1] == pytest.approx(300.0) and dur[-1] == pytest.approx(60.0)
    assert t0[-2] == pytest.approx(288.0) and dur[-2] == pytest.approx(12.0)
    assert m.position(np.array([288.0, 295.0, 300.0])) == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)
    assert m.velocity(np.array([287.0, 290.0])) == pytest.approx([-0.01, 0.0], abs=1e-12)


# ------------------------------------------------------------------ twin.motion_checks (Python)

def test_a_motion_built_in_python_is_within_the_acceleration_limit():
    """``check_pieces`` holds each piece's |a| to MAX_ACCELERATION = 50 m/s2: 100 m/s2 for 10 ms
    (ending at 1 m/s, within the feed limit, 5 mm further) is refused naming the axis's moves; the
    same 5 mm at 50 m/s2 over sqrt(2) x 10 ms is taken."""
    from twin.motion_checks import check_pieces

    hard = Motion("Y", [0.0], [0.01], [0.1], [0.0], [100.0], 0.105)
    with pytest.raises(InputError) as err:
        check_pieces(hard, "s", "axis[0].move")
    assert err.value.field == "axis[0].move" and "100 m/s2" in err.value.message
    t = np.sqrt(2) * 0.01
    check_pieces(Motion("Y", [0.0], [t], [0.1], [0.0], [50.0], 0.1 + 25.0 * t ** 2), "s", "axis[0].move")


def test_a_motion_built_in_python_is_held_to_the_travel_at_both_ends():
    """``check_motions``: every extreme of a motion built in Python (no positions written in a file)
    lies within the travel, the upper end too: on ``cframe-vmc``'s Y (0-400 mm) a motion from
    300 mm at 2 mm/s for 100 s ends at 500 mm and is refused naming the axis's moves."""
    from twin.motion_checks import check_motions

    machine = cframe()
    up = Motion("Y", [0.0], [100.0], [0.3], [0.002], [0.0], 0.5)
    with pytest.raises(InputError) as err:
        check_motions(replace(SHORT, axes=(up,)), machine)
    assert err.value.field == "axis[0].move" and "500 mm is outside the Y travel 0 .. 400 mm" in err.value.message
    down = Motion("Y", [0.0], [100.0], [0.3], [-0.002], [0.0], 0.1)
    check_motions(replace(SHORT, axes=(down,)), machine)


# ------------------------------------------------------------------------ twin.scenario, limits

def test_an_air_event_starting_at_the_end_of_the_run_is_refused():
    """An ``[[ambient.events]]`` entry starts within the run (README: "starting within the run"):
    one starting at the run's end (10 min of 10 min) would change nothing and is refused naming
    its start; one starting a sample earlier is taken."""
    event = {"start": "10 min", "change": "-2 K", "fall": "5 min"}
    data = {**BASE, "ambient": {"temperature": "20 degC", "events": [event]}}
    refused(data, "ambient.events[0].start", "at or after the end of the run")
    event["start"] = "9 min"
    assert len(scenario_from_dict(data, "s.toml").ambient.events) == 1


def test_a_run_of_exactly_a_million_steps_is_affordable():
    """The run-size limit refuses *more* than MAX_STEPS = 10^6 time steps (duration / sample
    interval): 10^6 s at 1 s is taken (nothing is built by loading it), 10^6 + 1 s is refused
    naming the spindle steps and the size."""
    from twin import limits

    assert limits.check_steps(1e6, 1.0, "s.toml", "sample_interval") == 1_000_000
    data = {**BASE, "sample_interval": "1 s", "spindle": [{"speed": "0 rpm", "duration": "1000000 s"}]}
    assert scenario_from_dict(data, "s.toml").duration == 1e6
    data["spindle"][0]["duration"] = "1000001 s"
    refused(data, "spindle", "would take 1e+06 time steps")


def test_a_step_a_fraction_of_a_sample_off_the_grid_is_refused():
    """Each ``[[spindle]]`` step is a whole number of sample intervals, to 1e-6 of a sample
    (``twin.limits.check_whole_samples``): 600.3 s at 60 s samples (10.005 samples) is refused
    naming the step's duration, in a file and in Python alike; 600 s is taken."""
    data = {**BASE, "spindle": [{"speed": "6000 rpm", "duration": "600.3 s"}]}
    refused(data, "spindle[0].duration", "multiple of the sample interval (60 s)")
    with pytest.raises(InputError) as err:
        replace(SHORT, steps=((600.3, 8000.0),)).check()
    assert err.value.source == "short.toml" and err.value.field == "spindle[0].duration"
    replace(SHORT, steps=((600.0, 8000.0),)).check()


def test_a_table_ambient_built_in_python_covers_the_run_to_half_a_sample():
    """A table ambient set in Python covers the run to half a sample interval at its end (a log's
    last step snapped to the grid; ``Scenario.check``): on a 600 s run at 60 s samples a table to
    570 s is taken, one ending a whole sample early (540 s) is refused naming ``ambient.times``."""
    def table(end):
        return replace(SHORT, ambient=Ambient("table", times=(0.0, end), temperatures=(20.0, 21.0)))
    table(570.0).check()
    with pytest.raises(InputError) as err:
        table(540.0).check()
    assert err.value.source == "short.toml" and err.value.field == "ambient.times"
    assert "must cover the scenario's 0 to" in err.value.message


# ------------------------------------------------------------------------------ twin.simulate

def test_a_runs_timings_count_its_time_steps():
    """``RunResult.timings["steps"]`` (also what ``twin.dataset.build_case`` reports per case) is
    the number of time steps, duration / sample interval = len(times) - 1: a 100 mm box in 50 mm
    cells run for 120 s at 60 s samples takes 2 steps over 3 instants."""
    from tests.conftest import box_body
    from twin.model import ModelSpec
    from twin.observe import HeatBalance
    from twin.simulate import run

    mm = box_body((0.1, 0.1, 0.1), 0.05)
    sc = Scenario("s", ((120.0, 0.0),), Ambient("constant", mean=20.0), 60.0)
    result = run(mm.machine, sc, ModelSpec(()), mm=mm, observers=[HeatBalance()])
    assert len(result.times) == 3 and result.timings["steps"] == 2
