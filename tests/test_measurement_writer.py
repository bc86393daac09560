"""``twin.io.measurement_writer.write_measurement``: a Dataset written as a CSV with its column
mapping reads back as the same measurement (sensors at named sites and at their own positions,
times to the microsecond), and a Dataset or argument that could not read back is refused before
anything is written (API audit: dotted sensor names wrote malformed TOML, a custom sensor lost its
position, NaN and an unknown machine were written, 0.5 s times collapsed to whole seconds)."""

from __future__ import annotations

import numpy as np
import pytest

from tests.fuzz_files import result_dataset
from twin.errors import InputError
from twin.io.measurement import read_measurement
from twin.io.measurement_writer import write_measurement


def test_a_result_reads_back_as_the_same_measurement(tmp_path):
    ds = result_dataset()
    csv_path, toml_path = write_measurement(ds, tmp_path / "m", "run", "cframe-vmc")
    back = read_measurement(csv_path)
    assert list(back.sensor.values) == list(ds.sensor.values)
    np.testing.assert_allclose(back.temperature.values, ds.temperature.values, atol=5e-5)
    np.testing.assert_allclose(back.probe.values, ds.probe.values, atol=5e-3)
    np.testing.assert_allclose(back.time.values, ds.time.values, atol=0.0)
    assert 'site = "' in toml_path.read_text()


def test_every_csv_reading_of_a_gantry_and_an_axis_log_reads_back(tmp_path):
    """Lasers, FBG strains (compensated and raw), the C axis's speed with its duty and a logged axis
    position are written with the temperatures and read back as they were (each to its written
    precision); a reading only a NetCDF measurement holds, or a C-axis duty that changes while
    turning, is refused naming the variable and nothing is written (the writer dropped them all,
    silently)."""
    from tests.fuzz_files import GANTRY_MAPPING, gantry_csv

    (tmp_path / "g.csv").write_text(gantry_csv(), encoding="utf-8")
    (tmp_path / "g.toml").write_text(GANTRY_MAPPING, encoding="utf-8")
    ds = read_measurement(tmp_path / "g.csv")
    ds["spindle_speed"] = ("time", np.zeros(ds.sizes["time"]), {"units": "rpm"})
    csv_path, _ = write_measurement(ds, tmp_path / "out", "gantry", "gantry-ram")
    back = read_measurement(csv_path)
    for var, tol in (("laser", 5.1e-3), ("strain", 5.1e-4), ("strain_raw", 5.1e-4), ("c_axis_speed", 5.1e-4),
                     ("c_axis_duty", 0.0), ("temperature", 5.1e-5)):
        assert back[var].dims == ds[var].dims, var
        np.testing.assert_allclose(back[var].values, ds[var].values, rtol=0, atol=tol, err_msg=var)
    assert list(back.laser_id.values) == list(ds.laser_id.values) and list(back.gauge.values) == list(ds.gauge.values)
    assert float(ds.c_axis_duty.max()) == 0.5
    ds["c_axis_duty"] = ("time", np.where(ds.time.values < 300, 0.5, 0.7) * (ds.c_axis_speed.values > 0))
    with pytest.raises(InputError) as err:
        write_measurement(ds, tmp_path / "bad", "gantry", "gantry-ram")
    assert err.value.field == "c_axis_duty" and not (tmp_path / "bad").exists()

    cf = result_dataset()
    y = 100.0 + 0.5 * np.arange(cf.sizes["time"])
    cf["axis_position"] = (("time", "axis_name"), y[:, None], {"units": "mm"})
    cf = cf.assign_coords(axis_name=("axis_name", ["Y"]))
    np.testing.assert_allclose(read_measurement(write_measurement(cf, tmp_path / "ax", "run", "cframe-vmc")[0])
                               .axis_position.values, y[:, None], rtol=0, atol=5.1e-7)
    cf["positioning_error"] = (("time",), np.zeros(cf.sizes["time"]), {"units": "um"})
    with pytest.raises(InputError) as err:
        write_measurement(cf, tmp_path / "pe", "run", "cframe-vmc")
    assert err.value.field == "positioning_error" and not (tmp_path / "pe").exists()


