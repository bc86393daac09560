"""A diagnosis called from Python: each bad argument is one InputError naming it, raised before
the baseline runs (``validate.diagnose_args``): NaN or out-of-range thresholds that would change
the verdict silently, unknown candidates, a model outside its parameters' bounds, measurements
with NaN, too few samples or unplaced sensors, a model-error estimate of the wrong shape."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import xarray as xr

import validate.diagnose as diagnose_module
from geometries import build_machine
from twin.errors import InputError
from twin.model import ModelSpec, default_spec
from twin.scenario import load_scenario
from validate.diagnose import diagnose, diagnose_many
from validate.diagnose_args import check_model_error

MACHINE = build_machine("cframe-vmc")
SCENARIO = replace(load_scenario("spindle-heat-cool-9000"), steps=((600.0, 9000.0),))


def measurement(n: int = 11) -> xr.Dataset:
    """Two of the machine's sensor sites read every minute (no run needed: the checks come first)."""
    sites = [p.name for p in MACHINE.points if p.part != "air"][:2]
    t = 60.0 * np.arange(n)
    return xr.Dataset({"temperature": (("time", "sensor"), np.full((n, 2), 20.0), {"units": "degC"})},
                      coords={"time": ("time", t, {"units": "s"}), "sensor": sites}, attrs={"machine": MACHINE.name})


@pytest.fixture
def no_run(monkeypatch):
    """Fail the test if the twin is prepared: every check must come first."""
    def refuse(*args, **kwargs):
        raise AssertionError("the twin was prepared before the arguments were checked")
    monkeypatch.setattr(diagnose_module, "PreparedTwin", refuse)


def with_nan() -> xr.Dataset:
    ds = measurement()
    ds.temperature[3, 1] = np.nan
    return ds


BAD = [
    ("machine-a-name", {"machine": "cframe-vmc"}, "machine"),
    ("scenario-a-name", {"scenario": "spindle-heat-cool-9000"}, "scenario"),
    ("measurement-a-path", {"ds": "m.csv"}, "measurement"),
    ("measurement-nan", {"ds": with_nan()}, "temperature:"),
    ("measurement-one-sample", {"ds": measurement(1)}, "time"),
    ("measurement-nan-time", {"ds": measurement().assign_coords(time=[np.nan] + [60.0 * i for i in range(1, 11)])},
     "time"),
    ("sensor-unplaced", {"ds": measurement().assign_coords(sensor=["s0", "s1"])}, "sensor s0"),
    ("spec-a-text", {"spec": "+door_stream"}, "spec"),
    ("spec-negative-power", {"spec": ModelSpec(default_spec(MACHINE).effects,
                                               {"spindle_bearings": {"front_power": -500.0}})},
     "spec spindle_bearings.front_power"),
    ("spec-negative-noise", {"spec": ModelSpec(default_spec(MACHINE).effects, {"temperature_sensor": {"noise": -0.5}})},
     "spec temperature_sensor.noise"),
    ("candidates-unknown", {"candidates": ["nope"]}, "candidates[0]"),
    ("candidates-a-text", {"candidates": "door_stream"}, "candidates"),
    ("custom-unknown", {"custom": ("nope",)}, "custom[0]"),
    ("custom-a-library-effect", {"custom": ("door_stream",)}, "custom[0]"),
    ("min-explained-nan", {"min_explained": float("nan")}, "min_explained"),
    ("min-explained-5", {"min_explained": 5}, "min_explained"),
    ("min-explained-0", {"min_explained": 0.0}, "min_explained"),
    ("pair-threshold-negative", {"pair_threshold": -0.1}, "pair_threshold"),
    ("bic-margin-negative", {"bic_margin": -10.0}, "bic_margin"),
    ("bic-margin-inf", {"bic_margin": float("inf")}, "bic_margin"),
    ("pair-pool-negative", {"pair_pool": -1}, "pair_pool"),
    ("pair-pool-a-float", {"pair_pool": 2.5}, "pair_pool"),
    ("localise-steps-0", {"localise_steps": 0}, "localise_steps"),
    ("progress-a-number", {"progress": 5}, "progress"),
    ("parameters-a-text", {"parameters": "no"}, "parameters"),          # "no" is true in Python
    ("localise-regions-a-text", {"localise_regions": "no"}, "localise_regions"),
    ("calibrate-expansion-a-number", {"calibrate_expansion": 0}, "calibrate_expansion"),
    ("resolution-unknown", {"resolution": "ultra"}, "resolution"),
    ("error-resolution-unknown", {"error_resolution": "ultra"}, "error_resolution"),
    ("twin-a-text", {"twin": "coarse"}, "twin"),
]


