"""The diagnosis on the gantry (laser triangulation and FBG strain channels, the C axis): the
engine against a simulation, a gantry log read from CSV, and one small case of the study (truth on
the default mesh with half the time step, perturbed materials, noise, quantisation and bias;
model on coarse)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from geometries import build_machine
from twin.fem.mesh import mesh_machine
from twin.model import model_spec
from twin.rotary import RotarySchedule
from twin.scenario import Ambient, Scenario
from validate.diagnose import diagnose, diagnosis_json, format_diagnosis
from validate.signatures import Engine
from validate.synthetic import truth_measurement

# the seed's C-axis test shortened: 2500 rpm, 10 s on / 10 s off for 1 h, then 1 h at rest, every 2 min
C_TEST = Scenario("c-axis-short", ((7200.0, 0.0),), Ambient("constant", mean=20.0), 120.0,
                  c_axis=RotarySchedule(((3600.0, 2500.0, 0.5), (3600.0, 0.0, 1.0))))
QUIET = ["fbg.noise=0um/m", "fbg.quantisation=0um/m", "temperature_sensor.noise=0K",
         "temperature_sensor.quantisation=0K", "laser_triangulation.noise=0um", "laser_triangulation.resolution=0um",
         "temperature_sensor.bias=0.1K"]


@pytest.fixture(scope="module")
def gantry():
    return build_machine("gantry-ram")


@pytest.fixture(scope="module")
def coarse(gantry):
    return mesh_machine(gantry, "coarse")


def test_engine_reads_what_a_simulation_records(gantry, coarse):
    """With the instruments' noise and quantisation off, the engine's channels equal the result's
    readings: temperatures through the sensor lag plus bias, lasers, and the FBG readings,
    eps_raw = eps + k_T dT_g and eps_comp = eps_raw - k_T (T_s - T_s(0)) with T_s the compensating
    sensor's reading (twin.observe.strain), to round-off."""
    from twin.api import simulate
    sc = replace(C_TEST, sample_interval=60.0)
    ds, _ = simulate("gantry-ram", sc, None, QUIET, "coarse", 0)
    e = Engine(gantry, sc, mm=coarse)
    out = e.observe(model_spec(gantry, None, QUIET))
    col = {n: i for i, n in enumerate(e.names)}
    for group, var, dim in (("temperature", "temperature", "sensor"), ("laser", "laser", "laser_id"),
                            ("strain", "strain", "gauge"), ("strain_raw", "strain_raw", "gauge")):
        labels = [str(v) for v in ds[dim].values]
        mine = out[:, [col[f"{group}:{lab}"] for lab in labels]]
        theirs = ds[var].transpose("time", dim).values
        np.testing.assert_allclose(mine, theirs, atol=1e-9 * max(1.0, np.abs(theirs).max()), err_msg=var)
    assert np.abs(ds.strain_raw.values - ds.strain.values).max() > 1.0   # the compensation matters here


def test_expansion_sensitivity_of_lasers_and_strain_is_exact(gantry, coarse):
    """Laser readings and FBG strains (mechanical plus thermal, eps = d . (u(b) - u(a)) / L) are
    linear in each material's alpha_m for given temperatures, and the grating's cross-sensitivity
    k_T dT_g does not depend on alpha: the one-run response equals the difference quotient
    (y(alpha_m (1 + s)) - y(alpha_m)) / s of a twin rebuilt with the scaled material, to round-off,
    on lasers, compensated and raw strains alike; temperatures do not respond."""
    from geometries.materials import MATERIALS
    spec = model_spec(gantry)
    engine = Engine(gantry, C_TEST, mm=coarse)
    base, resp = engine.observe_with_expansion(spec, ["steel"])
    scaled = Engine(gantry, C_TEST, mm=coarse, materials={"steel": MATERIALS["steel"].scaled(expansion=1.05)})
    quotient = (scaled.observe(spec) - base) / 0.05
    np.testing.assert_allclose(resp[0], quotient, atol=1e-8 * np.abs(quotient).max())
    col = {n: i for i, n in enumerate(engine.names)}
    assert abs(quotient[:, col["laser:Z"]]).max() > 10 and abs(quotient[:, col["strain:FBG-1"]]).max() > 10
    np.testing.assert_array_equal(resp[0][:, col["strain:FBG-1"]], resp[0][:, col["strain_raw:FBG-1"]])
    assert not resp[0][:, :engine.nsensor].any()


