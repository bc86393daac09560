"""Measurements (NetCDF, CSV + TOML mapping), scenarios from measured inputs, and compare."""

from __future__ import annotations

import numpy as np
import pytest

from twin.api import simulate
from twin.errors import InputError
from twin.io.results import write_netcdf
from twin.scenario import Ambient, Scenario
from validate.channels import detect_phases
from validate.compare import compare, format_compare, stats
from twin.io.measured_inputs import scenario_from_measurement, speed_steps
from twin.io.measurement import read_measurement

SITES = ("motor", "column_side", "bed_front")
PROBES = ("X1", "X2", "Y1", "Y2", "Z")


@pytest.fixture(scope="module")
def sim():
    sc = Scenario("mc", ((3600.0, 9000.0), (1800.0, 6000.0), (3600.0, 0.0)), Ambient("daily", mean=20.0, amplitude=2.0), 60.0)
    ds, _ = simulate("cframe-vmc", sc, resolution="coarse")
    return ds


def write_csv(tmp_path, ds, *, extra_col=False, mutate=None, unit_T="degC", time_unit="min"):
    """CSV (time in minutes, probes in mm) + mapping from a simulation; returns the CSV path."""
    t = ds.time.values / 60.0
    cols = {"t": t, "n": ds.spindle_speed.values, "room": ds.ambient_temperature.values}
    cols.update({f"T_{s}": ds.temperature_true.sel(sensor=s).values for s in SITES})
    cols.update({f"p{p}": ds.probe_true.sel(probe_id=p).values * 1e-3 for p in PROBES})
    if extra_col:
        cols["junk"] = np.zeros_like(t)
    data = np.column_stack(list(cols.values()))
    if mutate:
        mutate(data)
    lines = [",".join(cols)] + [",".join(repr(float(v)) for v in row) for row in data]
    (tmp_path / "m.csv").write_text("\n".join(lines) + "\n")
    toml = ['machine = "cframe-vmc"', f'[columns.t]\nrole = "time"\nunit = "{time_unit}"',
            '[columns.n]\nrole = "spindle_speed"\nunit = "rpm"', '[columns.room]\nrole = "ambient_temperature"\nunit = "degC"']
    toml += [f'[columns.T_{s}]\nrole = "temperature"\nsite = "{s}"\nunit = "{unit_T}"' for s in SITES]
    toml += [f'[columns.p{p}]\nrole = "probe"\nprobe = "{p}"\nunit = "mm"' for p in PROBES]
    (tmp_path / "m.toml").write_text("\n".join(toml) + "\n")
    return tmp_path / "m.csv"


def test_csv_measurement_has_the_result_schema(tmp_path, sim):
    meas = read_measurement(write_csv(tmp_path, sim))
    for var in ("spindle_speed", "ambient_temperature", "temperature", "probe", "probe_drift", "tilt"):
        assert var in meas and meas[var].dims == sim[var].dims
    assert list(meas.sensor.values) == list(SITES)
    assert np.allclose(meas.time, sim.time)
    assert np.allclose(meas.z.sel(sensor="motor"), sim.z.sel(sensor="motor"))
    assert np.allclose(meas.temperature, sim.temperature_true.sel(sensor=list(SITES)), atol=1e-9)
    assert np.allclose(meas.tilt, sim.tilt_true, atol=1e-6)
    from geometries import build_machine
    from twin.observe import derived_from_probes

    expected, _ = derived_from_probes(sim.probe_true.values, list(PROBES), build_machine("cframe-vmc"))
    assert np.allclose(meas.probe_drift, expected, atol=1e-6)  # ISO 230-3 five-probe evaluation


def test_netcdf_read_as_is(tmp_path, sim):
    path = write_netcdf(sim, tmp_path / "r.nc")
    meas = read_measurement(path)
    assert set(sim.data_vars) == set(meas.data_vars)
    assert np.allclose(meas.temperature, sim.temperature)


