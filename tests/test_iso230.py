"""ISO 230-3 evaluations (``twin report iso230-3``): a synthetic drift with known ranges gives
those ranges exactly; per-step ranges and segment statistics are the definitions'."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from geometries.axes import LinearAxis
from tests.fuzz_files import result_dataset
from tests.stubs import OneAxisMachine
from twin.errors import InputError
from twin.observe.interferometer import InterferometerConfig, LaserInterferometer
from validate.iso230 import STILL_AIR_K, default_test, evaluate, segments_of


def synthetic(n: int = 241, speed: bool = True) -> xr.Dataset:
    """4 h at 1 min: drift X, Y, Z with ranges 1, 6, 12 um (exact binary fractions), tilts 3 and
    5 urad, air range 2.5 K; spindle 6000 rpm for 2 h, then stopped."""
    ds = result_dataset(n)
    t = ds.time.values
    ramp = np.minimum(t / 7200.0, 1.0)                 # 0 -> 1 over the first 2 h, then held
    z = -12.0 * ramp + 4.0 * (t > 3 * 3600)            # range 12 over the test; 4 in the last hour
    y = 6.0 * np.sin(np.pi * t / t[-1]) ** 2           # 0 .. 6 .. 0
    x = np.where(t < 3600, 0.0, 1.0)
    drift = np.column_stack([x, y, z])
    ds["probe_drift"] = (("time", "axis"), drift, {"units": "um"})
    ds["drift"] = (("time", "axis"), 0.5 * drift, {"units": "um"})   # the truth, not what the probes give
    ds["tilt"] = (("time", "rotation"), np.column_stack([3.0 * ramp, -5.0 * ramp]), {"units": "urad"})
    ds["ambient_temperature"] = ("time", 20.0 + 2.5 * ramp, {"units": "degC"})
    ds["spindle_speed"] = ("time", np.where(t < 7200, 6000.0 if speed else 0.0, 0.0), {"units": "rpm"})
    return ds


def test_known_ranges_are_returned_exactly():
    """max - min of each five-probe channel and of the air, exactly (no tolerance)."""
    ev = evaluate(synthetic(), "etve")
    ranges = {c.name: c.range for c in ev.channels}
    assert ranges == {"X": 1.0, "Y": 6.0, "Z": 12.0, "A": 3.0, "B": 5.0}
    assert ev.air_range == 2.5
    assert [c.unit for c in ev.channels] == ["um"] * 3 + ["urad"] * 2


def test_the_air_range_is_max_minus_min_wherever_the_extremes_fall():
    """ETVE's air range is max - min over the test: a room 20 - 2 sin(2 pi t / t_end) + 0.5 sin
    (4 pi t / t_end) neither starts nor ends at an extreme, and its range is read from the samples'
    own max and min, exactly (the synthetic ramp above starts at its minimum, where max - first
    would pass)."""
    ds = synthetic()
    t = ds.time.values
    air = 20.0 - 2.0 * np.sin(2 * np.pi * t / t[-1]) + 0.5 * np.sin(4 * np.pi * t / t[-1])
    ds["ambient_temperature"] = ("time", air, {"units": "degC"})
    ev = evaluate(ds, "etve")
    assert ev.air_range == air.max() - air.min()
    assert air.max() - air[0] < ev.air_range - 1.0 and air[0] - air.min() < ev.air_range - 1.0


def test_spindle_test_ranges_per_speed_step():
    """Steps found in the speed log, [0, 2 h) at 6000 rpm and [2 h, 4 h] stopped; Z ramps 12 um in
    the first (range 12 * 119/120: the last sample before 2 h) and jumps by 4 um in the second."""
    ds = synthetic()
    assert default_test(ds) == "spindle" and default_test(synthetic(speed=False)) == "etve"
    ev = evaluate(ds, "spindle")
    assert [(a, b, n) for a, b, n in ev.steps] == [(0.0, 7200.0, 6000.0), (7200.0, 14400.0, 0.0)]
    first, second = ev.step_ranges()
    assert first["Z"] == pytest.approx(12.0 * 119 / 120, abs=1e-12) and second["Z"] == 4.0
    assert first["X"] == 1.0 and second["X"] == 0.0


def test_segment_statistics_are_the_definitions():
    """Per segment: max, mean +- 2 std (population std), 95th percentile of |value| (linear)."""
    ds = synthetic()
    ev = evaluate(ds, "etve", segment=3600.0)
    assert [(a / 3600, b / 3600) for a, b in ev.segments] == [(0, 1), (1, 2), (2, 3), (3, 4)]
    z = ds.probe_drift.sel(axis="Z").values
    stats = ev.segment_stats()["Z"]
    last = z[180:]                         # t >= 3 h, the last segment includes its end
    s = stats[3]
    assert s["max"] == last.max() and s["min"] == last.min()
    assert s["mean"] == pytest.approx(last.mean(), abs=1e-12)
    assert s["high"] - s["low"] == pytest.approx(4 * last.std(), abs=1e-12)
    assert s["p95_abs"] == pytest.approx(np.percentile(np.abs(last), 95), abs=1e-12)
    first = z[:60]
    assert stats[0]["p95_abs"] == pytest.approx(np.percentile(np.abs(first), 95), abs=1e-12)
    assert segments_of(np.array([0.0, 10.0, 20.0]), 100.0) == [(0.0, 20.0)]


def test_spindle_test_needs_the_spindle_turning():
    """A spindle thermal-drift evaluation of a record whose spindle never turns is refused on
    --test (as the axis test is without axis motion); the same record evaluates as an ETVE."""
    ds = synthetic(speed=False)
    with pytest.raises(InputError) as err:
        evaluate(ds, "spindle", source="m.csv")
    assert err.value.field == "--test" and "neither the spindle nor a C axis turns" in err.value.message
    assert evaluate(ds, "etve").test == "etve"


def test_a_turning_c_axis_is_the_spindle_evaluation_and_lasers_are_the_drift():
    """The gantry's C-axis test: the C axis is the rotating source (its speed steps), the laser
    triangulation sensors and their tilt are the measured drift (not the true tool point), and the
    conditions say so; a record whose axes moved without an interferometer is the axis test on
    that drift."""
    ds = synthetic(speed=False)
    n = ds.time.size
    ds["c_axis_speed"] = ("time", np.where(np.arange(n) < n // 2, 2500.0, 0.0), {"units": "rpm"})
    ds["laser"] = (("time", "laser_id"), np.column_stack([np.linspace(0, 2, n), np.linspace(0, 9, n)]), {"units": "um"})
    ds["laser_tilt"] = ("time", np.linspace(0, 18, n), {"units": "urad"})
    ds = ds.assign_coords(laser_id=["Y", "Z"]).drop_vars(["probe", "probe_drift", "probe_true", "probe_id"],
                                                         errors="ignore")
    assert default_test(ds) == "spindle"
    ev = evaluate(ds, "spindle")
    assert [c.name for c in ev.channels] == ["laser Y", "laser Z", "A (lasers)"]
    assert ev.channels[1].range == pytest.approx(9.0, rel=1e-12) and [s[2] for s in ev.steps] == [2500.0, 0.0]
    rows = dict(ev.conditions)
    assert "laser triangulation" in rows["displacement sensors"] and rows["C axis"].startswith("up to 2500 rpm")
    moved = ds.drop_vars("c_axis_speed").assign_attrs(moved_axes="Z")
    assert default_test(moved) == "axis" and [c.name for c in evaluate(moved, "axis").channels][1] == "laser Z"
    assert dict(evaluate(moved, "axis").conditions)["axes moved"] == "Z"


def test_axis_needs_positioning_errors():
    """The axis evaluation reads the interferometer's schema, positioning_error(run_time, target,
    direction): the mean of both directions at each target, relative to the first run, at the
    runs' instants (the air interpolated there)."""
    ds = synthetic()
    with pytest.raises(InputError) as err:
        evaluate(ds, "axis", source="r.nc")
    assert err.value.field == "--test" and "interferometer" in err.value.message and "axes that moved" in err.value.message
    runs = np.array([0.0, 1200.0, 2400.0])
    fwd = np.array([[0.0, 1.0], [2.0, 0.0], [3.0, -1.0]])
    pe = np.stack([fwd, fwd + 0.5], axis=-1)            # a constant reversal error cancels in the mean
    ds["positioning_error"] = (("run_time", "target", "direction"), pe, {"units": "um"})
    ds = ds.assign_coords(run_time=("run_time", runs, {"units": "s"}), target=("target", [100.0, 400.0], {"units": "mm"}),
                          direction=["forward", "backward"])
    ev = evaluate(ds, "axis")
    assert default_test(ds) == "axis"
    assert [(c.name, c.range) for c in ev.channels] == [("target 100 mm", 3.0), ("target 400 mm", 2.0)]
    assert np.array_equal(ev.channels[0].values, [0.0, 2.0, 3.0]) and np.array_equal(ev.time, runs)
    assert np.allclose(ev.air, np.interp(runs, ds.time.values, ds.ambient_temperature.values), rtol=0, atol=1e-12)
    with pytest.raises(InputError, match="two"):
        evaluate(ds.isel(run_time=[0]), "axis", source="r.nc")
    from validate.iso230_report import sections
    table = dict(sections(ev))["Positioning-error change at the targets, run by run"]
    assert table[2:5] == [f"| {t:.3f} h | {a:.3f} | {b:.3f} | {air:.2f} |" for t, a, b, air in
                          zip(runs / 3600, [0.0, 2.0, 3.0], [0.0, -1.0, -2.0], ev.air)]
    assert "Positioning-error change at the targets, run by run" not in dict(sections(evaluate(synthetic(), "etve")))
    # the air read at the runs is said to be that, not the whole record's range (which the
    # conditions table gives)
    assert dict(sections(ev))["Maximum range over the test"][-1] == (
        f"Room air range at the interferometer's runs: {ev.air_range:.3f} K ({ev.air.min():.2f} to {ev.air.max():.2f} degC).")


