"""The input/output layer (twin/io/, twin/units.py) held to what the README promises, one test per
behaviour that a mutation audit of the layer found untested: a check dropped, a comparison
flipped or a unit changed there left every other test passing. Each test is small (files in
tmp_path, no simulation) and says in its docstring which behaviour it holds."""

from __future__ import annotations

import json
import os
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr

from tests.fuzz_files import GANTRY_MAPPING, MAPPING, gantry_csv, measurement_csv, result_dataset
from twin.errors import InputError


def _error(call) -> InputError:
    with pytest.raises(InputError) as err:
        call()
    return err.value


def _measurement(folder: Path, csv: str, mapping: str, stem: str = "m") -> Path:
    (folder / f"{stem}.csv").write_text(csv, encoding="utf-8")
    (folder / f"{stem}.toml").write_text(mapping, encoding="utf-8")
    return folder / f"{stem}.csv"


def _nan_drift():
    ds = result_dataset()
    ds.drift[3, 0] = np.nan          # a variable no physical limit reads: only the finite check sees it
    return ds


# ------------------------------------------------------------------------------------- times
def test_a_nan_time_is_refused_naming_its_line():
    """twin/io/times.check_times: times are finite; a NaN time compares false with everything, so
    the increasing and gap checks let it through, and an ISO 230-3 evaluation or a model's time
    axis (which reach only this check) would compute with it. The error names the line."""
    from twin.io.times import check_times

    err = _error(lambda: check_times(np.array([0.0, 60.0, np.nan, 180.0]), "m.csv", "t", lines=[2, 3, 5, 6]))
    assert (err.source, err.field, err.message) == ("m.csv", "t", "line 5: not a finite number")


# ------------------------------------------------------------------ a measurement (CSV, Dataset)
def test_a_machine_on_the_command_line_must_be_the_mappings(tmp_path):
    """The mapping names machine cframe-vmc; read with machine belt-vmc (--machine, or Python's
    machine=) the measurement is refused naming the mapping and its key 'machine', never read
    silently as the other machine's (its sites and speed limits would be another machine's)."""
    from twin.io.measurement import read_measurement

    csv = _measurement(tmp_path, measurement_csv(), MAPPING)
    err = _error(lambda: read_measurement(csv, machine="belt-vmc"))
    assert (err.source, err.field) == (str(tmp_path / "m.toml"), "machine")
    assert err.message == "the mapping names machine 'cframe-vmc', the command line 'belt-vmc'"
    assert read_measurement(csv, machine="cframe-vmc").attrs["machine"] == "cframe-vmc"


def test_a_dataset_measurement_in_another_unit_is_refused():
    """check_measurement (a measurement given as a Dataset to compare or diagnose from Python) holds
    it to the twin's units as a NetCDF file is held: probes stated in mm would be read as um,
    1000 times too small. One error naming the variable and the unit it states."""
    from geometries import build_machine
    from twin.io.measurement import check_measurement

    ds = result_dataset()
    ds["probe"].attrs["units"] = "mm"
    err = _error(lambda: check_measurement(ds, build_machine("cframe-vmc"), "run.nc"))
    assert (err.source, err.field) == ("run.nc", "probe")
    assert err.message.startswith("in 'mm'; a NetCDF file is read as a twin result, which holds probe in 'um'")


def test_a_dataset_measurement_with_nan_in_any_variable_is_refused():
    """check_measurement checks every variable finite, not only those with a physical limit: a NaN
    in drift (which no limit reads) would score as NaN. The error names the variable and the time."""
    from geometries import build_machine
    from twin.io.measurement import check_measurement

    err = _error(lambda: check_measurement(_nan_drift(), build_machine("cframe-vmc"), "run.nc"))
    assert (err.source, err.field, err.message) == ("run.nc", "drift", "holds NaN or infinite values from t = 180 s")


def test_the_c_axis_duty_is_the_mappings_while_turning_and_zero_at_rest(tmp_path):
    """A logged C-axis speed with duty = 0.5: c_axis_duty [1] is 0.5 while the axis turns and 0 at
    rest (module doc of twin/io/measurement.py), not the mapping's duty at 0 rpm too."""
    from twin.io.measurement import read_measurement

    ds = read_measurement(_measurement(tmp_path, gantry_csv(), GANTRY_MAPPING, "g"))
    speed, duty = ds.c_axis_speed.values, ds.c_axis_duty.values
    assert ds.c_axis_duty.attrs["units"] == "1"
    assert (speed > 0).any() and (speed == 0).any()
    np.testing.assert_array_equal(duty, np.where(speed > 0, 0.5, 0.0))