def test_scenario_from_measured_inputs(tmp_path, sim):
    sc = scenario_from_measurement(read_measurement(write_csv(tmp_path, sim)))
    assert sc.steps == ((3600.0, 9000.0), (1800.0, 6000.0), (3600.0, 0.0))
    assert sc.sample_interval == pytest.approx(60.0)
    t = np.linspace(0, 9000, 37)
    assert np.allclose(sc.ambient_temperature(t), np.interp(t, sim.time, sim.ambient_temperature))


def test_speed_steps_and_phase_detection_on_synthetic_trace():
    t = np.arange(0, 8 * 3600 + 1, 60.0)
    n = np.select([t < 3600, t < 7200, t < 10800], [0.0, 8000.0, 4000.0], 0.0) + np.where(t >= 3600, 5.0, 0) * (t < 10800)
    amb = 20 + np.where(t < 4 * 3600, t / 3600 * 0.5, 2.0 - (t - 4 * 3600) / 3600 * 0.5)
    assert [s[2] for s in speed_steps(t, n)] == [0.0, 8005.0, 4005.0, 0.0]
    ph = detect_phases(t, n, amb)
    spindle = [(p.label, p.start, p.end) for p in ph if p.kind == "spindle"]
    assert spindle == [("spindle off", 0.0, 3600.0), ("spindle on 8005 rpm", 3600.0, 7200.0),
                       ("speed change to 4005 rpm", 7200.0, 10800.0), ("spindle off", 10800.0, 8 * 3600.0)]
    ambient = [p.label for p in ph if p.kind == "ambient"]
    assert ambient == ["ambient rising", "ambient falling"]
    # the phases of each kind cover the record, every sample in exactly one, the last ending at
    # the last sample (no phase reaches past the record)
    for kind in ("spindle", "ambient"):
        mine = [p for p in ph if p.kind == kind]
        assert np.array_equal(sum(p.mask(t).astype(int) for p in mine), np.ones(t.size, int))
        assert mine[-1].end == t[-1] and mine[-1].closed and not any(p.closed for p in mine[:-1])
    turn = next(p for p in ph if p.label == "ambient falling").start
    assert abs(turn - 4 * 3600) <= 1800


def test_ambient_phases_survive_sensor_noise():
    """The room's rate is taken from a moving average (validate.channels.detect_phases): the trace
    above with 0.05 K of Gaussian sensor noise still splits into rising then falling, turning
    within 30 min of 4 h (the raw difference quotient of noisy samples flips sign every few
    samples and gave one phase for the whole record)."""
    t = np.arange(0, 8 * 3600 + 1, 60.0)
    amb = 20 + np.where(t < 4 * 3600, t / 3600 * 0.5, 2.0 - (t - 4 * 3600) / 3600 * 0.5)
    amb = amb + np.random.default_rng(0).normal(0.0, 0.05, t.size)
    ambient = [p for p in detect_phases(t, np.zeros_like(t), amb) if p.kind == "ambient"]
    assert [p.label for p in ambient] == ["ambient rising", "ambient falling"]
    assert abs(ambient[1].start - 4 * 3600) <= 1800


def test_a_constant_channel_off_by_a_constant_is_not_a_perfect_fit():
    """NSE = 1 - sum r^2 / sum (m - mean m)^2 is undefined for a constant measured channel: 1 only
    when nothing is missed (r = 0), NaN when it is off (a flat sensor 0.3 K off has RMSE and
    max |r| 0.3 K, and no NSE to show)."""
    off = stats(np.full(3, 20.0), np.full(3, 0.3))
    assert off.rmse == pytest.approx(0.3, rel=1e-15) and off.max_abs == pytest.approx(0.3, rel=1e-15)
    assert np.isnan(off.nse)
    assert stats(np.full(3, 20.0), np.zeros(3)).nse == 1.0


