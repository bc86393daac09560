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
