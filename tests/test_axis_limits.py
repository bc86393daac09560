"""Axis motion's limits (twin.limits.MAX_FEED, MAX_ACCELERATION, MAX_MOTION_PIECES), its
closed-form duration check (twin.motion: a reciprocation's count costs no time), and the
interferometer's need for the axis's motion (twin.observe.interferometer.check_interferometer)."""

from __future__ import annotations


import numpy as np
import pytest

from twin import limits
from twin.errors import InputError
from twin.scenario import scenario_from_dict

BASE = {"name": "s", "sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
        "spindle": [{"speed": "6000 rpm", "duration": "10 min"}]}


def reciprocate(**kw) -> dict:
    move = {"kind": "reciprocate", "between": ["0 mm", "280 mm"], "feed": "20 mm/s", "acceleration": "10 mm/s2",
            "duration": "5 min"}
    move.update(kw)
    return {**BASE, "axis": [{"name": "Y", "move": [move]}]}


def refused(data: dict) -> InputError:
    with pytest.raises(InputError) as err:
        scenario_from_dict(data, "s.toml")
    return err.value


@pytest.fixture
def nothing_built(monkeypatch):
    """Building any motion's pieces fails the test: a refusal must come from the closed-form plan."""
    import twin.motion

    def build(*args, **kwargs):
        raise AssertionError("a motion's pieces were built")
    monkeypatch.setattr(twin.motion._Builder, "__init__", build)


@pytest.mark.parametrize("count", [1_000_000_000, 10**15])
def test_a_huge_count_is_refused_in_closed_form(count, nothing_built):
    move = reciprocate(count=count)
    del move["axis"][0]["move"][0]["duration"]
    err = refused(move)
    assert err.field == "axis[0].move" and "longer than the scenario" in str(err)
    one = 280e-3 / 20e-3 + 20e-3 / 10e-3          # d / v + v / a [s]: one stroke
    assert f"{count * one:g} s" in str(err)


def test_the_closed_form_plan_matches_the_built_motion():
    data = reciprocate(duration="9 min", dwell="2 s")
    data["axis"][0]["move"].append({"kind": "move", "to": "100 mm", "feed": "30 mm/s", "acceleration": "50 mm/s2",
                                    "duration": "30 s"})
    data["axis"][0]["move"].append({"kind": "table", "times": ["0 s", "10 s", "20 s"],
                                    "positions": ["100 mm", "150 mm", "120 mm"]})
    sc = scenario_from_dict({**data, "spindle": [{"speed": "6000 rpm", "duration": "20 min"}]}, "s.toml")
    m = sc.axes[0]
    planned, end, bound = m.duration, m.x_end, m.pieces
    assert m._pieces is None                        # nothing built by loading the scenario
    t0, dur = m.t0, m.dur                           # builds
    assert np.isclose(planned, t0[-1] + dur[-1]) and np.isclose(planned, 9 * 60 + 30 + 20)
    assert np.isclose(end, m.position(np.array([1e4]))[0]) and np.isclose(end, 0.12)
    assert len(t0) <= bound


def test_a_count_within_the_scenario_still_runs():
    data = reciprocate(count=3)
    del data["axis"][0]["move"][0]["duration"]
    m = scenario_from_dict(data, "s.toml").axes[0]
    assert np.isclose(m.duration, 3 * 16.0) and np.isclose(m.x_end, 0.28)
    assert np.isclose(m.position(np.array([16.0]))[0], 0.28) and np.isclose(m.position(np.array([32.0]))[0], 0.0)


def test_too_many_pieces_are_refused_before_building(nothing_built):
    data = reciprocate(between=["0 mm", "1e-8 mm"], duration="10 min")
    err = refused(data)
    assert err.field == "axis[0].move" and "affordable" in str(err)


@pytest.mark.parametrize("key, value, field", [
    ("feed", "1000 m/s", "feed"), ("feed", "121 m/min", "feed"), ("acceleration", "1e9 m/s2", "acceleration"),
    ("acceleration", "51 m/s2", "acceleration")])
def test_feeds_and_accelerations_beyond_machine_tools_are_refused(key, value, field):
    err = refused(reciprocate(**{key: value}))
    assert err.field == f"axis[0].move[0].{field}"
    assert f"{limits.MAX_FEED:g} m/s" in str(err) if key == "feed" else f"{limits.MAX_ACCELERATION:g} m/s2" in str(err)


def test_the_limits_themselves_and_the_gantry_feed_pass():
    scenario_from_dict(reciprocate(feed="120 m/min", acceleration="50 m/s2"), "s.toml")
    scenario_from_dict(reciprocate(feed="70 m/min", acceleration="3 m/s2"), "s.toml")


def test_a_table_faster_than_the_feed_limit_is_refused():
    data = {**BASE, "axis": [{"name": "Y", "move": [{"kind": "table", "times": ["0 s", "1 ms"],
                                                      "positions": ["0 mm", "280 mm"]}]}]}
    err = refused(data)
    assert err.field == "axis[0].move[0].positions" and "280 m/s" in str(err)
    data["axis"][0]["move"][0]["times"] = ["0 s", "1 s"]       # 0.28 m/s: fine
    scenario_from_dict(data, "s.toml")