def test_conditions_say_when_the_file_has_no_temperature_sensor():
    """ISO 230-3 lists the sensors; a record without temperature sensors says so instead of
    leaving the row out."""
    rows = dict(evaluate(synthetic(), "etve").conditions)
    assert rows["temperature sensors"] == "3: motor, column_side, bed_front"
    rows = dict(evaluate(synthetic().drop_vars(["temperature", "temperature_true", "sensor"], errors="ignore"),
                         "etve").conditions)
    assert rows["temperature sensors"] == "none in the file"


def test_cli_writes_both_reports_with_the_ranges_and_the_warning(tmp_path, capsys):
    from twin.cli import main

    path = tmp_path / "r.nc"
    synthetic(speed=False).to_netcdf(path, engine="h5netcdf")
    assert main(["report", "iso230-3", str(path), "-o", str(tmp_path / "rep")]) == 0
    md = (tmp_path / "rep" / "report.md").read_text()
    assert "| Z | 12.000 |" in md and "Room air range over the test: 2.500 K" in md
    assert "not to be used to compare machines" in md
    html = (tmp_path / "rep" / "index.html").read_text()
    assert html.count("data:image/png;base64,") == 2 and "<table>" in html
    assert "ISO 230-3 etve: X 1.0 um, Y 6.0 um, Z 12.0 um" in capsys.readouterr().out