def _write_log(ds, folder, duty):
    """A gantry log as a user would write it: minutes, C-axis speed, room air, T1, the lasers in mm,
    FBG-1 and FBG-2 compensated (ppm) and raw (um/m)."""
    t = ds.time.values / 60.0
    cols = {"minutes": t, "c_rpm": ds.c_axis_speed.values, "room": ds.ambient_temperature.values,
            "T1": ds.temperature.sel(sensor="T1").values}
    cols.update({f"L{p}": ds.laser.sel(laser_id=p).values * 1e-3 for p in ("Y", "Z", "A1", "A2")})
    for g in ("1", "2"):
        cols.update({f"F{g}": ds.strain.sel(gauge=f"FBG-{g}").values, f"F{g}r": ds.strain_raw.sel(gauge=f"FBG-{g}").values})
    lines = [",".join(cols)] + [",".join(f"{cols[c][i]:.9g}" for c in cols) for i in range(len(t))]
    (folder / "log.csv").write_text("\n".join(lines) + "\n")
    mapping = ['machine = "gantry-ram"', '[columns.minutes]\nrole = "time"\nunit = "min"',
               f'[columns.c_rpm]\nrole = "c_axis_speed"\nduty = {duty}\nunit = "rpm"',
               '[columns.room]\nrole = "ambient_temperature"\nunit = "degC"',
               '[columns.T1]\nrole = "temperature"\nsite = "T1"\nunit = "degC"']
    mapping += [f'[columns.L{p}]\nrole = "laser"\nlaser = "{p}"\nunit = "mm"' for p in ("Y", "Z", "A1", "A2")]
    mapping += [f'[columns.F{g}]\nrole = "strain"\ngauge = "FBG-{g}"\nreading = "compensated"\nunit = "ppm"'
                for g in ("1", "2")]
    mapping += [f'[columns.F{g}r]\nrole = "strain"\ngauge = "FBG-{g}"\nreading = "raw"\nunit = "um/m"'
                for g in ("1", "2")]
    (folder / "log.toml").write_text("\n\n".join(mapping) + "\n")
    return folder / "log.csv"


@pytest.fixture(scope="module")
def quiet_result(gantry):
    from twin.api import simulate
    ds, _ = simulate("gantry-ram", C_TEST, None, QUIET[:-1], "coarse", 0)   # no bias: the log's start is the room's
    return ds


def test_gantry_log_drives_the_twin_and_compares_to_round_off(quiet_result, tmp_path):
    """A CSV log with laser [mm], strain [ppm, um/m; compensated and raw] and C-axis speed columns
    (the rhythm's duty in the mapping) reads back as the result's channels (units converted, nulled
    at the first sample), its C axis becomes the twin's schedule, and `twin compare` of the twin's
    own noise-free log against the twin driven by it leaves residuals at the CSV's rounding (the
    temperature: its sensor's 5 s lag, which compare leaves in the reading)."""
    from validate.compare import compare, model_for
    from twin.io.measured_inputs import scenario_from_measurement
    from twin.io.measurement import read_measurement

    ds = quiet_result
    meas = read_measurement(_write_log(ds, tmp_path, 0.5))
    np.testing.assert_allclose(meas.laser.sel(laser_id="Z").values, ds.laser.sel(laser_id="Z").values, atol=1e-6)
    np.testing.assert_allclose(meas.strain_raw.sel(gauge="FBG-2").values, ds.strain_raw.sel(gauge="FBG-2").values,
                               atol=1e-6)
    assert meas.laser.attrs["units"] == "um" and meas.strain.attrs["units"] == "um/m"
    sc = scenario_from_measurement(meas)
    turning = lambda steps: [(d, n, duty if n > 0 else None) for d, n, duty in steps]   # duty at rest: moot
    assert turning(sc.c_axis.steps) == turning(C_TEST.c_axis.steps) and all(n == 0 for _, n in sc.steps)
    model, _ = model_for(meas, "gantry-ram", None, None, QUIET[:-1], "coarse")
    res = compare(meas, model)
    names = {c.name: c for c in res.channels}
    assert {"laser:Z", "strain:FBG-1", "strain_raw:FBG-2", "temperature:T1"} <= set(names)
    assert names["laser:Z"].stats.rmse < 1e-3 and abs(ds.laser.sel(laser_id="Z")).max() > 10
    assert names["strain_raw:FBG-2"].stats.rmse < 1e-3 and names["strain:FBG-1"].stats.rmse < 1e-3
    assert names["temperature:T1"].stats.rmse < 0.01   # compare holds the reading (5 s lag) against the true T
    assert any(p.kind == "c_axis" and p.label == "C axis on 2500 rpm" for p in res.phases)