def test_an_axis_moving_even_half_a_minute_past_the_scenario_is_refused():
    """An axis may not move longer than the ``[[spindle]]`` steps (README, "Motion in a
    scenario"; ``twin.motion_checks.check_durations``, to 1e-6 s): a 10.5 min hold on a 10 min
    run is refused naming the axis's moves, a 10 min hold is taken."""
    data = {**BASE, "axis": [{"name": "Y", "move": [{"kind": "hold", "position": "140 mm", "duration": "10.5 min"}]}]}
    err = refused(data)
    assert err.field == "axis[0].move" and "longer than the scenario" in str(err)
    data["axis"][0]["move"][0]["duration"] = "10 min"
    assert scenario_from_dict(data, "s.toml").axes[0].duration == 600.0


def test_a_table_move_starts_at_0_s():
    """A ``table`` move's times start at 0 s (relative to the move's start) and increase
    strictly (``twin.motion``): a table from 5 s is refused naming its times, not shifted
    silently to start at 0 s."""
    data = {**BASE, "axis": [{"name": "Y", "move": [{"kind": "table", "times": ["5 s", "15 s"],
                                                      "positions": ["0 mm", "100 mm"]}]}]}
    err = refused(data)
    assert err.field == "axis[0].move[0].times" and "start at 0 s" in str(err)


def test_a_move_must_start_where_the_axis_is():
    """Each move starts where the axis is (README: a move that does not start where the axis is
    is refused): after a hold at 100 mm a reciprocation between 100.5 mm and 280 mm is refused
    naming that move (the axis would jump by 0.5 mm), one between 100 mm and 280 mm is taken."""
    hold = {"kind": "hold", "position": "100 mm", "duration": "1 min"}
    data = reciprocate(between=["100.5 mm", "280 mm"])
    data["axis"][0]["move"].insert(0, hold)
    err = refused(data)
    assert err.field == "axis[0].move[1]" and "add a move" in str(err)
    data["axis"][0]["move"][1]["between"] = ["100 mm", "280 mm"]
    assert scenario_from_dict(data, "s.toml").axes[0].position(np.array([0.0]))[0] == pytest.approx(0.1)


def test_a_position_even_half_a_millimetre_beyond_the_travel_is_refused():
    """Every position an axis reaches lies within its travel (``check_motions``, to 1e-9 m):
    ``cframe-vmc``'s Y travels 0-400 mm, so a move to 400.5 mm is refused naming the axis's moves
    and the travel, a move to 400 mm is taken."""
    from geometries import build_machine
    from twin.motion import check_motions

    machine = build_machine("cframe-vmc")

    def to(position: str):
        move = {"kind": "move", "to": position, "feed": "20 mm/s", "acceleration": "10 mm/s2"}
        return scenario_from_dict({**BASE, "axis": [{"name": "Y", "start": "390 mm", "move": [move]}]}, "s.toml")
    with pytest.raises(InputError) as err:
        check_motions(to("400.5 mm"), machine)
    assert err.value.field == "axis[0].move[0].to" and "400.5 mm is outside the Y travel 0 .. 400 mm" in str(err.value)
    check_motions(to("400 mm"), machine)


@pytest.mark.parametrize("start, move, field, written", [
    # the value as written, under its own key (the trapezoid's first piece, -0.5 mm, was named before)
    ("0 mm", {"kind": "move", "to": "-1 mm"}, "axis[0].move[0].to", "-1 mm"),
    ("-3 mm", {"kind": "move", "to": "100 mm"}, "axis[0].start", "-3 mm"),
    ("0 mm", {"kind": "reciprocate", "between": ["0 mm", "500 mm"], "count": 2}, "axis[0].move[0].between", "500 mm"),
    ("0 mm", {"kind": "hold", "position": "0 mm", "duration": "1 min"}, None, None),
])
def test_a_position_beyond_the_travel_is_named_as_written(start, move, field, written):
    from geometries import build_machine
    from twin.motion import check_motions

    if move["kind"] != "hold":
        move = {**move, "feed": "20 mm/s", "acceleration": "10 mm/s2"}
    sc = scenario_from_dict({**BASE, "axis": [{"name": "Y", "start": start, "move": [move]}]}, "s.toml")
    if field is None:
        check_motions(sc, build_machine("cframe-vmc"))
        return
    with pytest.raises(InputError) as err:
        check_motions(sc, build_machine("cframe-vmc"))
    assert err.value.field == field and err.value.message.startswith(f"{written} is outside the Y travel")


def test_a_planned_motion_pickles():
    import pickle
    m = scenario_from_dict(reciprocate(), "s.toml").axes[0]
    back = pickle.loads(pickle.dumps(m))
    assert np.allclose(back.t0, m.t0) and back.x_end == m.x_end and back.duration == m.duration


def test_the_interferometer_of_an_axis_never_moved_is_refused():
    from geometries import build_machine
    from twin.motion import machine_for
    from twin.observe.interferometer import check_interferometer

    data = {**BASE, "interferometer": {"axis": "Y", "runs": ["0 min", "10 min"]}}
    sc = scenario_from_dict(data, "s.toml")
    machine = machine_for(build_machine("cframe-vmc"), sc)
    with pytest.raises(InputError) as err:
        check_interferometer(sc.interferometer, sc, machine)
    assert err.value.field == "interferometer.axis" and "[[axis]]" in str(err.value)
    held = {**data, "axis": [{"name": "Y", "move": [{"kind": "hold", "position": "140 mm", "duration": "10 min"}]}]}
    sc = scenario_from_dict(held, "s.toml")
    check_interferometer(sc.interferometer, sc, machine_for(build_machine("cframe-vmc"), sc))
    from validate.signatures import Engine      # the diagnosis's engine checks it as a simulation does
    with pytest.raises(InputError) as err:
        Engine(machine, scenario_from_dict(data, "s.toml"), "coarse")
    assert err.value.field == "interferometer.axis"