@pytest.mark.parametrize("case, change, field", BAD, ids=[c for c, _, _ in BAD])
def test_a_bad_argument_is_named_before_the_twin_is_prepared(case, change, field, no_run):
    args = {"ds": measurement(), "machine": MACHINE, "scenario": SCENARIO, "resolution": "coarse", **change}
    with pytest.raises(InputError) as err:
        diagnose(args.pop("ds"), args.pop("machine"), args.pop("scenario"), **args)
    assert err.value.field.startswith(field), str(err.value)


def test_the_list_of_measurements_is_checked_item_by_item(no_run):
    for measurements, field in (([], "measurements"), ([measurement()], "measurements[0]"),
                                ([("", measurement(), SCENARIO)], "measurements[0]"), ("m.csv", "measurements")):
        with pytest.raises(InputError) as err:
            diagnose_many(measurements, MACHINE, resolution="coarse")
        assert err.value.field == field, str(err.value)


def test_a_model_error_estimate_is_one_finite_value_at_least_zero_per_channel():
    channels = ["temperature:a", "temperature:b", "probe:Z"]
    assert check_model_error([0.1, 0.0, 2.0], channels, "m").tolist() == [0.1, 0.0, 2.0]
    for value, field in (([0.1, 0.2], "model_error"), (np.ones((3, 1)), "model_error"), ("x", "model_error"),
                         ([0.1, -1.0, 0.0], "model_error[1]"), ([0.1, 0.0, np.nan], "model_error[2]")):
        with pytest.raises(InputError) as err:
            check_model_error(value, channels, "m")
        assert err.value.field == field, str(err.value)


def test_a_spec_built_in_python_takes_only_finite_numbers():
    with pytest.raises(InputError, match="finite number"):
        ModelSpec(default_spec(MACHINE).effects, {"spindle_bearings": {"front_power": float("nan")}})
    with pytest.raises(InputError, match="finite number"):
        ModelSpec(default_spec(MACHINE).effects, {"spindle_bearings": {"front_power": True}})
    default_spec(MACHINE).check_bounds()


def test_the_synthetic_truth_names_a_bad_factor_or_settings_and_lets_the_user_set_the_instruments(monkeypatch):
    """API audit: ``short_scenario(sc, -1)`` gave 10 s steps silently, a settings text was read
    letter by letter, and a user's own sensor noise clashed with the truth's built-in one."""
    import validate.synthetic as synthetic

    for factor in (-1, 0, float("nan"), "2"):
        with pytest.raises(InputError) as err:
            synthetic.short_scenario(SCENARIO, factor)
        assert err.value.field == "factor"
    assert synthetic.short_scenario(SCENARIO, 0.5).duration == 300.0
    with pytest.raises(InputError) as err:
        synthetic.truth_measurement("cframe-vmc", SCENARIO, settings="probe.noise=0.1 um")
    assert err.value.field == "--set"
    seen = {}

    class Stop(Exception):
        pass

    def simulate(*args, **kwargs):
        seen.update(kwargs)
        raise Stop
    monkeypatch.setattr(synthetic, "simulate", simulate)
    with pytest.raises(Stop):
        synthetic.truth_measurement("cframe-vmc", SCENARIO, settings=["temperature_sensor.noise=0.2 K"])
    assert "temperature_sensor.noise=0.2 K" in seen["settings"]
    assert sum(s.startswith("temperature_sensor.noise") for s in seen["settings"]) == 1


def test_a_mesh_or_resolution_beside_a_prepared_twin_must_be_its_own():
    """diagnose_many(twin=..., resolution=...) and Engine(prepared=..., resolution=...) would use
    the twin's mesh and drop the other: refused, naming the argument, before the baseline runs."""
    from twin.physics.prepared import PreparedTwin
    from validate.signatures import Engine

    twin = PreparedTwin(MACHINE, resolution="coarse")
    with pytest.raises(InputError) as err:
        diagnose_many([("m", measurement(), SCENARIO)], MACHINE, resolution="default", twin=twin)
    assert err.value.field == "resolution" and "the prepared twin's mesh is 'coarse'" in str(err.value)
    with pytest.raises(InputError) as err:
        Engine(MACHINE, SCENARIO, "default", prepared=twin)
    assert err.value.field == "resolution"
    assert Engine(MACHINE, SCENARIO, "coarse", prepared=twin).twin is twin