# ------------------------------------------------------------ sensor names and positions in a mapping
def _with_name(name_line: str) -> str:
    assert 'site = "column_side"' in MAPPING
    return MAPPING.replace('site = "column_side"', 'site = "column_side"\n' + name_line, 1)


@pytest.mark.parametrize("toml_name, words", [
    ('name = "col\\tside"', "control characters"),          # a tab: a channel name no table can show
    ('name = " column"', "leading/trailing spaces"),         # ' column' and 'column' would be two sensors
])
def test_a_sensor_name_with_a_control_character_or_surrounding_blanks_is_refused(tmp_path, toml_name, words):
    """A mapping's sensor name is printable text without surrounding blanks (it becomes the channel
    name temperature:<name>): one error naming the mapping and the column's name key."""
    from twin.io.measurement import read_measurement

    csv = _measurement(tmp_path, measurement_csv(), _with_name(toml_name))
    err = _error(lambda: read_measurement(csv))
    assert (err.source, err.field) == (str(tmp_path / "m.toml"), "columns.T_column_side.name")
    assert words in err.message


def test_a_column_name_with_a_colon_is_no_sensor_name_without_name(tmp_path):
    """A temperature column at a position takes its column's name as the sensor's; a column
    'T:motor' would give a sensor name with ':' (which splits part from name in a channel): refused
    naming the column's table, with the advice to give name = "..."."""
    from twin.io.measurement import read_measurement

    at = ('[columns."T:motor"]\nrole = "temperature"\nx = "0 m"\ny = "-0.109 m"\nz = "1.7 m"\npart = "motor"\n'
          'unit = "degC"')
    mapping = MAPPING.replace('[columns.T_motor]\nrole = "temperature"\nsite = "motor"\nunit = "degC"', at, 1)
    assert at in mapping
    csv = _measurement(tmp_path, measurement_csv().replace("T_motor", "T:motor", 1), mapping)
    err = _error(lambda: read_measurement(csv))
    assert (err.source, err.field) == (str(tmp_path / "m.toml"), "columns.T:motor")
    assert err.message == "the sensor name 'T:motor' (from the column) may not contain ':'; give name = \"...\""


def test_a_logged_axis_position_half_a_millimetre_past_the_travel_is_refused(tmp_path):
    """Logged axis positions stay in the travel (Y: 0 .. 400 mm on cframe-vmc): 400.5 mm is refused
    naming the CSV and the column (the tolerance is round-off, not a millimetre)."""
    from twin.io.measurement import read_measurement

    lines = measurement_csv().splitlines()
    rows = [line + (",400.5" if i == 3 else ",140") for i, line in enumerate(lines[1:])]
    csv = _measurement(tmp_path, "\n".join([lines[0] + ",y_mm"] + rows) + "\n",
                       MAPPING + '[columns.y_mm]\nrole = "axis_position"\naxis = "Y"\nunit = "mm"\n')
    err = _error(lambda: read_measurement(csv))
    assert (err.source, err.field) == (str(csv), "y_mm")
    assert "400.5 mm is outside the Y travel 0 .. 400 mm" in err.message


def test_an_axis_logs_errors_name_the_line_an_editor_shows(tmp_path):
    """A logged axis position outside the travel, or a jump faster than MAX_FEED between two
    samples, names the CSV line (header line 1, blank lines counted), as every other CSV error
    does: with a blank line after the header the third data row is line 5 (it said 'row 3')."""
    from twin.io.measurement import read_measurement

    lines = measurement_csv().splitlines()
    mapping = MAPPING + '[columns.y_mm]\nrole = "axis_position"\naxis = "Y"\nunit = "mm"\n'
    rows = [line + (",900" if i == 2 else ",140") for i, line in enumerate(lines[1:])]
    csv = _measurement(tmp_path, "\n".join([lines[0] + ",y_mm", ""] + rows) + "\n", mapping)
    err = _error(lambda: read_measurement(csv))
    assert (err.source, err.field) == (str(csv), "y_mm")
    assert err.message.startswith("line 5: 900 mm is outside the Y travel"), err.message
    # a 200 mm jump in 10 ms arrives at the second sample: its line, or its data row without lines
    from geometries import build_machine
    from twin.io.axis_logs import check_log

    t, x = np.array([0.0, 0.01, 0.02]), np.array([0.0, 0.2, 0.2])
    for lines_, place in (([3, 5, 6], "line 5"), (None, "data row 2")):
        err = _error(lambda: check_log("Y", t, x, build_machine("cframe-vmc"), "m.csv", "y_mm", lines_))
        assert err.message.startswith(f"{place}: a feed between samples of 20 m/s"), err.message


