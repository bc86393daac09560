"""The diagnosis says what its numbers say (audit B): a candidate that passes the significance test
is called significant even when the verdict does not name it; without a model-error estimate no
"model error 0 K" and the comparison is said to be with noise alone; only the groups above the
limit are called above noise; every percentage states its base; the BIC weight is not called a
confidence that the candidate is the cause, and the ranking marks who passes the test; candidate
parameters at a bound of their range are flagged; the JSON's numbers carry their units.

One diagnosis on the coarse mesh (about 20 s on 2 cores): the demo's measurement (the C-frame's
heat-cool test with an electrical cabinet of 120 W, truth on coarse, logged every minute, written
and read back as CSV), a model whose cabinet makes 95 W, no model-error estimate
(``--error-mesh none``), the uncertain parameters as candidates. The rest are the message and
the helpers on numbers given by hand."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from validate.candidates import Candidate
from validate.search import Fit
from validate.verdict import WITHIN, group_levels, message, residual_factors

LEVELS = {"temperature": (0.057, 0.028), "probe": (0.098, 0.12)}
NOISE_ONLY = {"temperature": (0.054, None), "probe": (0.11, None)}


@pytest.fixture(scope="module")
def cabinet_at_95(machine, mm, tmp_path_factory):
    """The audit's case 3: model cabinet 95 W, truth 120 W, ``--error-mesh none``."""
    from twin.io.measured_inputs import scenario_from_measurement
    from twin.io.measurement import read_measurement
    from twin.io.measurement_writer import write_measurement
    from twin.model import model_spec
    from twin.scenario import load_scenario
    from validate.diagnose import diagnose
    from validate.synthetic import truth_measurement

    sc = replace(load_scenario("spindle-heat-cool-9000"), sample_interval=60.0)
    truth = truth_measurement("cframe-vmc", sc, "+electrical_cabinet", ["electrical_cabinet.power=120W"],
                              resolution="coarse", seed=1)
    csv, _ = write_measurement(truth, tmp_path_factory.mktemp("meas"), "spindle-test", "cframe-vmc")
    meas = read_measurement(csv)
    spec = model_spec(machine, "+electrical_cabinet", ["electrical_cabinet.power=95W"])
    return diagnose(meas, machine, scenario_from_measurement(meas), spec, mm=mm, candidates=[],
                    localise_regions=False)


# --- 3: significant, but within the envelope: said honestly, and `significant` means the test ---------

def test_a_significant_candidate_within_the_envelope_is_called_significant(cabinet_at_95):
    """Every factor <= 3 (against noise alone), the cabinet's power explains > 50 % at > 10 BIC
    units: the verdict stays ``nothing_missing`` (without a model-error estimate the diagnosis
    cannot show the candidate is more than the model's own error), but ``significant`` is the
    README's test (true), ``named`` is false, and the message says the candidate is significant,
    what it explains of which residual, and why the verdict does not name it; never 'not
    significant'."""
    from validate.diagnose import diagnosis_json
    d = cabinet_at_95
    top = d.candidates[0]
    assert top["effect"] == "electrical_cabinet.power"
    assert top["delta_bic"] >= 10 and top["explained"] >= 0.5 and top["significant"]
    assert all(f <= WITHIN for f in d.residual_factor.values())
    assert d.verdict == "nothing_missing" and d.significant and not d.named
    assert "not significant" not in d.message
    assert f"electrical_cabinet.power is significant (dBIC {top['delta_bic']:.1f} >= 10, explains " \
           f"{top['explained']:.0%} >= 50% of the weighted residual (all groups, none above noise))" in d.message
    assert "so the verdict does not name it: no model error was estimated" in d.message
    doc = json.loads(json.dumps(diagnosis_json(d)))
    assert doc["significant"] is True and doc["named"] is False and doc["candidates"][0]["significant"] is True


def test_nothing_missing_message_states_why_a_candidate_is_not_named():
    """With a model-error estimate the reason is the signature ratio; a candidate that fails the
    test is 'not significant' with the failing condition."""
    top = {"effect": "e.p", "explained": 0.57, "delta_bic": 40.0, "significant": True, "statement": "x"}
    text = message("nothing_missing", top, {"temperature": 2.0, "probe": 1.5}, None, LEVELS, [], "", [], 2.4)
    assert "e.p is significant" in text and "only 2.4x what the model error alone produces" in text
    assert "not significant" not in text
    top.update(explained=0.07, significant=False)
    text = message("nothing_missing", top, {"temperature": 1.0, "probe": 0.4}, None, LEVELS, [], "", [], 1.0)
    assert "would explain 7% of the weighted residual (all groups, none above noise)" in text
    assert "not significant (explains < 50%)" in text


