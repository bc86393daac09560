"""Limits of the measurement column mapping and of several measurements in one diagnosis: a
temperature column is placed at a named site or at a position, never both; its sensor name is a
non-empty string without '@', ':' or ','; two measurements of the same file name in different
folders get labels that tell them apart, so every channel of a diagnosis is distinct."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from tests.fuzz_files import MAPPING, measurement_csv
from twin.cli import build_parser, main
from twin.errors import InputError
from twin.io.measurement import read_measurement
from validate.inputs import load_measurements, measurement_labels

SIDE = 'site = "column_side"'


@pytest.fixture(scope="module")
def csv_text():
    return measurement_csv()


def _write(folder, csv_text, mapping=MAPPING):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "m.csv").write_text(csv_text)
    (folder / "m.toml").write_text(mapping)
    return folder / "m.csv"


@pytest.mark.parametrize("extra, field", [
    ('x = "0 m"', "x"), ('y = "0 m"', "y"), ('z = "1 m"', "z"), ('part = "bed"', "part"),
    ('name = ""', "name"), ('name = 3', "name"), ('name = "a@b.csv"', "name"), ('name = "a:b"', "name"),
    ('name = "a,b"', "name"),
])
def test_bad_temperature_column_is_refused(tmp_path, csv_text, extra, field):
    path = _write(tmp_path, csv_text, MAPPING.replace(SIDE, SIDE + "\n" + extra))
    with pytest.raises(InputError) as err:
        read_measurement(path)
    text = str(err.value)
    assert f"columns.T_column_side.{field}" in text and "m.toml" in text


def test_site_and_position_cli_exit_2(tmp_path, csv_text, capsys):
    path = _write(tmp_path, csv_text, MAPPING.replace(SIDE, SIDE + '\nz = "1 m"'))
    before = sorted(p.name for p in tmp_path.iterdir())
    assert main(["compare", str(path), "--mesh", "coarse"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {tmp_path / 'm.toml'}: columns.T_column_side.z: ")
    assert "site or a position" in err[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_good_sensor_name_is_kept(tmp_path, csv_text):
    path = _write(tmp_path, csv_text, MAPPING.replace(SIDE, SIDE + '\nname = "side wall"'))
    ds = read_measurement(path)
    assert "side wall" in list(ds.sensor.values)


def test_labels_unique():
    assert measurement_labels(["a/m.csv", "b/m.csv"]) == ["a/m.csv", "b/m.csv"]
    assert measurement_labels(["m.csv", "n.csv"]) == ["m.csv", "n.csv"]
    labels = measurement_labels(["x/a/m.csv", "y/a/m.csv", "b/m.csv", "c.csv"])
    assert labels == ["x/a/m.csv", "y/a/m.csv", "b/m.csv", "c.csv"]


def test_same_file_name_in_two_folders_keeps_every_channel(tmp_path, csv_text, monkeypatch):
    """``twin diagnose a/m.csv b/m.csv``: the runs' labels differ, so the diagnosis' channels
    (``channel@label``, :meth:`validate.evidence.Evidence.channel_names`) are all distinct."""
    from validate.evidence import Evidence
    _write(tmp_path / "a", csv_text)
    _write(tmp_path / "b", csv_text + "\n")     # another file (a byte copy is one run twice: refused)
    monkeypatch.chdir(tmp_path)
    args = build_parser().parse_args(["diagnose", "a/m.csv", "b/m.csv", "--error-mesh", "none", "--no-parameters"])
    runs, _, _, _ = load_measurements(args)
    assert [label for label, _, _ in runs] == ["a/m.csv", "b/m.csv"]
    records = []
    for label, ds, _ in runs:
        chans = [f"temperature:{s}" for s in ds.sensor.values] + [f"probe:{p}" for p in ds.probe_id.values]
        records.append(SimpleNamespace(label=label, channels=chans, measured=np.zeros((2, len(chans)))))
    names = Evidence(records).channel_names()
    per_run = len(records[0].channels)
    assert per_run == 8 and len(names) == 2 * per_run == len(set(names))
    assert "probe:Z@a/m.csv" in names and "probe:Z@b/m.csv" in names


@pytest.mark.parametrize("option,message", [
    ("--mapping", "applies to a single measurement; give each CSV its own mapping next to it"),
    ("--scenario", "applies to a single measurement; leave it out (each measurement drives the twin by its own "
                   "logged inputs) or diagnose one measurement at a time"),
])
def test_mapping_or_scenario_with_two_measurements_names_its_own_option(tmp_path, csv_text, capsys, option,
                                                                         message):
    """``twin diagnose a.csv b.csv --scenario s.toml`` speaks of the scenario, not of mappings."""
    _write(tmp_path / "a", csv_text)
    _write(tmp_path / "b", csv_text)
    (tmp_path / "s.toml").write_text('name = "s"\nsample_interval = "60 s"\n[ambient]\ntemperature = "20 degC"\n'
                                     '[[spindle]]\nspeed = "6000 rpm"\nduration = "60 min"\n')
    given = tmp_path / ("a/m.toml" if option == "--mapping" else "s.toml")
    assert main(["diagnose", str(tmp_path / "a/m.csv"), str(tmp_path / "b/m.csv"), option, str(given),
                 "--error-mesh", "none", "--no-parameters"]) == 2
    assert capsys.readouterr().err == f"error: command line: {option}: {message}\n"


def test_a_result_with_sensors_on_the_feed_drive_reads_as_a_measurement(tmp_path):
    """A twin result of a feed-drive scenario places sensors on the drive's parts (the Y screw's
    bearings), which the bare machine lacks: read back as a measurement it is placed on the machine
    with its feed drives, as a mapping's site is; a point off every part is still refused."""
    from geometries import build_machine
    from geometries.axes import with_feed_drives
    from tests.fuzz_files import netcdf_bytes, result_dataset

    p = with_feed_drives(build_machine("cframe-vmc")).point("Y_front_bearing")
    ds = result_dataset().assign_coords(sensor=["motor", "column_side", "Y_front_bearing"],
                                        x=("sensor", [*result_dataset().x.values[:2], p.xyz[0]]),
                                        y=("sensor", [*result_dataset().y.values[:2], p.xyz[1]]),
                                        z=("sensor", [*result_dataset().z.values[:2], p.xyz[2]]),
                                        part=("sensor", [*result_dataset().part.values[:2], p.part]))
    assert p.part == "y_front_bearing"
    (tmp_path / "r.nc").write_bytes(netcdf_bytes(ds))
    assert list(read_measurement(tmp_path / "r.nc").sensor.values)[-1] == "Y_front_bearing"
    (tmp_path / "off.nc").write_bytes(netcdf_bytes(ds.assign_coords(x=("sensor", [*ds.x.values[:2], 5.0]))))
    with pytest.raises(InputError, match="Y_front_bearing"):
        read_measurement(tmp_path / "off.nc")


