"""Hidden-effect proof on the coarse mesh: truth on the default mesh, half time step, perturbed
materials, sensor noise, quantisation and bias (validate.synthetic); diagnosing model on coarse."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from geometries import build_machine
from twin.api import model_spec
from twin.scenario import load_scenario
from validate.diagnose import diagnose, diagnosis_json, format_diagnosis
from validate.signatures import Engine
from validate.synthetic import short_scenario, truth_measurement


@pytest.fixture(scope="module")
def case():
    sc = short_scenario(replace(load_scenario("spindle-heat-cool-9000"), sample_interval=20.0), 0.5)
    machine = build_machine("cframe-vmc")
    ds = truth_measurement("cframe-vmc", sc, resolution="default")
    return machine, machine.mesh("coarse"), sc, ds


def test_engine_matches_simulate_run(case):
    from twin.simulate import run
    machine, mm, sc, _ = case
    short = replace(sc, steps=((600.0, 9000.0), (200.0, 0.0)))
    spec = model_spec()
    r = run(machine, short, spec, mm=mm)
    out = Engine(machine, short, mm=mm).true_outputs(spec)
    np.testing.assert_allclose(out[:, :16], r.sensor_true, atol=1e-9)
    np.testing.assert_allclose(out[:, 16:], r.probe * 1e6, atol=1e-9)


def test_hidden_spindle_motor_found(case):
    machine, mm, sc, ds = case
    d = diagnose(ds, machine, sc, model_spec("-spindle_motor"), mm=mm)
    top = d.candidates[0]
    assert d.significant, format_diagnosis(d)
    assert top["effect"] == "spindle_motor"
    fitted = d.fits[0].values["spindle_motor"]["power"]
    assert abs(fitted / 60.0 - 1) < 0.25, fitted
    probes = [i for i, g in enumerate(d.groups) if g == "probe"]
    before = np.sqrt(np.mean(d.residual[:, probes] ** 2))
    after = np.sqrt(np.mean((d.residual - d.fits[0].response)[:, probes] ** 2))
    assert after <= 0.3 * before, (before, after)
    doc = json.loads(json.dumps(diagnosis_json(d)))
    assert doc["candidates"][0]["parameters"]["spindle_motor"]["power"].endswith(" W")
    assert set(doc["baseline"]["rmse"]) == set(d.channels)
    assert "spindle_motor" in format_diagnosis(d)


def test_nothing_hidden_reports_nothing(case):
    machine, mm, sc, ds = case
    d = diagnose(ds, machine, sc, model_spec(), mm=mm)
    assert not d.significant, format_diagnosis(d)
    assert "nothing significant" in format_diagnosis(d)