# --- 4: no model-error estimate: said, null in JSON, never "0 K" --------------------------------------

def test_without_a_model_error_estimate_nothing_says_model_error_0(cabinet_at_95):
    from validate.diagnose import diagnosis_json, format_diagnosis
    d = cabinet_at_95
    assert d.model_error_rms is None
    assert all(e is None for _, e in d.levels.values())
    text = format_diagnosis(d)
    for out in (text, d.message):
        assert "model error 0 " not in out and "model error not estimated" in out
    assert d.message.startswith("nothing_missing: the residual is within 3x noise alone, the model error not estimated")
    assert "compare with noise only" in text
    doc = json.loads(json.dumps(diagnosis_json(d)))
    assert doc["model_error_rms"] is None
    assert all(v["model_error"] is None and v["model_error_estimated"] is False for v in doc["levels"].values())


def test_group_levels_none_without_an_estimate_and_the_factor_against_noise_alone():
    """e_g is None where no channel of the group has an estimate (no estimate at all, or the
    group's record has none); the factor is then RMS / noise."""
    class Ev:
        records = [type("R", (), {"noise": {"temperature": 0.05, "probe": 0.1}})()]
        mask = {"temperature": np.r_[np.ones(4, bool), np.zeros(2, bool)],
                "probe": np.r_[np.zeros(4, bool), np.ones(2, bool)]}

        def groups(self):
            return ["temperature", "probe"]

        def group_mask(self, g):
            return self.mask[g]

    ev = Ev()
    assert group_levels(ev, None) == {"temperature": (0.05, None), "probe": (0.1, None)}
    err = np.r_[np.full(4, 0.02), np.zeros(2)]
    partial = group_levels(ev, err, np.r_[np.ones(4, bool), np.zeros(2, bool)])
    assert partial["temperature"] == (0.05, pytest.approx(0.02)) and partial["probe"] == (0.1, None)
    r = np.r_[np.full(4, 0.1), np.full(2, 0.3)]
    f = residual_factors(ev, r, partial)
    assert f["probe"] == pytest.approx(3.0) and f["temperature"] == pytest.approx(0.1 / np.hypot(0.05, 0.02))
    text = message("nothing_missing", None, {"temperature": 1.0, "probe": 0.5}, None, partial, [], "", [])
    assert "noise alone for probe whose model error was not estimated" in text and "model error 0 " not in text


# --- 6: only the groups above the limit are "above"; each percentage names its base ------------

def test_unexplained_names_only_the_groups_above_the_limit_and_the_bases():
    """The audit's case: temperature 2.4x, probe 4.9x; the best candidate explains 37 % of the
    probes' weighted residual (17 % of all groups), a region 89 % of all groups."""
    top = {"effect": "ambient_stratification", "explained": 0.366, "explained_all": 0.171, "delta_bic": 38.0,
           "significant": False}
    regions = [{"region": "saddle", "power_W": 81.1, "schedule": "constant", "explained": 0.89}]
    text = message("unexplained", top, {"temperature": 2.4, "probe": 4.9}, None, LEVELS,
                   [("probe:Y2", 8.4)], "spindle off (1.0-1.7 h)", regions)
    assert text.startswith("unexplained: the residual is above noise and model error: probe 4.9x (noise 0.098 um, "
                           "model error 0.12 um); temperature 2.4x (noise 0.057 K, model error 0.028 K) is within the "
                           "limit of 3x")
    assert "explains only 37% of the weighted residual (of the groups above noise: probe), 17% of all groups" in text
    assert "not significant (explains < 50%)" in text
    assert "saddle (81.1 W constant, explains 89% of the weighted residual of all groups)" in text


def test_partly_explained_names_only_what_stays_above():
    top = {"effect": "a", "explained": 0.8, "delta_bic": 300.0, "significant": True, "confidence": 1.0,
           "statement": "a.p = 3 W"}
    regions = [{"region": "table", "power_W": 20.0, "schedule": "constant", "explained": 0.4}]
    text = message("partly_explained", top, {"temperature": 20.0, "probe": 2.0}, {"temperature": 5.0, "probe": 0.7},
                   LEVELS, [("temperature:table", 6.0)], "", regions)
    assert "what remains is still above noise and model error: temperature 5.0x" in text
    assert "probe 0.7x (noise 0.098 um, model error 0.12 um) is within the limit of 3x" in text
    assert "explains 80% of the weighted residual (of the groups above noise: temperature)" in text
    assert "40% of what remains (weighted, all groups)" in text
    assert "BIC weight 1.00 among the candidates" in text and "confidence" not in text