def test_surface_grid_names_read_back_but_at_signs_do_not(tmp_path):
    """A dataset case's surface-grid sensors are named part:face:u:v (twin.observe.sensor_grid):
    a NetCDF measurement allows ':' (the channel temperature:<name> keeps the name whole), while
    '@' (the diagnosis's measurement suffix) and ',' stay refused, as in a mapping."""
    from tests.fuzz_files import netcdf_bytes, result_dataset
    from validate.channels import split

    names = ["motor", "column:+x:0.015:1.175", "bed_front"]
    (tmp_path / "g.nc").write_bytes(netcdf_bytes(result_dataset().assign_coords(sensor=names)))
    assert list(read_measurement(tmp_path / "g.nc").sensor.values) == names
    assert split("temperature:" + names[1]) == ("temperature", names[1])
    for bad in ("a@b", "a,b"):
        (tmp_path / "b.nc").write_bytes(netcdf_bytes(result_dataset().assign_coords(sensor=[bad, *names[1:]])))
        with pytest.raises(InputError, match="sensor"):
            read_measurement(tmp_path / "b.nc")


def test_a_result_whose_scenario_moved_an_axis_needs_its_scenario(tmp_path):
    """A twin result of a scenario with axis motion records the moved axes (``moved_axes``) but not
    the moves (strokes faster than its samples): driven from the file alone the twin would run
    another machine (the ram standing: the gantry's own Z-axis test compared with itself left
    T5 5.9 K off), so compare asks for the scenario instead, and runs with it."""
    from tests.fuzz_files import netcdf_bytes, result_dataset
    from twin.io.measured_inputs import scenario_from_measurement

    ds = result_dataset().assign_attrs(moved_axes="Y", scenario="seed003-exp1")
    (tmp_path / "r.nc").write_bytes(netcdf_bytes(ds))
    meas = read_measurement(tmp_path / "r.nc")
    with pytest.raises(InputError) as err:
        scenario_from_measurement(meas)
    assert err.value.field == "axis_position" and "--scenario seed003-exp1" in err.value.message
    assert str(tmp_path / "r.nc") in err.value.source
    assert scenario_from_measurement(result_dataset()).axes == ()        # a spindle result drives itself