def test_a_measurement_column_without_a_name_is_refused_naming_the_header(tmp_path):
    """A comma at the end of every line (a spreadsheet's export) makes an empty last column: refused
    on the CSV's ``header`` with the column's number, not as an unmapped column with an empty
    name and a [columns.] table to add."""
    from twin.io.measurement import read_measurement

    lines = measurement_csv().splitlines()
    csv = _measurement(tmp_path, "\n".join(line + "," for line in lines) + "\n", MAPPING)
    err = _error(lambda: read_measurement(csv))
    assert (err.source, err.field) == (str(csv), "header")
    assert err.message.startswith(f"column {len(lines[0].split(',')) + 1} has no name"), err.message


# ------------------------------------------------------------------------------ measurement writer
def test_the_room_air_is_written_to_a_tenth_of_a_millikelvin(tmp_path):
    """write_measurement writes temperatures to 1e-4 K, the room air too (its docstring): a room
    of 20.0123456 degC reads back within 5e-5 K, not rounded to 20.1."""
    from twin.io.measurement import read_measurement
    from twin.io.measurement_writer import write_measurement

    ds = result_dataset()
    air = 20.0 + 0.0123456 * np.arange(ds.sizes["time"])
    ds["ambient_temperature"] = ("time", air, {"units": "degC"})
    csv, _ = write_measurement(ds, tmp_path, "run", "cframe-vmc")
    np.testing.assert_allclose(read_measurement(csv).ambient_temperature.values, air, rtol=0, atol=5.1e-5)


def test_a_sensor_named_like_a_site_but_elsewhere_keeps_its_position(tmp_path):
    """A sensor named 'motor' (a site of cframe-vmc) that sits 2 mm beside the site is written with
    its name and position, not as site = "motor", which would read back at the site."""
    from twin.io.measurement import read_measurement
    from twin.io.measurement_writer import write_measurement

    ds = result_dataset()
    x = ds.x.values.copy()
    x[0] += 0.002
    ds = ds.assign_coords(x=("sensor", x))
    assert str(ds.sensor.values[0]) == "motor"
    csv, toml = write_measurement(ds, tmp_path, "run", "cframe-vmc")
    assert 'site = "motor"' not in toml.read_text(encoding="utf-8")
    back = read_measurement(csv)
    assert str(back.sensor.values[0]) == "motor"
    assert float(back.x.values[0]) == pytest.approx(x[0], abs=1e-12)


def test_a_stem_ending_in_csv_is_refused_and_nothing_is_written(tmp_path):
    """write_measurement(ds, folder, "run.csv", ...) would write run.csv.csv and run.csv.toml:
    refused naming 'stem', with the name to give instead, and no folder or file is made."""
    from twin.io.measurement_writer import write_measurement

    err = _error(lambda: write_measurement(result_dataset(), tmp_path / "out", "run.csv", "cframe-vmc"))
    assert (err.source, err.field) == ("write_measurement", "stem")
    assert err.message.startswith("'run.csv' ends in .csv: give the name without it ('run' writes run.csv")
    assert not (tmp_path / "out").exists()


# ---------------------------------------------------------------------------------- atomic writes
def test_a_write_that_fails_midway_leaves_the_old_file_whole(tmp_path):
    """atomic_write writes to a temporary file beside the target and renames it when whole: a
    writer that fails after half its bytes (a full disk) leaves the existing file as it was and
    no temporary file; the error names the file."""
    from twin.io.atomic import atomic_write

    target = tmp_path / "out.csv"
    target.write_text("old")

    def half(tmp):
        Path(tmp).write_text("par")
        raise OSError(28, "No space left on device")

    err = _error(lambda: atomic_write(target, half, "-o"))
    assert (err.source, err.field, err.message) == (str(target), "-o", "could not be written (No space left on device)")
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]