def test_factors_after_a_candidate_name_the_model_error_they_were_held_against():
    """With the model error estimated again with the candidate in the model (levels_after), the
    text says so and prints that estimate beside each factor after, not the baseline's."""
    top = {"effect": "a", "explained": 0.99, "delta_bic": 300.0, "significant": True, "confidence": 1.0,
           "statement": "a.p = 3 W"}
    after_levels = {"temperature": (0.05, 0.5), "probe": (0.098, 0.9)}
    text = message("partly_explained", top, {"temperature": 20.0, "probe": 2.0}, {"temperature": 5.0, "probe": 0.7},
                   LEVELS, [("temperature:table", 6.0)], "", [], levels_after=after_levels)
    assert ("what remains, against the model error estimated again with the candidate in the model, is still above "
            "noise and model error: temperature 5.0x (noise 0.05 K, model error 0.5 K)") in text
    assert "probe 0.7x (noise 0.098 um, model error 0.9 um)" in text
    text = message("explained", top, {"temperature": 20.0, "probe": 2.0}, {"temperature": 1.0, "probe": 0.7},
                   LEVELS, [], "", [], levels_after=after_levels)
    assert ("within noise and model error, the model error estimated again with the candidate in the model "
            "(temperature 1.0x (noise 0.05 K, model error 0.5 K)") in text


# --- 7: the BIC weight is labelled as such; the table marks who passes the test -------------------

def test_ranking_labels_the_bic_weight_and_marks_significance(cabinet_at_95):
    from validate.diagnose import format_diagnosis
    d = cabinet_at_95
    text = format_diagnosis(d)
    head = next(line for line in text.splitlines() if line.startswith("rank"))
    assert "BIC wt" in head and "sig" in head and "conf" not in head
    assert "not the probability that it is the cause" in text
    for c in d.candidates:
        assert c["significant"] == (c["delta_bic"] >= 10 and c["explained"] >= 0.5)
    rows = [line for line in text.splitlines() if line[:4].strip().isdigit()]
    assert rows[0].split()[5:7] == [f"{d.candidates[0]['confidence']:.2f}", "yes"]
    assert all(r.split()[6] == "no" for r in rows[1:])   # weight 0.00, and they fail the test
    from validate.report import _CAPTIONS, _ranking
    assert _ranking(d)    # the figure colours a significant candidate the verdict does not name apart
    assert "BIC weight" in _CAPTIONS["Candidate"] and "not the probability" in _CAPTIONS["Candidate"]


# --- 9: candidate parameters at a bound of their range are flagged -------------------------------

def test_at_bound_flags_members_at_their_range():
    from validate.diagnose import at_bound, bound_text, format_bounds
    floor = Candidate("floor.conductance", "parameter", "floor", "conductance", 2.0, 200.0, 20.0, 110.0, False, True)
    cab = Candidate("electrical_cabinet", "effect", "electrical_cabinet", "power", 0.0, 1000.0, 0.0, 40.0, True, False)
    front = Candidate("spindle_bearings.front_power", "parameter", "spindle_bearings", "front_power", 50.0, 450.0,
                      150.0, 300.0, True, True)
    g = np.zeros(3)
    assert at_bound(Fit((floor,), (200.0,), g, 0.0)) == ["floor.conductance"]
    assert at_bound(Fit((front,), (151.5,), g, 0.0)) == []
    pair = Fit((cab, front), (0.0, 210.0), g, 0.0)
    assert at_bound(pair) == ["electrical_cabinet.power"]
    assert bound_text(pair) == "electrical_cabinet.power at its bound 0 W (range 0 W to 1000 W, where it adds nothing)"
    assert format_bounds(Fit((floor,), (200.0,), g, 0.0)) == {"floor": {"conductance": ["2 W/m2K", "200 W/m2K"]}}