def test_simulate_records_the_axes_its_scenario_moved():
    from twin.api import simulate
    from twin.scenario import scenario_from_dict

    sc = scenario_from_dict({"name": "y", "sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
                             "spindle": [{"speed": "0 rpm", "duration": "4 min"}],
                             "axis": [{"name": "Y", "move": [{"kind": "hold", "position": "140 mm",
                                                               "duration": "4 min"}]}]}, "y.toml")
    ds, _ = simulate("cframe-vmc", sc, resolution="coarse")
    assert ds.attrs["moved_axes"] == "Y"
    assert "moved_axes" not in simulate("cframe-vmc", scenario_from_dict(
        {"name": "s", "sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
         "spindle": [{"speed": "0 rpm", "duration": "4 min"}]}, "s.toml"), resolution="coarse")[0].attrs


def test_a_log_from_its_own_clock_is_reported_on_that_clock(tmp_path, capsys):
    """A log whose time starts at 08:00 (28800 s): the twin runs from its first sample, and compare
    and diagnose both report the phases on the log's clock (diagnose counted them from 0)."""
    import json

    def at_eight(cols):
        cols["t_s"] = cols["t_s"] + 28800.0

    path = _write(tmp_path, measurement_csv(at_eight))
    assert main(["compare", str(path), "--mesh", "coarse"]) == 0
    assert "8.00 h .." in capsys.readouterr().out
    report = tmp_path / "d.json"
    assert main(["diagnose", str(path), "--mesh", "coarse", "--error-mesh", "none", "--no-parameters",
                 "--json", str(report)]) == 0
    phases = json.loads(report.read_text())["phases"]
    spindle = [p for p in phases if p["kind"] == "spindle"]
    assert spindle[0]["start_s"] == 28800.0 and spindle[0]["end_s"] == 28800.0 + 600.0