def test_a_sensor_off_the_sites_keeps_its_name_and_position_and_half_seconds_stay(tmp_path):
    ds = result_dataset()
    names = list(ds.sensor.values)
    names[0] = "my.sensor 1"           # a dot and a space: a quoted TOML key
    ds = ds.assign_coords(sensor=names, time=("time", 0.5 * np.arange(ds.sizes["time"]), {"units": "s"}))
    csv_path, _ = write_measurement(ds, tmp_path, "run", "cframe-vmc")
    back = read_measurement(csv_path)
    assert back.sensor.values[0] == "my.sensor 1"
    for c in "xyz":
        assert float(back[c].values[0]) == pytest.approx(float(ds[c].values[0]), abs=1e-12)
    np.testing.assert_array_equal(back.time.values, ds.time.values)
    # a position that came through a unit conversion is written as a person would type it
    c = next(c for c in "xyz" if abs(float(ds[c].values[0])) > 1e-3)
    v = ds[c].values.copy()
    typed = round(float(v[0]), 4)
    v[0] = np.nextafter(typed, np.inf)                         # e.g. 1.5490000000000002
    assert repr(float(v[0])) != repr(typed)
    _, toml_path = write_measurement(ds.assign_coords({c: ("sensor", v, ds[c].attrs)}), tmp_path / "again", "run",
                                     "cframe-vmc")
    assert f'{c} = "{typed!r} m"' in toml_path.read_text(encoding="utf-8")


def nan_temperature():
    ds = result_dataset()
    ds.temperature[2, 1] = np.nan
    return ds


BAD = [
    ("machine-unknown", {"machine": "lathe"}, "machine"),
    ("machine-another", {"machine": "belt-vmc"}, "machine"),
    ("stem-empty", {"stem": ""}, "stem"),
    ("stem-a-path", {"stem": "a/b"}, "stem"),
    ("stem-hidden", {"stem": ".run"}, "stem"),
    ("dataset-none", {"ds": None}, "measurement"),
    ("temperature-nan", {"ds": nan_temperature()}, "temperature:"),
    ("sensor-name-colon", {"ds": result_dataset().assign_coords(sensor=["a:b"] + list(result_dataset().sensor.values[1:]))},
     "sensor[0]"),
    ("no-room-air", {"ds": result_dataset().drop_vars("ambient_temperature")}, "ambient_temperature"),
]


@pytest.mark.parametrize("case, change, field", BAD, ids=[c for c, _, _ in BAD])
def test_what_could_not_read_back_is_refused_and_nothing_is_written(tmp_path, case, change, field):
    args = {"ds": result_dataset(), "folder": tmp_path / "out", "stem": "run", "machine": "cframe-vmc", **change}
    with pytest.raises(InputError) as err:
        write_measurement(**args)
    assert err.value.field.startswith(field), str(err.value)
    assert not (tmp_path / "out").exists()


def test_a_folder_that_is_a_file_or_a_mapping_path_that_is_a_folder_writes_nothing(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(InputError, match="is not a folder"):
        write_measurement(result_dataset(), tmp_path / "file", "run", "cframe-vmc")
    (tmp_path / "out" / "run.toml").mkdir(parents=True)
    with pytest.raises(InputError):
        write_measurement(result_dataset(), tmp_path / "out", "run", "cframe-vmc")
    assert not (tmp_path / "out" / "run.csv").exists()       # never half a pair


def test_times_are_written_to_the_microsecond(tmp_path):
    """write_measurement's docstring: times are written to 1e-6 s ("%.6f"). A logger's clock at
    12.3456789 s (an odd start, as a measurement keeps time as logged) reads back as 12.345679 s,
    within half a microsecond at every sample; three decimals (1 ms) would be 0.1 ms off."""
    ds = result_dataset()
    t = 60.0 * np.arange(ds.sizes["time"]) + 12.3456789
    ds = ds.assign_coords(time=("time", t, {"units": "s"}))
    csv_path, _ = write_measurement(ds, tmp_path, "run", "cframe-vmc")
    assert csv_path.read_text().splitlines()[1].startswith("12.345679,")
    back = read_measurement(csv_path).time.values
    np.testing.assert_allclose(back, np.round(t, 6), rtol=0, atol=1e-9)
    assert np.max(np.abs(back - t)) <= 5e-7