def test_evaluate_from_python_names_a_bad_record_or_segment():
    """API audit: a path for the Dataset, a NaN or text segment, backwards or NaN time, room air
    below absolute zero, a NaN drift or spindle speed and a drift in mm are each one InputError
    naming it (as the command names them in a file), never a numpy error, a NaN speed step or a
    report of ranges 1000 times too small."""
    ds = result_dataset()
    nan_drift = ds.copy(deep=True)
    nan_drift.probe_drift[4, 2] = np.nan
    cold = ds.copy(deep=True)
    cold.ambient_temperature[3] = -380.0
    nan_speed = ds.copy(deep=True)
    nan_speed.spindle_speed[2] = np.nan
    in_mm = ds.copy(deep=True)
    in_mm.probe_drift.attrs["units"] = "mm"
    for args, field in ((("r.nc", "etve"), "ds"), ((nan_speed, "spindle"), "spindle_speed"),
                        ((in_mm, "etve"), "probe_drift"), ((ds, "spindle", float("nan")), "--segment"),
                        ((ds, "spindle", "1 h"), "--segment"), ((ds, "spindle", -60.0), "--segment"),
                        ((ds.isel(time=slice(None, None, -1)), "spindle"), "time"),
                        ((ds.assign_coords(time=np.r_[np.nan, ds.time.values[1:]]), "spindle"), "time"),
                        ((cold, "etve"), "ambient_temperature"), ((nan_drift, "spindle"), "Z"),
                        ((ds, None), "--test")):
        with pytest.raises(InputError) as err:
            evaluate(*args)
        assert err.value.field == field, str(err.value)
    assert evaluate(ds, "spindle").channels


