"""``validate.compare`` called from Python: a bad measurement, model or option is one InputError
naming it, never an AttributeError, a numpy error or a silent NaN or empty table (API audit)."""

from __future__ import annotations

import numpy as np
import pytest

from tests.fuzz_files import result_dataset
from twin.errors import InputError
from validate.compare import compare, format_compare


def refused(field: str, call, *args, **kwargs) -> InputError:
    with pytest.raises(InputError) as err:
        call(*args, **kwargs)
    assert err.value.field.startswith(field), str(err.value)
    return err.value


def test_a_measurement_and_its_model_compare_channel_by_channel():
    ds = result_dataset()
    result = compare(ds, ds)
    assert result.channel("probe:Z").stats.rmse == 0.0
    refused("channel", result.channel, "probe:W")
    refused("top", format_compare, result, top="3")
    refused("top", format_compare, result, top=-1)
    assert "probe:Z" in format_compare(result, top=1)


def with_nan(variable: str):
    ds = result_dataset()
    ds[variable][3, 0] = np.nan
    return ds


BAD = [
    ("measured-a-path", lambda ds: ("m.csv", ds), "measurement"),
    ("measured-nan", lambda ds: (with_nan("temperature"), ds), "temperature:"),
    ("measured-empty", lambda ds: (ds.isel(time=slice(0, 0)), ds), "time"),
    ("measured-backwards", lambda ds: (ds.isel(time=slice(None, None, -1)), ds), "time"),
    ("model-none", lambda ds: (ds, None), "model"),
    ("model-nan", lambda ds: (ds, with_nan("temperature_true")), "temperature:"),
    ("no-channel-in-common", lambda ds: (ds[["temperature", "spindle_speed", "ambient_temperature"]],
                                         ds[["probe", "spindle_speed"]]), "channels"),
]


@pytest.mark.parametrize("case, make, field", BAD, ids=[c for c, _, _ in BAD])
def test_a_bad_measurement_or_model_is_named(case, make, field):
    refused(field, compare, *make(result_dataset()))


def test_the_options_are_checked():
    ds = result_dataset()
    refused("phases", compare, ds, ds, phases="spindle")
    refused("model_true", compare, ds, ds, model_true="no")


def test_model_for_checks_the_measurement_and_its_machine_before_simulating():
    """The machine must be the measurement's (another was simulated and failed, if at all, only
    on a speed or a sensor position) and a name (a built machine's message held its whole repr)."""
    from geometries import build_machine
    from validate.compare import model_for

    ds = result_dataset()
    refused("measurement", model_for, None, "cframe-vmc")
    refused("machine", model_for, ds, "belt-vmc")
    err = refused("machine", model_for, ds, build_machine("cframe-vmc"))
    assert "pass its name, 'cframe-vmc'" in err.message and "parts=" not in err.message
    refused("temperature:", model_for, with_nan("temperature"), "cframe-vmc")


def test_a_measured_channel_the_model_lacks_is_refused_not_dropped():
    """Every measured channel is compared: one the model lacks (here probe Z and the sensor
    bed_front, taken out of the model) is an InputError naming it, never left out of the table."""
    ds = result_dataset()
    err = refused("probe:Z", compare, ds, ds.drop_sel(probe_id="Z"))
    assert "X1, X2, Y1, Y2" in err.message and "1 of the measurement's" in err.message
    refused("temperature:bed_front", compare, ds, ds.drop_sel(sensor="bed_front"))


def test_readings_compare_does_not_hold_are_named_in_the_table():
    """The interferometer's runs and the probing cycles are not compared here: the result says so
    (``not_compared``) and the table's last line names each, and a measurement without them names none."""
    ds = result_dataset()
    assert compare(ds, ds).not_compared == [] and "not compared" not in format_compare(compare(ds, ds))
    runs = ds.assign({"positioning_error": (("run_time", "target", "direction"), np.zeros((2, 3, 2)), {"units": "um"})}
                     ).assign_coords(run_time=[0.0, 600.0], target=[0.0, 100.0, 200.0], direction=["forward", "backward"])
    runs = runs.assign(probing_error=(("probe_time", "datum", "axis"), np.zeros((2, 1, 3)), {"units": "um"}))
    result = compare(runs, ds)
    assert len(result.not_compared) == 2 and result.not_compared[0].startswith("positioning_error")
    assert result.not_compared[1] == ("probing_error (the probing cycles' datum errors): no command holds it against "
                                      "the model yet")
    assert format_compare(result).splitlines()[-1].startswith("not compared here: positioning_error")


def test_an_error_found_after_reading_names_the_result_as_typed(tmp_path, monkeypatch, capsys):
    """``twin compare r.nc``: a message raised from the loaded Dataset (its scenario rebuilt from
    the logged inputs) names the file as the user typed it, not the absolute path xarray records."""
    from twin.cli import main

    monkeypatch.chdir(tmp_path)
    result_dataset().assign_attrs(moved_axes="Y").to_netcdf("r.nc", engine="h5netcdf")
    assert main(["compare", "r.nc", "--mesh", "coarse"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: r.nc: axis_position: the run moved axis Y") and err.count("\n") == 1, err