def test_a_measurement_of_another_machine_or_unit_or_span_is_refused(tmp_path, capsys):
    """API audit: a NetCDF measurement is read as a twin result, so a variable in another unit
    (probes in mm were read as um) is refused; compare refuses a model of another machine or
    one shorter than the measurement (it held the model flat past its end); diagnose refuses a
    measurement of another machine (it gave a verdict)."""
    from tests.fuzz_files import result_dataset
    from geometries import build_machine
    from validate.compare import compare
    from validate.diagnose import diagnose

    ds = result_dataset()
    ds["probe"].attrs["units"] = "mm"
    ds.to_netcdf(tmp_path / "mm.nc")
    with pytest.raises(InputError, match="probe: in 'mm'"):
        read_measurement(tmp_path / "mm.nc")
    ds["probe"].attrs["units"] = "um"
    # every variable a result writes, read by every command that reads a result (it reported a
    # drift in mm and a tilt in mrad 1000 times too small, a temperature in K as degC)
    for var, unit in (("probe_drift", "mm"), ("drift", "mm"), ("tilt", "mrad"), ("tilt_true", "mrad"),
                      ("temperature", "K")):
        bad = ds.copy(deep=True)
        bad[var].attrs["units"] = unit
        _refused_by_every_reader(bad, f"{var}: in '{unit}'", tmp_path, capsys)
    other = ds.assign_attrs(machine="belt-vmc")
    with pytest.raises(InputError, match="the measurement is of machine 'belt-vmc', the model of 'cframe-vmc'"):
        compare(other, ds)
    with pytest.raises(InputError, match="time: the measurement spans"):
        compare(ds, ds.isel(time=slice(0, len(ds.time) // 2)))
    with pytest.raises(InputError, match="machine: the measurement is of machine 'belt-vmc'"):
        diagnose(other, build_machine("cframe-vmc"), None)


def test_a_netcdf_variable_without_its_unit_is_refused(tmp_path, capsys):
    """A result's variable that states no unit cannot be told from one in mm or in K: every reader
    of a result refuses it naming the variable (plot and report read it as the twin's unit before),
    as `twin learn` already did."""
    from tests.fuzz_files import result_dataset

    for var in ("time", "drift", "probe_drift", "temperature"):
        bad = result_dataset()
        del bad[var].attrs["units"]
        _refused_by_every_reader(bad, f"{var}: states no unit", tmp_path, capsys)


def _refused_by_every_reader(bad, needle: str, tmp_path, capsys) -> None:
    """``bad`` written as u.nc is refused with ``needle`` by the reader and by report, plot and
    compare: one line, exit 2, no output."""
    bad.to_netcdf(tmp_path / "u.nc")
    with pytest.raises(InputError, match=needle):
        read_measurement(tmp_path / "u.nc")
    for argv in (["report", "iso230-3", str(tmp_path / "u.nc"), "-o", str(tmp_path / "rep")],
                 ["plot", str(tmp_path / "u.nc"), "-o", str(tmp_path / "u.png")],
                 ["compare", str(tmp_path / "u.nc"), "--mesh", "coarse"]):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f"u.nc: {needle}" in err, (argv, err)
    assert not (tmp_path / "rep").exists() and not (tmp_path / "u.png").exists()


def test_a_diagnosis_error_names_the_measurement_as_typed(tmp_path, csv_text, capsys, monkeypatch):
    """The diagnosis names each measurement by its label (its file name, or the shortest tail of
    its path that tells it from the others: ``a/m.csv``); an error raised inside it named that
    label, not the file the user typed. The CLI names the path as given, and a plain ValueError
    names every measurement."""
    import validate.diagnose

    a, b = _write(tmp_path / "x" / "a", csv_text), _write(tmp_path / "x" / "b", csv_text + "\n")   # not a byte copy

    def fails(runs, *args, **kwargs):
        assert [label for label, _, _ in runs] == ["a/m.csv", "b/m.csv"]
        raise InputError("b/m.csv", "channels", "refused inside the diagnosis")

    monkeypatch.setattr(validate.diagnose, "diagnose_many", fails)
    assert main(["diagnose", str(a), str(b), "--mesh", "coarse", "--error-mesh", "none", "--no-parameters"]) == 2
    assert capsys.readouterr().err.strip() == f"error: {b}: channels: refused inside the diagnosis"

    def fails_plainly(runs, *args, **kwargs):
        raise ValueError("measurement times lie outside the scenario's duration")

    monkeypatch.setattr(validate.diagnose, "diagnose_many", fails_plainly)
    assert main(["diagnose", str(a), str(b), "--mesh", "coarse", "--error-mesh", "none", "--no-parameters"]) == 2
    assert capsys.readouterr().err.strip() == f"error: {a} {b}: time: measurement times lie outside the scenario's duration"