def test_positioning_slope_is_the_least_squares_slope():
    """positioning_slope of each run is the least-squares slope of its error against the targets,
    sum (x - xbar)(e - ebar) / sum (x - xbar)^2 [um/mm], written out here, to round-off. The curves
    are not symmetric about mid-travel (a cubic; a line with one interior point bumped), so the
    end-point secant (e[-1] - e[0]) / (x[-1] - x[0]) gives other slopes."""
    obs = LaserInterferometer(InterferometerConfig("Y", (0.0, 600.0, 1200.0)),
                              OneAxisMachine(LinearAxis("Y", "y", (0.0, 0.4), "closed")))
    x = obs.targets * 1e3                                   # [mm], 0 .. 400 every 10
    cold = 3e-6 * np.sin(x / 70.0)                          # [m] the reference run's reading, subtracted
    bumped = 0.02 * x
    bumped[13] += 5.0                                       # at 130 mm
    errors = np.array([10.0 * (x / 400.0) ** 3, bumped])   # [um]
    data, _ = obs.data(np.vstack([cold, cold + errors * 1e-6]), None)
    dx = x - x.mean()
    expected = [0.0] + [np.sum(dx * (e - e.mean())) / np.sum(dx ** 2) for e in errors]
    np.testing.assert_allclose(data["positioning_slope"][1], expected, rtol=1e-12, atol=1e-15)


def test_segment_statistics_table_row_reads_min_max_mean_band_low_to_high():
    """Z over the last segment (3-4 h, segment = 3600 s) of synthetic(): the sample at t = 3 h is
    -12 (t > 3 h is false), the 60 after it -8, so values [-12, -8 x 60]: min -12, max -8,
    mean -492/61 = -8.066, population std 4 sqrt(60)/61 = 0.5079, mean -/+ 2 std = -9.081 .. -7.050
    (low .. high), 95th percentile of |value| (linear, index 0.95 * 60 = 57 of the sorted 61) = 8."""
    from validate.iso230_report import sections

    ds = synthetic()
    z = ds.probe_drift.sel(axis="Z").values[180:]
    assert z[0] == -12.0 and np.all(z[1:] == -8.0) and z.size == 61
    lines = dict(sections(evaluate(ds, "etve", segment=3600.0)))["Segment statistics"]
    start = lines.index("**Z** [um]")
    z_rows = [ln for ln in lines[start:] if ln.startswith("| 3-4 h")]
    assert z_rows[0] == "| 3-4 h | -12.000 | -8.000 | -8.066 | -9.081 .. -7.050 | 8.000 |"


def test_segment_statistics_head_each_table_with_its_channels_own_unit():
    """Each channel's segment-statistics table is headed by its name and its own unit, the drift
    X, Y, Z in um and the tilts A, B in urad (a heading that wrote um for every channel, or no unit,
    would pass a check on Z alone), and its columns read segment, min, max, mean, the 2-std band
    and the 95th percentile of |value|; the speed-step table's headers name each channel's unit."""
    from validate.iso230_report import sections

    secs = dict(sections(evaluate(synthetic(), "spindle", segment=3600.0)))
    lines = secs["Segment statistics"]
    assert [ln for ln in lines if ln.startswith("**")] == ["**X** [um]", "**Y** [um]", "**Z** [um]",
                                                             "**A** [urad]", "**B** [urad]"]
    i = lines.index("**B** [urad]")
    assert lines[i + 2] == "| segment | min | max | mean | mean -/+ 2 std | 95th percentile of abs. value |"
    assert lines[i + 4].startswith("| 0-1 h | -2.458 | 0.000 |")    # B = -5 t / 2 h: -5 * 59/120 at 59 min; -0 at 0
    assert secs["Range within each speed step"][0] == "| step | speed | X [um] | Y [um] | Z [um] | A [urad] | B [urad] |"


def test_the_reports_conditional_notes_appear_only_for_their_test():
    """The ISO 230-3 caution (not for comparing machines) belongs to the ETVE alone: a spindle and
    an axis evaluation of the same record carry neither the section nor the text; the room-air
    line appears only when the record logs the air, the speed-step table only
    for the spindle test."""
    from validate.iso230_report import markdown, sections

    ds = synthetic()
    etve, spindle = dict(sections(evaluate(ds, "etve"))), dict(sections(evaluate(ds, "spindle")))
    moved = evaluate(ds.assign_attrs(moved_axes="Z").drop_vars("spindle_speed"), "axis")
    assert "Caution" in etve and "not to be used to compare machines" in etve["Caution"][0]
    for other in (spindle, dict(sections(moved))):
        assert "Caution" not in other
        assert not any("compare machines" in ln for body in other.values() for ln in body)
    assert "not to be used to compare machines" not in markdown(evaluate(ds, "spindle"))
    assert "Range within each speed step" in spindle and "Range within each speed step" not in etve
    assert any(ln.startswith("Room air range over the test: 2.500 K") for ln in spindle["Maximum range over the test"])
    dry = dict(sections(evaluate(ds.drop_vars("ambient_temperature"), "spindle")))
    assert not any("Room air" in ln for ln in dry["Maximum range over the test"])