def test_candidates_at_a_bound_are_flagged_in_text_and_json(cabinet_at_95):
    from validate.diagnose import diagnosis_json, format_diagnosis
    d = cabinet_at_95
    doc = json.loads(json.dumps(diagnosis_json(d)))
    flagged = 0
    for c, j in zip(d.candidates, doc["candidates"]):
        want = []
        for e, vals in c["values_si"].items():
            for p, v in vals.items():
                f = next(f for f in d.fits if f.name == c["effect"])
                cand = next(x for x in f.candidates if x.effect == e and x.parameter == p)
                if min(abs(v - cand.lower), abs(v - cand.upper)) <= 1e-3 * (cand.upper - cand.lower):
                    want.append(f"{e}.{p}")
        assert j["at_bound"] == want and set(j["bounds"]) == set(j["parameters"])
        flagged += bool(want)
    assert flagged, "the case has a candidate at a bound (floor.conductance at 2 W/m2K)"
    text = format_diagnosis(d, top=len(d.candidates))
    for c in d.candidates:
        row = next(line for line in text.splitlines() if line[:4].strip().isdigit() and f" {c['effect']} " in line)
        assert ("AT ITS BOUND" in row) == bool(c["at_bound"]), row


# --- 11: units alongside every dimensional number of the JSON ------------------------------------

def test_json_numbers_carry_their_units(cabinet_at_95, machine, mm):
    from validate.diagnose import diagnose, diagnosis_json
    d = cabinet_at_95
    doc = json.loads(json.dumps(diagnosis_json(d)))
    units = doc["baseline"]["units"]
    assert units["temperature:motor"] == "K" and units["probe:Z"] == "um"
    for c in doc["candidates"]:
        assert c["rmse_after_units"] == units and set(c["rmse_after"]) == set(units)
        assert all(v.endswith((" W", " W/m2K", " W/K", " K/m", " 1/m")) for vals in c["model_parameters"].values()
                   for v in vals.values())
    assert doc["candidates"][0]["model_parameters"] == {"electrical_cabinet": {"power": "95 W"}}
    assert doc["calibration"]["units"] == units and doc["calibration"]["expansion_unit"] == "fraction of alpha"
    assert all(v["unit"] == "fraction of alpha" for v in list(doc["nuisance"].values())
               + list(doc["nuisance_baseline"].values()))
    assert {"residual_factor", "candidates[].explained", "candidates[].confidence"} <= set(doc["dimensionless"])
    # with an estimate: model_error_rms carries its units (a cheap diagnosis: no candidate, one run)
    e = d.evidence
    err = np.full(len(e.records[0].channels), 0.01)
    plain = diagnose(e.records[0].ds, machine, e.records[0].scenario, d.spec, mm=mm, candidates=[],
                     parameters=False, model_error=err, localise_regions=False)
    doc = json.loads(json.dumps(diagnosis_json(plain)))
    assert doc["model_error_rms"]["units"] == units
    assert all(v["model_error"] == pytest.approx(0.01) for v in doc["levels"].values())


# --- the helpers that apply and report a diagnosis refuse what is not this diagnosis's (API audit) ---

def test_apply_and_report_refuse_what_is_not_this_diagnosis(cabinet_at_95, tmp_path):
    """A wrong-shaped or NaN model vector, an unknown group, another machine, sections that are
    no (title, text) pairs, a diagnosis without fits: one InputError naming the argument, and
    ``write_report`` leaves no folder behind (it made one before it failed)."""
    from geometries import build_machine
    from twin.errors import InputError
    from validate.apply import apply_top, format_before_after, group_rms
    from validate.report import write_report

    d = cabinet_at_95
    base = d.base
    for call, field in ((lambda: format_before_after(d, base[:5]), "after"),
                        (lambda: format_before_after(d, np.full_like(base, np.nan)), "after"),
                        (lambda: format_before_after(d, base, base[:3]), "calibrated"),
                        (lambda: group_rms(d, base, "nope"), "group"),
                        (lambda: apply_top(None), "d"),
                        (lambda: apply_top(replace(d, fits=[])), "d"),
                        (lambda: write_report(d, build_machine("gantry-ram"), tmp_path / "r"), "machine"),
                        (lambda: write_report(d, "cframe-vmc", tmp_path / "r"), "machine"),
                        (lambda: write_report(d, d.twin.machine, tmp_path / "r", sections="hello"), "sections"),
                        (lambda: write_report(d, d.twin.machine, tmp_path / "r", after=base[:7]), "after"),
                        (lambda: write_report(d, d.twin.machine, tmp_path / "no" / "r"), "folder")):
        with pytest.raises(InputError) as err:
            call()
        assert err.value.field == field, str(err.value)
        assert not (tmp_path / "r").exists() and not (tmp_path / "no").exists()
    assert group_rms(d, base, "temperature") > 0