def test_phase_cells_rank_worst_first_by_rmse_over_the_channels_spread():
    """compare's worst phases: each (channel, phase) cell scored RMSE / std(measured channel), so
    kelvin and micrometres compare; the largest first. temperature a (spread 2 K): 1.0 K in
    'spindle on' scores 0.5; probe X1 (spread 10 um): 3.0 um scores 0.3, then both 'off' cells
    0.05 (by raw RMSE the probe's 3.0 um would lead)."""
    from validate.channels import Phase
    from validate.compare import ChannelResult, CompareResult, Stats

    def channel(name, unit, spread, on, off):
        return ChannelResult(name, unit, Stats(on, on, 0.0, 2), spread, [Stats(on, on, 0.0, 1), Stats(off, off, 0.0, 1)])

    phases = [Phase("spindle", "spindle on", 0.0, 60.0), Phase("spindle", "spindle off", 60.0, 120.0, closed=True)]
    result = CompareResult([channel("temperature:a", "K", 2.0, 1.0, 0.1), channel("probe:X1", "um", 10.0, 3.0, 0.5)],
                           phases, None)
    cells = [(c.name, p.label, score) for c, p, _, score in result.phase_ranking()]
    assert cells[:2] == [("temperature:a", "spindle on", 0.5), ("probe:X1", "spindle on", 0.3)]
    assert [score for *_, score in cells[2:]] == pytest.approx([0.05, 0.05], rel=1e-15)


def test_a_repeated_time_is_refused_with_its_row():
    """Times must increase strictly: a log line written twice (0, 60, 60, 120 s) would give the
    phase detection's rates a zero step; refused naming the data row and both times."""
    from twin.io.times import check_times

    with pytest.raises(InputError) as err:
        check_times(np.array([0.0, 60.0, 60.0, 120.0]), "m.csv", "t")
    assert err.value.field == "t" and "time is not increasing at data row 3 (60 -> 60 s)" in str(err.value)

RUN1_CSV = ("minutes,rpm,room,T_motor,X1\n0,9000,20.1,20.06,0.0\n1,9000,20.1,20.13,0.0\n2,9000,20.2,20.25,0.1\n"
            "3,0,20.2,20.31,0.1\n4,0,20.2,20.31,0.1\n")
RUN1_COLUMNS = {"minutes": ('role = "time"', "min"), "rpm": ('role = "spindle_speed"', "rpm"),
                "room": ('role = "ambient_temperature"', "degC"),
                "T_motor": ('role = "temperature"\nsite = "motor"', "degC"),
                "X1": ('role = "probe"\nprobe = "X1"', "um")}


def _run1(tmp_path, column=None, header=None, unit=None):
    """README's run1.csv (five of its columns) and run1.toml, the column ``column`` headed
    ``header`` in the CSV and the mapping, with the mapping's unit ``unit``."""
    csv = tmp_path / "run1.csv"
    csv.write_text(RUN1_CSV.replace(column, header, 1) if column else RUN1_CSV)
    tables = ['machine = "cframe-vmc"']
    for name, (keys, default) in RUN1_COLUMNS.items():
        named = f'"{header}"' if name == column else name
        tables.append(f'[columns.{named}]\n{keys}\nunit = "{unit if name == column else default}"')
    (tmp_path / "run1.toml").write_text("\n".join(tables) + "\n")
    return csv, tmp_path / "run1.toml"