def test_a_target_that_became_a_pipe_while_writing_is_not_replaced(tmp_path):
    """The target is checked again right before the rename: a pipe made at its name while the
    file was being written is refused (never replaced) and the temporary file removed."""
    import stat

    from twin.io.atomic import atomic_write

    target = tmp_path / "out.nc"

    def write_then_pipe(tmp):
        Path(tmp).write_text("whole")
        os.mkfifo(target)

    err = _error(lambda: atomic_write(target, write_then_pipe, "-o"))
    assert (err.source, err.field) == (str(target), "-o") and "is a pipe" in err.message
    assert stat.S_ISFIFO(os.lstat(target).st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.nc"]


# -------------------------------------------------------------------------------- NetCDF results
def test_a_result_file_with_nan_in_any_variable_is_refused(tmp_path):
    """read_result refuses NaN or inf anywhere (README, Errors): a NaN in drift, which no physical
    limit reads, is named with the time it begins. Only a variable that declares nan_means may
    hold NaN."""
    from twin.io.results import read_result

    path = tmp_path / "r.nc"
    _nan_drift().to_netcdf(path, engine="h5netcdf")
    err = _error(lambda: read_result(path))
    assert (err.source, err.field, err.message) == (str(path), "drift", "holds NaN or infinite values from t = 180 s")


def test_write_netcdf_refuses_nan_and_writes_nothing(tmp_path):
    """write_netcdf never writes a Dataset holding NaN (called from Python, not only from simulate):
    one error naming the path and the variable, and no file or temporary file is left."""
    from twin.io.results import write_netcdf

    path = tmp_path / "r.nc"
    err = _error(lambda: write_netcdf(_nan_drift(), path))
    assert (err.source, err.field) == (str(path), "drift")
    assert list(tmp_path.iterdir()) == []


def test_a_result_of_one_sample_is_refused(tmp_path):
    """read_result needs at least two time samples (README: an increasing time of at least two
    samples); a file of one is named with its count."""
    from twin.io.results import read_result

    path = tmp_path / "r.nc"
    result_dataset(n=1).to_netcdf(path, engine="h5netcdf")
    err = _error(lambda: read_result(path))
    assert (err.source, err.field, err.message) == (str(path), "time", "1 sample(s); at least 2 are needed")


# ------------------------------------------------------------------------------- room-air record
def test_a_room_record_counts_time_from_its_first_row(tmp_path):
    """twin/io/room_csv: a log that starts at 10 h (600 min) is shifted to start at 0, in seconds."""
    from twin.io.room_csv import read_room_csv

    path = tmp_path / "room.csv"
    path.write_text("time [min],air [degC]\n600,18.0\n630,18.5\n660,19.0\n", encoding="utf-8")
    t, air = read_room_csv(path)
    np.testing.assert_array_equal(t, [0.0, 1800.0, 3600.0])
    np.testing.assert_array_equal(air, [18.0, 18.5, 19.0])


def test_a_room_records_repeated_time_names_the_line_an_editor_shows(tmp_path):
    """A time that does not increase is named by its line (header line 1, blank lines counted)."""
    from twin.io.room_csv import read_room_csv

    path = tmp_path / "room.csv"
    path.write_text("time [h],air [degC]\n0,20\n\n1,21\n1,22\n", encoding="utf-8")
    err = _error(lambda: read_room_csv(path))
    assert (err.source, err.field, err.message) == (str(path), "time", "time does not increase at line 5 (1 after 1 h)")


def test_a_room_records_nan_time_is_refused_with_its_line(tmp_path):
    """A cell 'nan' in the time column is not a finite number (NaN compares false, so the
    increasing check alone would let it through)."""
    from twin.io.room_csv import read_room_csv

    path = tmp_path / "room.csv"
    path.write_text("time [h],air [degC]\n0,20\nnan,21\n2,22\n", encoding="utf-8")
    err = _error(lambda: read_room_csv(path))
    assert (err.source, err.field, err.message) == (str(path), "time", "line 3: 'nan' is not a finite number")


# ------------------------------------------------------------------------------------ TOML tables
def test_a_step_speed_just_below_zero_is_refused():
    """TableReader.speed_step: a [[spindle]] or [[c_axis]] step's speed is not negative, by any
    amount: -0.5 rpm is refused naming the key."""
    from twin.io.table_reader import TableReader

    reader = TableReader({"speed": "-0.5 rpm", "duration": "60 s"}, "s.toml", "spindle[0].")
    err = _error(lambda: reader.speed_step(60.0))
    assert (err.source, err.field, err.message) == ("s.toml", "spindle[0].speed", "must not be negative")


@pytest.mark.parametrize("kind, words", [(int, "an integer"), ((int, float), "a number")])
def test_a_toml_boolean_is_no_number(kind, words):
    """TableReader.get(kind=int) (a dataset spec's seed, cases) refuses a TOML boolean, which Python
    counts as the integer 1: 'expected an integer, got the boolean true'."""
    from twin.io.table_reader import TableReader

    err = _error(lambda: TableReader({"seed": True}, "spec.toml", "").get("seed", default=0, kind=kind))
    assert (err.source, err.field, err.message) == ("spec.toml", "seed", f"expected {words}, got the boolean true")


# ------------------------------------------------------------------------------- camera exports
def _camera_result(name: str = "front") -> xr.Dataset:
    """A result of one camera: three 2 x 3 frames at 0, 90, 180 s, its look-up table of counts."""
    lut = 20.0 + 0.01 * np.arange(100)
    frames = lut[np.array([[[5, 6, 7], [8, 9, 10]], [[11, 12, 13], [14, 15, 16]], [[17, 18, 19], [20, 21, 22]]])]
    info = {"name": name, "suffix": "", "settings": {}, "band_um": [8, 14], "intrinsics": {}, "pose": {}}
    return xr.Dataset({"thermogram": (("frame_time", "v", "u"), frames, {"units": "degC"}),
                       "camera_lut": (("count",), lut, {"units": "degC"})},
                      {"frame_time": ("frame_time", [0.0, 90.0, 180.0], {"units": "s"})},
                      {"camera": json.dumps(info), "seed": 0, "machine": "cframe-vmc"})


def test_a_tiff_sidecar_gives_the_frame_time_in_seconds(tmp_path):
    """write_tiff_frames: each frame's JSON sidecar says its time in seconds (frame_time_s), the
    frame's own (90 s for frame 1), and its TIFF holds centikelvin."""
    from PIL import Image

    from twin.io.thermography import write_tiff_frames

    paths = write_tiff_frames(_camera_result(), tmp_path)
    side = json.loads(paths[1].with_suffix(".json").read_text(encoding="utf-8"))
    assert (side["frame"], side["frame_time_s"]) == (1, 90.0)
    with Image.open(paths[1]) as image:
        assert np.asarray(image)[0, 0] == round(100 * (20.11 + 273.15))


def test_counts_are_recovered_as_the_nearest_look_up_value():
    """camera_counts without stored counts: each pixel's count is the look-up table's nearest entry
    (an exact table value gives its own count, never its neighbour's)."""
    from twin.io.thermography import camera_counts

    ds = _camera_result()
    np.testing.assert_array_equal(camera_counts(ds)[0], [[5, 6, 7], [8, 9, 10]])
    nudged = ds.copy(deep=True)
    nudged["thermogram"].values[0, 0, 0] += 0.004       # nearer count 5 than 6
    nudged["thermogram"].values[0, 0, 1] += 0.006       # nearer count 7 than 6
    assert camera_counts(nudged)[0, 0, :2].tolist() == [5, 7]


@pytest.mark.parametrize("name", ["../front", "a/b", ".."])
def test_a_camera_whose_name_cannot_name_a_file_is_refused(name):
    """A camera's name names its export's folder and files: a name with a path separator or '..'
    (which would write outside the export folder) is refused naming the attribute."""
    from twin.io.thermography import camera_names

    err = _error(lambda: camera_names(_camera_result(name), "r.nc"))
    assert (err.source, err.field, err.message) == ("r.nc", "camera", f"camera name {name!r} cannot name a file")


# --------------------------------------------------------------------------------- field files
@pytest.mark.parametrize("values, time_s, words", [
    (np.full(3, 20.0), -1.0, "the field's time must be a finite number of seconds >= 0, got -1.0"),
    (np.array([20.0, np.nan, 21.0]), 0.0, "must hold one finite temperature per temperature dof (3), got shape (3,), "
                                           "not finite"),
    (np.full(4, 20.0), 0.0, "must hold one finite temperature per temperature dof (3), got shape (4,)"),
])
def test_a_field_file_is_checked_before_anything_is_written(tmp_path, values, time_s, words):
    """save_temperature_field checks the field (one finite temperature per dof) and its time (finite,
    not negative) before it writes: one error naming the file and --field, and no file."""
    from twin.io.fields import save_temperature_field

    mm = SimpleNamespace(nheat=3, nnodes=3)
    err = _error(lambda: save_temperature_field(mm, values, tmp_path / "hot.vtu", time_s))
    assert (err.source, err.field) == (str(tmp_path / "hot.vtu"), "--field")
    assert words in err.message
    assert list(tmp_path.iterdir()) == []
