"""The diagnosis reads the laser interferometer (issue 11, item 9): its positioning error is a
measured channel group, read at the runs; each check against an exact identity."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr

from twin.scenario import scenario_from_dict
from validate.channels import stack_runs
from validate.evidence import POSITIONING_FLOOR, channel_weights, noise_levels

AXIS_SCENARIO = {
    "sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
    "spindle": [{"speed": "0 rpm", "duration": "10 min"}],
    "axis": [{"name": "Y", "move": [{"kind": "reciprocate", "between": ["0 mm", "280 mm"], "feed": "20 mm/s",
                                     "acceleration": "10 mm/s2", "duration": "10 min"}]}],
    "interferometer": {"axis": "Y", "runs": ["0 min", "4 min", "10 min"], "targets": ["0 mm", "280 mm"],
                       "spacing": "40 mm"},
}


@pytest.fixture(scope="module")
def axis_run():
    """The C-frame moving Y for 10 min on the coarse mesh: (machine, scenario, result, engine)."""
    from geometries import build_machine
    from twin.api import simulate
    from twin.motion import machine_for
    from validate.signatures import Engine
    sc = scenario_from_dict(AXIS_SCENARIO, "axis.toml")
    machine = machine_for(build_machine("cframe-vmc"), sc)
    ds = simulate("cframe-vmc", sc, resolution="coarse")[0]
    return machine, sc, ds, Engine(machine, sc, "coarse")


def test_engine_reads_the_interferometer_as_the_simulation_does(axis_run):
    """The diagnosis engine's positioning columns, taken at the runs, are the simulated
    ``positioning_error`` (the same rows R: e(t_k) = R (T(t_k) - T_0)), to round-off."""
    from twin.model import model_spec
    machine, sc, ds, engine = axis_run
    t, runs = stack_runs(ds)
    cols = [engine.names.index(c) for c in runs.names]
    steps = np.round(t / sc.sample_interval).astype(int)
    y = engine.observe(model_spec(machine))[np.ix_(steps, cols)]
    scale = np.abs(runs.values).max()
    assert scale > 0.1   # um: the nut and bearings heat the screw within 10 min
    assert np.abs(y - runs.values).max() <= 1e-9 * scale


def test_positioning_expansion_responses_sum_to_the_reading(axis_run):
    """The positioning error is homogeneous of degree 1 in the expansion coefficients, so by
    Euler's theorem sum_m d e / d s_m = e for alpha_m (1 + s_m): the per-material rows (the
    screw's line integral in steel's) add up to the instrument's rows, exactly."""
    machine, sc, ds, engine = axis_run
    twin, obs = engine.twin, engine.positioning
    loads = SimpleNamespace(mm=twin.mm)
    T = 20.0 + np.random.default_rng(3).random(twin.mm.nheat)
    whole = obs.rows(twin, loads) @ T
    parts = sum(obs.material_rows(twin, loads, m) @ T for m in {p.material.name for p in machine.parts})
    assert np.abs(parts - whole).max() <= 1e-10 * np.abs(whole).max()
    steel_only = obs.material_rows(twin, loads, "steel") - obs.material_rows(twin, loads, "grey_cast_iron")
    assert abs(steel_only @ T).max() > 0   # the screw is steel: its term sits in steel's rows


def test_the_diagnosis_holds_the_interferometer_as_a_record_of_its_runs(axis_run):
    """A measurement with interferometer runs gives a second record (same label, same engine) at
    the runs; it counts as the first record's samples: sum (w r)^2 = n_t of the first record for a
    residual at the noise level in every channel."""
    from twin.model import model_spec
    from validate.evidence import make_records
    machine, sc, ds, engine = axis_run
    recs = make_records("run", ds, sc, machine, engine.twin)
    assert [r.label for r in recs] == ["run", "run"] and recs[0].engine is recs[1].engine
    main, pos = recs
    assert set(pos.groups) == {"positioning"} and np.allclose(pos.times, [0.0, 240.0, 600.0])
    assert pos.counts_as == len(main.times) == 11
    spec = model_spec(machine)
    runs_before = main.engine.runs
    main.observe(spec), pos.observe(spec)
    assert main.engine.runs == runs_before + 1   # one twin run serves both records
    r = np.full(pos.measured.shape, 0.2)
    w = channel_weights(r, pos.groups, {"positioning": 0.2}, None, pos.counts_as)
    assert float(np.sum((w * r) ** 2)) == pytest.approx(11.0, rel=1e-12)


def test_interferometer_runs_without_one_in_the_scenario_are_refused_by_name(axis_run):
    """Runs the driving scenario does not make are an error naming the variable, never dropped."""
    from dataclasses import replace

    from twin.errors import InputError
    from validate.evidence import make_records
    machine, sc, ds, engine = axis_run
    with pytest.raises(InputError) as err:
        make_records("run.nc", ds, replace(sc, interferometer=None), machine, engine.twin)
    assert err.value.field == "positioning_error" and "[interferometer]" in str(err.value)


def test_positioning_noise_comes_from_second_differences_along_the_targets():
    """A run linear along the targets has zero second difference: the floor; white noise of
    sigma on it reads sigma (var(d2) = 6 sigma^2), within the sampling error of 4000 draws."""
    from twin.model import ModelSpec
    spec = ModelSpec(())
    x = np.linspace(0.0, 280.0, 41)
    runs = np.outer(np.arange(1, 101), 0.05 * x)   # 100 runs, slopes growing in time
    assert noise_levels(runs, ["positioning"] * 41, spec)["positioning"] == POSITIONING_FLOOR
    noisy = runs + 0.3 * np.random.default_rng(0).standard_normal(runs.shape)
    assert noise_levels(noisy, ["positioning"] * 41, spec)["positioning"] == pytest.approx(0.3, rel=0.05)


def test_stack_runs_takes_the_mean_of_both_directions():
    """The positioning channel is the mean of the forward and backward readings (a reversal error
    +-b cancels), one channel per target labelled by its position in mm."""
    pe = np.zeros((2, 3, 2))
    pe[1, :, 0], pe[1, :, 1] = [1.0, 2.0, 3.0], [3.0, 4.0, 5.0]
    ds = xr.Dataset({"positioning_error": (("run_time", "target", "direction"), pe)},
                    coords={"run_time": [0.0, 60.0], "target": [0.0, 10.0, 20.0], "direction": ["forward", "backward"]})
    t, ch = stack_runs(ds)
    assert list(t) == [0.0, 60.0] and ch.names == ["positioning:0", "positioning:10", "positioning:20"]
    assert np.array_equal(ch.values[1], [2.0, 3.0, 4.0])