@pytest.mark.parametrize("column,header,unit,agreeing,message", [
    # the audit's run1.csv with 'minutes' renamed 't [min]' and a mapping in s: read as a 4 s log, rc 0
    ("minutes", "t [min]", "s", "min", "'s' contradicts the header of {csv}, 't [min]' (times in min)"),
    ("minutes", "t [h]", "min", "hr", "'min' contradicts the header of {csv}, 't [h]' (times in h)"),
    # a kelvin header under a degC mapping (kelvin is no temperature unit of the twin's: it says so)
    ("room", "room [K]", "degC", None,
     "'degC' contradicts the header of {csv}, 'room [K]' (temperatures in K; 'K' is not a unit of temperature"),
    ("X1", "X1 [mm]", "um", "mm", "'um' contradicts the header of {csv}, 'X1 [mm]' (values in mm)"),
])
def test_a_header_unit_that_contradicts_the_mapping_is_refused(tmp_path, capsys, column, header, unit, agreeing,
                                                                message):
    """A unit in a CSV header cell ('t [min]') and the mapping's unit for that column must agree,
    as an effect schedule's header and its time_unit must (one check: twin.io.csv_header.
    unit_contradiction): else one error naming the mapping, the column's unit key, the CSV and
    the header cell, and twin compare exits 2. The mapping in the header's unit (any spelling of
    it: 'h' and 'hr') reads."""
    from twin.cli import main

    csv, mapping = _run1(tmp_path, column, header, unit)
    with pytest.raises(InputError) as err:
        read_measurement(csv)
    key = f"columns.{header}.unit"
    assert (err.value.source, err.value.field) == (str(mapping), key), str(err.value)
    assert err.value.message.startswith(message.format(csv=csv)), err.value.message
    assert main(["compare", str(csv)]) == 2
    assert f"error: {mapping}: {key}: {message.format(csv=csv)}" in capsys.readouterr().err
    if agreeing:
        meas = read_measurement(_run1(tmp_path, column, header, agreeing)[0])
        np.testing.assert_allclose(meas.time.values, np.arange(5.0) * (3600.0 if header == "t [h]" else 60.0))
        if column == "X1":
            np.testing.assert_allclose(meas.probe.sel(probe_id="X1").values, [0, 0, 100, 100, 100], atol=1e-9)


def test_csv_time_errors_name_the_line_an_editor_shows(tmp_path):
    """Every CSV error names the file's line (header line 1, blank lines counted), the time
    column's too: a blank line after the first data row and a repeated time on line 5 said
    'data row 3'; a gap names the line it ends on."""
    lines = RUN1_CSV.splitlines()
    csv, _ = _run1(tmp_path)
    csv.write_text("\n".join(lines[:2] + [""] + lines[2:3] + [lines[2]] + lines[4:]) + "\n")
    assert csv.read_text().splitlines()[4] == lines[2]        # the repeat is line 5
    with pytest.raises(InputError) as err:
        read_measurement(csv)
    assert (err.value.field, err.value.message) == ("minutes", "time is not increasing at line 5 (60 -> 60 s)")
    csv.write_text("\n".join(lines[:4] + ["", lines[4].replace("3,", "30,", 1), lines[5].replace("4,", "31,", 1)])
                   + "\n")
    with pytest.raises(InputError) as err:
        read_measurement(csv)
    assert (err.value.field, err.value.message) == (
        "minutes", "line 6: gap of 1680 s after t = 120 s (more than 3 x the median interval 60 s)")


def test_compare_with_itself_is_perfect(sim):
    r = compare(sim, sim, model_true=False)
    assert float(np.abs(r.residuals.residual).max()) == 0.0
    for c in r.channels:
        assert c.stats.rmse == 0.0 and c.stats.max_abs == 0.0 and c.stats.nse == 1.0
    assert len(r.channels) == 16 + 5 + 2
    assert "temperature:motor" in format_compare(r)


def test_known_offset_gives_rmse_equal_offset(sim):
    shifted = sim.copy(deep=True)
    shifted["temperature"] = shifted.temperature_true + 0.3
    shifted["probe"] = shifted.probe_true - 2.0
    r = compare(shifted, sim)
    for c in r.channels:
        if c.name.startswith("temperature:"):
            assert c.stats.rmse == pytest.approx(0.3) and c.stats.max_abs == pytest.approx(0.3)
        elif c.name.startswith("probe:"):
            assert c.stats.rmse == pytest.approx(2.0)
    ph = r.channel("temperature:motor").phases
    assert all(s.rmse == pytest.approx(0.3) for s in ph if s.n)
    # NSE = 1 - n c^2 / sum (m - mean)^2 for a constant offset c
    m = shifted.temperature.sel(sensor="motor").values
    assert r.channel("temperature:motor").stats.nse == pytest.approx(1 - len(m) * 0.09 / np.sum((m - m.mean()) ** 2))
    assert r.ranking()[0].name.startswith("temperature:")  # a 0.3 K offset hurts the flat sensors most


