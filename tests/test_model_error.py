"""The diagnosing model's discretisation-error estimate with the named candidate in the model
(validate.model_error): the residual a candidate leaves is held against the error of the model that
leaves it."""

from __future__ import annotations

import numpy as np
import pytest

from learners.metrics import rms
from twin.model import model_spec
from twin.scenario import Ambient, Scenario
from validate.diagnose import diagnose, format_diagnosis
from validate.model_error import error_with, mesh_error
from validate.signatures import with_effect
from validate.synthetic import truth_measurement

# 40 min at 9000 rpm, then 20 min stopped, logged every minute
SHORT = Scenario("short-heat-cool", ((2400.0, 9000.0), (1200.0, 0.0)), Ambient("constant", mean=20.0), 60.0)


@pytest.fixture(scope="module")
def hidden_motor(machine, mm):
    """The model lacks the spindle motor (60 W in the truth); model coarse, error mesh default."""
    ds = truth_measurement("cframe-vmc", SHORT, None, [], resolution="default")
    return diagnose(ds, machine, SHORT, model_spec(machine, "-spindle_motor"), mm=mm, error_resolution="default",
                    localise_regions=False)


def test_the_baseline_estimate_is_the_diagnosis_own(machine, hidden_motor):
    """m(spec) = y(spec, error mesh) - y(spec, diagnosing mesh) per channel: for the diagnosing
    model it reproduces the estimate the diagnosis weighted with (the same two runs), exactly."""
    d = hidden_motor
    again = error_with(d.evidence, machine, d.spec, d.error_resolution)
    assert np.array_equal(again, d.model_error_flat)


def test_the_estimate_with_a_source_is_linear_in_its_power(machine, hidden_motor):
    """Heat conduction, the sensors and the drift are linear in a source's power, so on both
    meshes m(spec + P motor) = m(spec) + (P / P1) (m(spec + P1 motor) - m(spec)): superposition,
    to round-off of the runs."""
    d = hidden_motor
    rec = d.evidence.records[0]
    base = mesh_error(rec, machine, d.spec, d.error_resolution, rec.error_engine)
    at = {p: mesh_error(rec, machine, with_effect(d.spec, "spindle_motor", {"power": p}), d.error_resolution,
                        rec.error_engine) for p in (30.0, 75.0)}
    predicted = base + 75.0 / 30.0 * (at[30.0] - base)
    assert np.abs(at[75.0] - base).max() > 0.01            # the motor's own mesh error is not nothing
    np.testing.assert_allclose(at[75.0], predicted, rtol=0, atol=1e-9 * np.abs(at[75.0]).max())


def test_the_factors_after_a_partly_explained_candidate_are_held_against_its_model(machine, hidden_motor):
    """A partly_explained verdict is judged again against the model error of the model with the
    candidate (one more run on each mesh): levels_after is that model's RMS per group, the factors
    after are RMS(residual after) / sqrt(noise^2 + e_after^2), and the verdict follows them."""
    from validate import verdict as V
    from validate.diagnose import _error_after

    d = hidden_motor
    assert d.fits, format_diagnosis(d)
    after = d.fitter.residual_after(d.fits[0].response)
    d.verdict, d.levels_after = "partly_explained", {}

    class Stages:
        def grow(self, n):
            pass

        def __call__(self):
            pass

    _error_after(d, machine, after, Stages())
    flat = error_with(d.evidence, machine, d.fits[0].in_model(d.spec), d.error_resolution)
    for g, (noise, e) in d.levels_after.items():
        mask = d.evidence.group_mask(g)
        assert e == pytest.approx(rms(flat[mask]), rel=1e-12)
        assert d.residual_factor_after[g] == pytest.approx(rms(after[mask]) / np.hypot(noise, e), rel=1e-12)
    assert d.verdict == V.decide(d.residual_factor, d.significant, d.residual_factor_after, d.beyond_model_error)
    # the motor's own response moves the estimate (its sign may cancel the baseline's: 0.105 um here
    # against 0.113 um without it)
    assert d.levels_after["probe"][1] != pytest.approx(d.levels["probe"][1], rel=1e-2)