def test_a_segment_without_samples_has_no_row_and_the_later_ones_still_do():
    """Interferometer runs at 0, 10, 20 min and 2 h 10, 2 h 20 min in 1 h segments: the segment
    1-2 h holds no run and gets no row (no statistics of nothing), and the segment after it still
    gets its own: rows '0-1 h' over the first three runs and '2-2.33 h' over the last two."""
    from validate.iso230 import Channel, Evaluation
    from validate.iso230_report import sections

    t = np.array([0.0, 600.0, 1200.0, 7800.0, 8400.0])
    ev = Evaluation("axis", "r.nc", t, [Channel("target 100 mm", "um", np.array([0.0, 1.0, 2.0, 5.0, 7.0]))],
                    None, segments_of(t, 3600.0), runs=True)
    assert len(ev.segments) == 3
    stats = ev.segment_stats()["target 100 mm"]
    assert [(s["start"], s["end"], s["min"], s["max"]) for s in stats] == [(0.0, 3600.0, 0.0, 2.0),
                                                                             (7200.0, 8400.0, 5.0, 7.0)]
    rows = [ln for ln in dict(sections(ev))["Segment statistics"] if ln.startswith("| ") and "h |" in ln]
    assert [r.split(" | ")[0] for r in rows] == ["| 0-1 h", "| 2-2.33 h"]


def test_a_record_that_departs_from_the_tests_conditions_is_evaluated_and_says_so(tmp_path, capsys):
    """An ETVE test keeps the machine idle over a room that varies (seed 000's ETVE tests:
    "spindle stationary"); a spindle test moves no axis; an axis test turns no spindle. A record
    that departs is still evaluated, and the report, its HTML and the command's output say how:
    here the spindle turning in an ETVE evaluation, a room still to less than 0.1 K, axes moved in
    a spindle evaluation, the spindle turning in an axis evaluation; an idle record in a varying
    room departs from nothing."""
    from twin.cli import main
    from validate.iso230 import STILL_AIR_K
    from validate.iso230_report import sections

    ds = synthetic()
    assert evaluate(synthetic(speed=False), "etve").departures == []
    assert evaluate(ds, "spindle").departures == []
    turning = evaluate(ds, "etve").departures
    assert turning == ["The spindle turned (up to 6000 rpm): an ETVE test keeps the machine idle, so these ranges "
                       "hold the spindle's own heat as well as the room's."]
    still = ds.assign(ambient_temperature=("time", np.full(ds.sizes["time"], 20.0) + 0.99 * STILL_AIR_K
                                           * (ds.time.values == ds.time.values[-1]), {"units": "degC"}))
    assert [d.split(":")[0] for d in evaluate(still.assign(spindle_speed=0.0 * still.spindle_speed), "etve").departures] \
        == ["The room air varied by 0.099 K only (less than 0.1 K)"]
    assert evaluate(ds.assign_attrs(moved_axes="X,Z"), "spindle").departures == [
        "Axes moved (X,Z): the ranges hold the feed drives' heat as well as the spindle's."]
    assert evaluate(ds.assign_attrs(moved_axes="Z"), "axis").departures[0].startswith(
        "The spindle turned (up to 6000 rpm) during the axis test")
    assert dict(sections(evaluate(ds, "etve")))["Departures from the test's conditions"] == [f"- {turning[0]}"]
    assert "Departures from the test's conditions" not in dict(sections(evaluate(ds, "spindle")))
    path = tmp_path / "r.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    assert main(["report", "iso230-3", str(path), "--test", "etve", "-o", str(tmp_path / "rep")]) == 0
    assert f"  not as the test asks: {turning[0]}" in capsys.readouterr().out.splitlines()
    html = (tmp_path / "rep" / "index.html").read_text()
    assert "<h2>Departures from the test&#x27;s conditions</h2><p>&bull; The spindle turned" in html