def test_stats_closed_form():
    s = stats(np.array([1.0, 2.0, 3.0]), np.array([0.0, 1.0, -1.0]))
    assert s.rmse == pytest.approx(np.sqrt(2 / 3)) and s.max_abs == 1.0 and s.nse == pytest.approx(0.0)


def _bad(tmp_path, sim, match, **kw):
    with pytest.raises(InputError, match=match) as err:
        read_measurement(write_csv(tmp_path, sim, **kw))
    return err.value


def test_errors_name_file_and_column(tmp_path, sim):
    e = _bad(tmp_path, sim, "not mapped", extra_col=True)
    assert e.source.endswith("m.csv") and e.field == "junk"
    e = _bad(tmp_path, sim, "does not fit", unit_T="rpm")
    assert e.source.endswith("m.toml") and e.field == "columns.T_motor.unit"

    def nan(d):
        d[5, 3] = np.nan
    e = _bad(tmp_path, sim, "NaN", mutate=nan)
    assert e.field == "T_motor"

    def backwards(d):
        d[10, 0] = d[8, 0]
    assert _bad(tmp_path, sim, "not increasing", mutate=backwards).field == "t"

    def gap(d):
        d[20:, 0] += 10.0  # 10 min jump with 1 min logging
    assert _bad(tmp_path, sim, "gap", mutate=gap).field == "t"


def test_mapping_errors(tmp_path, sim):
    csv = write_csv(tmp_path, sim)
    toml = (tmp_path / "m.toml").read_text()
    (tmp_path / "m.toml").write_text(toml + '[columns.ghost]\nrole = "temperature"\nsite = "motor"\nunit = "degC"\n')
    with pytest.raises(InputError, match="no such column") as err:
        read_measurement(csv)
    assert err.value.field == "columns.ghost"
    (tmp_path / "m.toml").write_text(toml.replace('site = "motor"', 'site = "nowhere"'))
    with pytest.raises(InputError, match="no sensor site"):
        read_measurement(csv)
    (tmp_path / "m.toml").write_text(toml.replace('role = "spindle_speed"', 'role = "speeed"'))
    with pytest.raises(InputError, match="unknown role"):
        read_measurement(csv)
    (tmp_path / "m.toml").unlink()
    with pytest.raises(InputError, match="no column mapping"):
        read_measurement(csv)


SMALL_CSV = "min,rpm,T\n0,9000,20.0\n1,9000,20.1\n2,9000,20.2\n3,0,20.3\n"
SMALL_MAP = ('machine = "cframe-vmc"\n[columns.min]\nrole = "time"\nunit = "min"\n[columns.rpm]\n'
             'role = "spindle_speed"\nunit = "rpm"\n[columns.T]\nrole = "temperature"\nsite = "motor"\nunit = "degC"\n')
GANTRY_CSV = "min,c_rpm,F1\n0,2500,0.0\n1,2500,1.0\n2,0,2.0\n3,0,2.5\n"
GANTRY_MAP = ('machine = "gantry-ram"\n[columns.min]\nrole = "time"\nunit = "min"\n[columns.c_rpm]\n'
              'role = "c_axis_speed"\nunit = "rpm"\n[columns.F1]\nrole = "strain"\ngauge = "FBG-1"\nunit = "ppm"\n')