@pytest.fixture(scope="module")
def bearing_case(gantry, coarse):
    """Class 'parameter' on the gantry: the truth's C-axis bearing loses 600 W at 2500 rpm, the
    model says 400 W."""
    ds = truth_measurement("gantry-ram", C_TEST, None, ["c_axis_drive.bearing_power=600W"])
    return ds, diagnose(ds, gantry, C_TEST, model_spec(gantry), mm=coarse, error_resolution="default",
                        localise_steps=30)


def test_wrong_c_axis_bearing_power_is_named_from_lasers_and_strain(bearing_case):
    """The wrong parameter is named first, fitted within 25 % of 600 W, the verdict names it, and
    each new group (laser in um, strain in um/m) has its own noise, model error and residual
    factor in the JSON."""
    ds, d = bearing_case
    top = d.candidates[0]
    assert top["effect"] == "c_axis_drive.bearing_power" and top["kind"] == "parameter", format_diagnosis(d)
    assert d.verdict in ("explained", "partly_explained"), d.message
    assert abs(d.fits[0].value_of("c_axis_drive.bearing_power") / 600.0 - 1) < 0.25
    doc = diagnosis_json(d)
    assert set(doc["residual_factor"]) == {"temperature", "laser", "strain"}
    assert doc["levels"]["laser"]["unit"] == "um" and doc["levels"]["strain"]["unit"] == "um/m"
    assert doc["levels"]["strain"]["noise"] >= 0.4 - 1e-12     # floored at half the 0.8 um/m step
    assert doc["baseline"]["units"]["strain:FBG-1"] == "um/m"
    assert not any(c.startswith("strain_raw:") for c in doc["baseline"]["rmse"])   # each gauge once
    assert doc["missing_channels"] == []


@pytest.mark.parametrize("keep", ["strain", "strain_raw", "laser"])
def test_one_group_alone_is_diagnosed_and_the_rest_costed(bearing_case, gantry, coarse, keep):
    """Strain gauges only (compensated, or raw: the model then adds k_T dT_g), or lasers only: the
    expansion is fitted (both groups respond to alpha) and the missing groups are stated with what
    they cost (>= 1x: the full set never stands lower). The seven gauges alone name the bearing
    power first within 25 %; the four lasers alone see one drift of the ram's end, to which the C motor and the C
    bearing contribute alike: the top candidate is one of the two and the other is reported as
    not distinguishable from it."""
    ds, _ = bearing_case
    drop = [v for v in ds.data_vars if v.split("_")[0] in ("temperature", "laser", "strain")
            and not (v.startswith(keep) and (keep != "strain" or v != "strain_raw"))]
    d = diagnose(ds.drop_vars(drop), gantry, C_TEST, model_spec(gantry), mm=coarse, localise_regions=False,
                 candidates=[])   # the model's own uncertain parameters only: quicker, the same question
    top = d.candidates[0]
    if keep.startswith("strain"):
        assert top["effect"] == "c_axis_drive.bearing_power", format_diagnosis(d)
        assert abs(d.fits[0].value_of("c_axis_drive.bearing_power") / 600.0 - 1) < 0.25
    else:
        pair = {"c_axis_drive.bearing_power", "c_axis_drive.motor_power"}
        assert top["effect"] in pair and (pair - {top["effect"]}) <= set(top["indistinguishable_from"]), \
            format_diagnosis(d)
    assert d.materials and set(d.residual_factor) == {keep}
    gaps = {g["group"]: g for g in d.missing_channels}
    assert set(gaps) == {"temperature", "laser", "strain"} - {keep.split("_")[0]}
    assert all(g["cost"] >= 1.0 and "full set" in g["note"] for g in gaps.values())