def _piecewise_air(ds):
    """The room through 20, 22.5, 20, 19, 20.5 degC at 0..4 h (knots on the 1-min samples): min 19,
    max 22.5, range 3.5 K; max - first would read 2.5 K, last - first 0.5 K."""
    t = ds.time.values
    air = np.interp(t, [0.0, 3600.0, 7200.0, 10800.0, 14400.0], [20.0, 22.5, 20.0, 19.0, 20.5])
    return ds.assign(ambient_temperature=("time", air, {"units": "degC"}))


def test_speed_step_table_rows_read_each_steps_own_ranges():
    """synthetic(): steps [0, 2 h) at 6000 rpm and [2 h, 4 h] stopped. First step, samples 0..119
    min: X 0 -> 1 (1.000), Y 0 -> 6 sin^2(pi 119/240) = 6 cos^2(pi/240) = 5.99897, Z 12 * 119/120 = 11.900,
    A 3 * 119/120 = 2.975, B 5 * 119/120 = 4.958; second: X 0, Y 6 -> 0, Z -12 -> -8 (4.000), A, B
    held (0.000)."""
    from validate.iso230_report import sections

    lines = dict(sections(evaluate(synthetic(), "spindle")))["Range within each speed step"]
    assert lines[2:] == ["| 0-2 h | 6000 rpm | 1.000 | 5.999 | 11.900 | 2.975 | 4.958 |",
                         "| 2-4 h | 0 rpm | 0.000 | 6.000 | 4.000 | 0.000 | 0.000 |"]


def test_an_etve_record_whose_axes_moved_says_so():
    """An ETVE record whose axes moved is named as departing from the test (only the spindle
    test's note was tested)."""
    ev = evaluate(synthetic(speed=False).assign_attrs(moved_axes="X"), "etve")
    assert ev.departures == ["Axes moved (X): the ranges hold the feed drives' heat as well as the room's."]


def test_departure_names_the_top_speed_not_the_first_sample():
    """The spindle stands at first, runs 3000 rpm, then 9000 rpm, then stops: "up to 9000 rpm" for
    the ETVE note and the axis-test note alike."""
    ds = synthetic(speed=False)
    n = ds.sizes["time"]
    speed = np.zeros(n)
    speed[10:60], speed[60:120] = 3000.0, 9000.0
    ds = ds.assign(spindle_speed=("time", speed, {"units": "rpm"}))
    assert evaluate(ds, "etve").departures[0].startswith("The spindle turned (up to 9000 rpm): ")
    assert evaluate(ds.assign_attrs(moved_axes="Z"), "axis").departures[0].startswith(
        "The spindle turned (up to 9000 rpm) during the axis test")


def test_a_room_that_varied_by_exactly_the_still_air_limit_is_not_still():
    """A room still to less than STILL_AIR_K (0.1 K) departs; a range of exactly 0.1 K does not
    (air 0.0 / 0.1 degC: exactly 0.1 in binary, which a difference near 20 degC is not)."""
    ds = synthetic(speed=False)
    air = np.zeros(ds.sizes["time"])
    air[-1] = 0.1
    ev = evaluate(ds.assign(ambient_temperature=("time", air, {"units": "degC"})), "etve")
    assert ev.air_range == STILL_AIR_K
    assert ev.departures == []
    air[-1] = np.nextafter(0.1, 0.0)
    ev = evaluate(ds.assign(ambient_temperature=("time", air, {"units": "degC"})), "etve")
    assert [d.split(":")[0] for d in ev.departures] == ["The room air varied by 0.100 K only (less than 0.1 K)"]


def test_cli_summary_prints_ranges_air_range_and_every_departure(tmp_path, capsys):
    """X offset by +2 um: range 1.0, max |X| 3.0; the piecewise room: range 3.5 K (max - first 2.5);
    the spindle turning and axes moved in an ETVE: two departures, both printed."""
    from twin.cli import main

    ds = _piecewise_air(synthetic()).assign_attrs(moved_axes="X,Z")
    drift = ds.probe_drift.values.copy()
    drift[:, 0] += 2.0
    ds["probe_drift"] = (("time", "axis"), drift, {"units": "um"})
    path = tmp_path / "r.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    assert main(["report", "iso230-3", str(path), "--test", "etve", "-o", str(tmp_path / "rep")]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "ISO 230-3 etve: X 1.0 um, Y 6.0 um, Z 12.0 um, A 3.0 urad, B 5.0 urad; room air range 3.5 K"
    notes = [ln for ln in out if ln.startswith("  not as the test asks: ")]
    assert [n.split(": ")[1].split(" (")[0] for n in notes] == ["The spindle turned", "Axes moved"]