@pytest.mark.parametrize("csv,mapping,source,message", [
    # a misspelled key is named, not its correct sibling reported missing (or "unknown role None")
    (SMALL_CSV, SMALL_MAP.replace('role = "time"', 'rol = "time"'), "m.toml",
     "columns.min.rol: unknown key (known: axis, duty, gauge, laser, name, part, probe, reading, role, site, start, "
     "unit, x, y, z)"),
    (SMALL_CSV, SMALL_MAP.replace('unit = "min"', 'unit = "min"\nsight = "motor"'), "m.toml",
     "columns.min.sight: unknown key for role time (known: role, unit)"),
    (SMALL_CSV, SMALL_MAP.replace('role = "time"', 'role = true'), "m.toml",
     "columns.min.role: unknown role the boolean true; known: time"),
    (SMALL_CSV, SMALL_MAP.replace('machine', 'machin'), "m.toml",
     "machin: unknown key (known: columns, machine)"),
    # a missing key in words, not "got None"
    (GANTRY_CSV, GANTRY_MAP, "m.toml", 'columns.F1.reading: missing; expected "compensated"'),
    # an infinite cell is not finite, not "missing/NaN"
    (SMALL_CSV.replace("20.1", "inf"), SMALL_MAP, "m.csv", "T: line 3: not finite (inf)"),
    (SMALL_CSV.replace("20.1", "nan"), SMALL_MAP, "m.csv", "T: 1 missing/NaN value(s), first at line 3"),
])
def test_mapping_and_cell_errors_name_the_key_in_words(tmp_path, csv, mapping, source, message):
    (tmp_path / "m.csv").write_text(csv)
    (tmp_path / "m.toml").write_text(mapping)
    with pytest.raises(InputError) as err:
        read_measurement(tmp_path / "m.csv")
    assert str(err.value).startswith(f"{tmp_path / source}: {message}"), str(err.value)
    assert "None" not in str(err.value) and "True" not in str(err.value)


def test_compare_command_on_csv(tmp_path, sim, capsys):
    """The ``twin compare`` subcommand as the CLI wires it (add_compare_parser -> run_compare)."""
    import argparse

    from validate.compare_cli import add_compare_parser

    parser = argparse.ArgumentParser(prog="twin")
    add_compare_parser(parser.add_subparsers(dest="command", required=True))
    csv = write_csv(tmp_path, sim)
    args = parser.parse_args(["compare", str(csv), "--machine", "cframe-vmc", "--mesh", "coarse"])
    assert args.func(args) == 0
    out = capsys.readouterr().out
    assert "temperature:motor" in out and "worst channels" in out and "spindle on 9000 rpm" in out
    args = parser.parse_args(["compare", str(tmp_path / "missing.csv")])
    with pytest.raises(InputError, match="no such measurement file"):
        args.func(args)


def test_compare_table_stays_aligned_with_long_channel_names():
    """A sensor name longer than the default column keeps every row's numbers in one column."""
    from validate.compare import ChannelResult, CompareResult

    def channel(name, rmse):
        return ChannelResult(name, "K", stats(np.array([1.0, 2.0, 3.0]), np.array([rmse, -rmse, rmse])), 1.0, [])

    long = "temperature:" + "x" * 40
    r = CompareResult([channel("temperature:motor", 0.5), channel(long, 0.2)], [], None)
    rows = [ln for ln in format_compare(r).splitlines() if ln.startswith("temperature:")]
    assert len({row.index(" K ") for row in rows}) == 1
    ranked = [ln for ln in format_compare(r).splitlines() if ln.startswith("  1.") or ln.startswith("  2.")]
    assert len(ranked) == 2 and len({len(ln) for ln in ranked}) == 1


def _noise_free(ds):
    """``ds`` with its measured temperatures replaced by the noise-free ones (exact offsets)."""
    out = ds.copy(deep=True)
    out["temperature"] = out.temperature_true.copy()
    return out


def test_residual_sign_is_measured_minus_model(sim):
    """Module docstring: r_i = m_i - y_i (measured minus model). A model that reads every
    temperature 0.3 K above the measurement gives r = m - (m + 0.3) = -0.3 K at every instant."""
    measured = _noise_free(sim)
    model = sim.copy(deep=True)
    model["temperature_true"] = model.temperature_true + 0.3
    r = compare(measured, model)
    res = r.residuals.residual.sel(channel="temperature:motor").values
    np.testing.assert_allclose(res, np.full(res.size, -0.3), rtol=0, atol=1e-9)
    assert r.channel("temperature:motor").stats.rmse == pytest.approx(0.3, rel=1e-9)


def test_spread_is_population_std_and_normalises_the_rmse(sim):
    """spread = std(m) with ddof 0: sqrt(sum (m_i - mean m)^2 / n); normalised RMSE = RMSE / spread,
    here 0.3 / spread for a constant 0.3 K offset."""
    measured = _noise_free(sim)
    model = sim.copy(deep=True)
    model["temperature_true"] = model.temperature_true + 0.3
    c = compare(measured, model).channel("temperature:motor")
    m = measured.temperature.sel(sensor="motor").values.astype(float)
    spread = np.sqrt(np.sum((m - m.sum() / m.size) ** 2) / m.size)
    assert c.spread == pytest.approx(spread, rel=1e-12)
    assert c.normalised_rmse == pytest.approx(0.3 / spread, rel=1e-9)


def test_a_measurement_logged_from_a_later_start_compares_the_same(sim):
    """Both axes count from their first sample: t_model = t - t[0] + t_model[0]. A measurement whose
    clock starts at 3600 s (every time + 3600 s) gives the same residuals and statistics as the
    same measurement from 0 s, and no error (its span equals the model's)."""
    measured = _noise_free(sim)
    model = sim.copy(deep=True)
    model["temperature_true"] = model.temperature_true + 0.3
    late = measured.assign_coords(time=("time", measured.time.values + 3600.0, measured.time.attrs))
    a, b = compare(measured, model), compare(late, model)
    np.testing.assert_allclose(b.residuals.residual.values, a.residuals.residual.values, rtol=0, atol=1e-12)
    for ca, cb in zip(a.channels, b.channels):
        assert cb.name == ca.name
        assert cb.stats.rmse == pytest.approx(ca.stats.rmse, rel=1e-12, abs=1e-15)
        assert cb.spread == pytest.approx(ca.spread, rel=1e-12)
    assert b.channel("temperature:motor").stats.rmse == pytest.approx(0.3, rel=1e-9)


def test_tilt_residuals_are_in_microradians():
    """GROUPS["tilt"] = ("rotation", "urad"): a tilt residual's unit is urad, and stacking a result's
    tilt (rotations A, B) gives two channels, each in urad (not um, the probes' unit)."""
    from tests.fuzz_files import result_dataset
    from validate.channels import residual_unit, stack

    assert residual_unit("tilt") == "urad"
    ch = stack(result_dataset(), ("tilt",))
    assert ch.names == ["tilt:A", "tilt:B"]
    assert ch.units == ["urad", "urad"]


def test_ambient_flat_after_a_rise_is_steady_not_falling():
    """Room air rising 1 K/h (2.8e-4 K/s > 0.1 K/h threshold) for 3 h, then flat (rate 0) for 3 h,
    sampled every 60 s: rate 0 is neither above 0.1 K/h nor below -0.1 K/h, so the phases are
    ["ambient rising", "ambient steady"] (no "falling": the flat stretch's rate is not < -0.1 K/h)."""
    t = np.arange(0, 6 * 3600 + 1, 60.0)
    amb = 20.0 + np.minimum(t, 3 * 3600) / 3600.0
    ph = detect_phases(t, None, amb)
    assert [p.label for p in ph if p.kind == "ambient"] == ["ambient rising", "ambient steady"]


def _read_written(folder, stem, csv, mapping):
    """The measurement ``stem.csv`` with its mapping ``stem.toml``, written into ``folder`` and read."""
    (folder / f"{stem}.csv").write_text(csv)
    (folder / f"{stem}.toml").write_text(mapping)
    return read_measurement(folder / f"{stem}.csv")


def test_probe_laser_and_strain_readings_are_nulled_at_the_first_sample(tmp_path):
    """The module doc of twin/io/measurement.py: probe, laser and strain readings are zeroed at the
    first sample (the probes are nulled at the start, as the twin's are; its strains are changes
    from a zero-strain start). A log whose probe starts at 5 um reads 0, 0.5, 1.5 um: its changes,
    not its offset, which would otherwise read as 5 um of drift at t = 0; likewise a laser from
    2 mm and a gauge from 100 um/m."""
    def column(name, role, unit, **keys):
        extra = "".join(f'{k} = "{v}"\n' for k, v in keys.items())
        return f'[columns.{name}]\nrole = "{role}"\nunit = "{unit}"\n{extra}'

    time = column("min", "time", "min")
    meas = _read_written(tmp_path, "m", "min,pX1,T\n0,5.0,20.0\n1,5.5,20.1\n2,6.5,20.2\n",
                         'machine = "cframe-vmc"\n' + time + column("pX1", "probe", "um", probe="X1")
                         + column("T", "temperature", "degC", site="motor"))
    np.testing.assert_allclose(meas.probe.sel(probe_id="X1").values, [0.0, 0.5, 1.5], atol=1e-12)
    meas = _read_written(tmp_path, "g", "min,lz,F1\n0,2.0,100\n1,2.001,101\n2,2.003,103\n",
                         'machine = "gantry-ram"\n' + time + column("lz", "laser", "mm", laser="Z")
                         + column("F1", "strain", "ppm", gauge="FBG-1", reading="compensated"))
    np.testing.assert_allclose(meas.laser.sel(laser_id="Z").values, [0.0, 1.0, 3.0], atol=1e-9)
    np.testing.assert_allclose(meas.strain.sel(gauge="FBG-1").values, [0.0, 1.0, 3.0], atol=1e-9)


def test_a_time_gap_of_three_median_steps_is_kept_and_a_longer_one_refused():
    """check_times (twin/io/measurement.py): a record may pause for up to three median sampling
    intervals; a gap of more is refused (a logger that stopped). The boundary is inclusive: 1 s
    sampling with a 3 s gap passes, a 3.01 s gap is refused, naming where and the median."""
    from twin.io.times import check_times

    check_times(np.array([0.0, 1.0, 2.0, 3.0, 4.0, 7.0]), "m.csv", "t")          # exactly 3 x the median
    check_times(np.array([0.0, 1.0, 2.0, 3.0, 4.0, 6.99]), "m.csv", "t")
    with pytest.raises(InputError) as err:
        check_times(np.array([0.0, 1.0, 2.0, 3.0, 4.0, 7.01]), "m.csv", "t")
    assert err.value.field == "t"
    assert err.value.message == "gap of 3.01 s after t = 4 s (more than 3 x the median interval 1 s)"


def test_a_speed_within_the_tolerance_of_zero_is_a_stop():
    """speed_steps: a step whose median speed lies within ``tolerance`` (50 rpm by default) of
    0 is a stop, 0 rpm (a run-down residue or an encoder's jitter at rest is no spindle load);
    the boundary is inclusive: 49.9 and 50 rpm are 0, 50.1 rpm is kept, and a larger tolerance
    moves the boundary with it."""
    t = np.arange(4) * 60.0
    for n, expected in ((49.9, 0.0), (50.0, 0.0), (50.1, 50.1)):
        assert speed_steps(t, np.full(4, n)) == [(0.0, 180.0, expected)]
    assert speed_steps(t, np.full(4, 80.0), tolerance=100.0)[0][2] == 0.0
    assert speed_steps(t, np.full(4, 80.0), tolerance=50.0)[0][2] == 80.0
    run_down = np.array([0.0, 3000.0, 3000.0, 30.0])
    assert [s[2] for s in speed_steps(t, run_down)] == [0.0, 3000.0, 0.0]
