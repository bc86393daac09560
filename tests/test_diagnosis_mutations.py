"""The diagnosis's decision and text code held to what it documents, where a mutation audit found
no test that would notice a change: the worst time of a C-axis test, the per-measurement "loud"
blocks of the significance share, the verdict message's bases, limits and omitted parts, the
region map's ranking, schedules and air sensors, the reasoning per channel and phase, the printed
factors after a candidate and the JSON's ``levels_after``, the expansion nuisance's text,
Gauss-Newton's best point and a pair's statement.

Every test runs on small stand-ins (records with channels, groups and samples; no twin run, no
mesh): the whole file takes a few seconds."""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace as NS

import numpy as np
import pytest

from twin.rotary import RotarySchedule
from twin.scenario import Ambient, Scenario
from validate import verdict as V
from validate.candidates import Candidate
from validate.channels import Phase
from validate.evidence import Evidence
from validate.fit import BoundedFitter, gauss_newton
from validate.search import Fit

LEVELS = {"temperature": (0.057, 0.028), "probe": (0.098, 0.12)}
FRONT = Candidate("spindle_bearings.front_power", "parameter", "spindle_bearings", "front_power", 50.0, 450.0,
                  150.0, 300.0, True, True)
CABINET = Candidate("electrical_cabinet", "effect", "electrical_cabinet", "power", 0.0, 1000.0, 0.0, 40.0, True, False)


def _record(label, measured, groups, channels=None, noise=None, model_error=None, phases=(), t0=0.0, dt=60.0):
    """A record stand-in: (n_t, n_ch) samples every ``dt`` s, its groups, noise levels and
    per-channel model-error RMS (None: not estimated)."""
    measured = np.asarray(measured, float)
    return NS(label=label, measured=measured, groups=list(groups), phases=list(phases), t0=t0,
              channels=list(channels or [f"{g}:{k}" for k, g in enumerate(groups)]),
              times=np.arange(len(measured)) * dt, noise=dict(noise or {}),
              model_error=None if model_error is None else np.asarray(model_error, float))


# --- validate.verdict: worst time, loud blocks --------------------------------------------------

def test_the_worst_time_of_a_c_axis_test_is_a_c_axis_phase():
    """worst_time looks for the phase holding most of sum (w r)^2 among the spindle's *and the C
    axis's* phases (a gantry's C-axis test has C-axis phases only, the spindle at rest): residual
    0.1 in the first hour (C axis on), 1.0 in the second (off), weights 1: the second hour holds
    6 x 1 against 7 x 0.01 (the off phase closed, holding the last sample), printed on the log's
    clock, t0 = 1 h: 'C axis off (2.0-3.0 h)'. An ambient phase, however loud, is no answer."""
    t = np.arange(0.0, 7201.0, 600.0)
    phases = [Phase("c_axis", "C axis on 2500 rpm", 0.0, 3600.0),
              Phase("c_axis", "C axis off", 3600.0, 7200.0, closed=True),
              Phase("ambient", "ambient steady", 0.0, 7200.0, closed=True)]
    res = np.where(t < 3600.0, 0.1, 1.0)[:, None]
    rec = _record("m", res, ["laser"], phases=phases, t0=3600.0, dt=600.0)
    ev = Evidence([rec])
    assert V.worst_time(ev, res.ravel(), np.ones(res.size)) == "C axis off (2.0-3.0 h)"


def test_a_quiet_measurement_is_loud_only_beyond_its_noise_and_model_error():
    """loud_blocks (the significance share's channels with several measurements): a record's
    group block counts when RMS(r) / sqrt(noise^2 + e^2) > WITHIN, e the RMS of the record's
    per-channel model-error estimate. A spindle run at 1.0 K over sqrt(0.05^2 + 0.02^2) is 18.6x:
    loud; a rest run at 0.3 K over sqrt(0.05^2 + 0.2^2) = 0.206 K is 1.46x: not loud, though it
    is 6x its noise alone. The share's set A is then exactly the spindle run's block."""
    spin = _record("spin", np.full((5, 2), 1.0), ["temperature"] * 2, noise={"temperature": 0.05},
                   model_error=[0.02, 0.02])
    rest = _record("rest", np.full((4, 2), 0.3), ["temperature"] * 2, noise={"temperature": 0.05},
                   model_error=[0.2, 0.2])
    ev = Evidence([spin, rest])
    r = ev.measured
    (loud,) = V.loud_blocks(ev, r, ["temperature"])
    np.testing.assert_array_equal(loud, np.r_[np.ones(10, bool), np.zeros(8, bool)])
    share = V.Share(ev, BoundedFitter(r, np.ones_like(r)), {"temperature": 10.0}, r)
    np.testing.assert_array_equal(share.mask, loud)
    # without an estimate in the rest run, it is 6x its noise: loud too
    rest.model_error = None
    assert len(V.loud_blocks(ev, r, ["temperature"])) == 2


# --- validate.verdict: the message's bases, limits and parts ------------------------------------

def test_the_share_base_says_all_groups_when_every_group_is_above_noise():
    """share_text: '(all groups)' when every group is above WITHIN (the share counts them all),
    '(of the groups above noise: ...)' when only some are, '(all groups, none above noise)' when
    none is."""
    assert V.share_text({"temperature": 5.0, "probe": 4.0}) == "(all groups)"
    assert V.share_text({"temperature": 5.0, "probe": 1.0}) == "(of the groups above noise: temperature)"
    assert V.share_text({"temperature": 2.0, "probe": 1.0}) == "(all groups, none above noise)"


def test_a_factor_at_or_near_the_limit_is_listed_on_its_side_with_two_decimals():
    """_above_text / _factor_text: a group at exactly 3.0 is 'within the limit of 3x' (not above,
    and not dropped from the text); a factor within 0.05 of the limit prints two decimals, so an
    above-limit 3.04 never reads as the limit's '3.0x' and a within-limit 2.96 as '3.0x'."""
    text = V.message("unexplained", None, {"temperature": 3.0, "probe": 4.0}, None, LEVELS, [], "", [])
    assert ("above noise and model error: probe 4.0x (noise 0.098 um, model error 0.12 um); temperature 3.00x "
            "(noise 0.057 K, model error 0.028 K) is within the limit of 3x") in text
    text = V.message("unexplained", None, {"temperature": 3.04, "probe": 2.96}, None, LEVELS, [], "", [])
    assert "above noise and model error: temperature 3.04x (noise" in text
    assert "probe 2.96x (noise 0.098 um, model error 0.12 um) is within the limit of 3x" in text


def test_every_printed_factor_stays_on_its_side_of_the_limit():
    """ratio_text: the printed factor compares with the limit as the factor does under the verdict's
    rule (f > 3 above the envelope; beyond >= 10 names a candidate): 3.004 is '3.004x', not the
    limit's '3.00x'; 9.996 along the signature is '9.996x', not '10.00x'. The summary lines of
    format_diagnosis use it too (they printed 3.04 as '3.0x' beside a message saying 3.04x)."""
    from validate.diagnosis_text import format_diagnosis

    assert [V.ratio_text(f) for f in (4.93, 3.04, 3.0, 2.96, 3.004)] == ["4.9x", "3.04x", "3.00x", "2.96x", "3.004x"]
    assert [V.ratio_text(f, V.BEYOND, strict=False) for f in (9.996, 10.0, 12.34)] == ["9.996x", "10.00x", "12.3x"]
    d = _diagnosis()
    d.residual_factor = {"temperature": 3.04, "probe": 1.2}
    d.residual_factor_after = {"temperature": 3.004, "probe": 0.5}
    d.beyond_model_error = 9.996
    text = format_diagnosis(d)
    assert "temperature: residual 3.04x noise and model error" in text
    assert "; 3.004x after the top candidate" in text
    assert "top candidate's fitted change: 9.996x what the model error alone" in text


def test_a_named_candidate_that_lifts_a_group_above_the_limit_is_partly_explained():
    """decide, every factor before <= 3 and a significant candidate beyond the model error (>= 10x
    along its signature): ``explained`` only when it leaves every factor <= 3 (README: explained
    "leaves every factor <= 3"); one that lifts a group to 3.5x is ``partly_explained``."""
    before = {"temperature": 2.0, "probe": 1.0}
    assert V.decide(before, True, {"temperature": 2.5, "probe": 0.5}, 50.0) == "explained"
    assert V.decide(before, True, {"temperature": 3.5, "probe": 0.5}, 50.0) == "partly_explained"
    assert V.decide(before, True, {"temperature": 3.5, "probe": 0.5}, 5.0) == "nothing_missing"


def test_not_significant_names_each_failing_condition():
    """significance_reasons: dBIC < 10 is named with its number ('dBIC 4.0 < 10'), explained < 50 %
    as 'explains < 50%', both joined by 'and'; the pair-test wording only when neither fails."""
    top = {"effect": "e.p", "explained": 0.7, "delta_bic": 4.0, "significant": False}
    assert V.significance_reasons(top, (10.0, 0.5)) == "dBIC 4.0 < 10"
    top["explained"] = 0.2
    assert V.significance_reasons(top, (10.0, 0.5)) == "dBIC 4.0 < 10 and explains < 50%"
    top.update(explained=0.7, delta_bic=12.0)
    assert V.significance_reasons(top, (10.0, 0.5)) == "it fails the pair test"
    text = V.message("nothing_missing", {**top, "explained": 0.7, "delta_bic": 4.0}, {"temperature": 2.0, "probe": 1.0},
                     None, LEVELS, [], "", [], 1.5)
    # the ratio along the signature is stated for a candidate that is not significant too
    assert ("dBIC 4.0: not significant (dBIC 4.0 < 10); along its signature the fitted change is 1.5x what the "
            "model error alone produces") in text


def test_explained_within_the_envelope_states_the_factors_after_the_candidate():
    """``explained`` with every factor <= 3 (beyond >= 10): the message gives the factors before
    (within the envelope), the ratio along the signature and the factors *after* the candidate,
    not the ones before again."""
    top = {"effect": "electrical_cabinet.power", "explained": 0.6, "delta_bic": 300.0, "significant": True,
           "confidence": 1.0, "statement": "electrical_cabinet.power is 125 W, not 90 W"}
    text = V.message("explained", top, {"temperature": 2.1, "probe": 1.2}, {"temperature": 1.4, "probe": 0.7},
                     LEVELS, [], "", [], 74.7)
    assert "the residual before it was within noise and model error (temperature 2.1x (noise 0.057 K" in text
    assert ("but along its signature the fitted change is 74.7x what the model error alone produces; after it: "
            "temperature 1.4x (noise 0.057 K, model error 0.028 K), probe 0.7x (noise 0.098 um, model error 0.12 um)"
            ) in text


def test_partly_explained_and_unexplained_say_where_and_when():
    """partly_explained names the worst channels of what remains ('worst at temperature:table
    6.0x'); unexplained names them and the phase holding most of the residual ('mostly during
    spindle off (1.0-1.7 h)')."""
    top = {"effect": "a", "explained": 0.8, "delta_bic": 300.0, "significant": True, "confidence": 1.0,
           "statement": "a.p = 3 W"}
    text = V.message("partly_explained", top, {"temperature": 20.0, "probe": 2.0}, {"temperature": 5.0, "probe": 0.7},
                     LEVELS, [("temperature:table", 6.0), ("temperature:x", 4.2)], "", [])
    assert "; worst at temperature:table 6.0x, temperature:x 4.2x" in text
    top = {"effect": "b", "explained": 0.3, "explained_all": 0.1, "delta_bic": 38.0, "significant": False}
    text = V.message("unexplained", top, {"temperature": 2.4, "probe": 4.9}, None, LEVELS,
                     [("probe:Y2", 8.4)], "spindle off (1.0-1.7 h)", [])
    assert "worst at probe:Y2 8.4x, mostly during spindle off (1.0-1.7 h)" in text


# --- validate.localise: ranking, schedules, air sensors -----------------------------------------

def test_the_region_map_is_ranked_best_first_and_keeps_top_regions(monkeypatch):
    """localise ranks regions by the share a generic heat input there explains, best first, and
    keeps ``top`` of them. Orthonormal columns u_k and r = sum a_k u_k (a = 6, 5, ..., 1): region
    k alone explains a_k^2 / sum a^2 at a_k W; with top = 3 the map is r0, r1, r2, exactly."""
    import validate.localise as L
    q, _ = np.linalg.qr(np.random.default_rng(5).standard_normal((60, 6)))
    a = np.arange(6, 0, -1.0)
    cols = q.T[::-1]                                   # the columns given worst first
    r = q @ a
    labels = [(f"r{k}", "volume", "constant") for k in range(6)][::-1]
    monkeypatch.setattr(L, "region_columns", lambda *args, **kw: (cols, labels))
    regions = L.localise(None, BoundedFitter(r, np.ones_like(r)), None, None, top=3, twin=object())
    assert [x["region"] for x in regions] == ["r0", "r1", "r2"]
    total = float(a @ a)
    assert [x["explained"] for x in regions] == pytest.approx([36 / total, 25 / total, 16 / total], rel=1e-9)
    assert [x["power_W"] for x in regions] == pytest.approx([6.0, 5.0, 4.0], rel=1e-9)


def test_region_schedules_are_dimensionless_shapes_of_the_logged_inputs():
    """schedules: s(t) [-]: 'constant' always; 'spindle_on' (0/1) when a spindle turns; 'speed' =
    |n| / n_max only with two or more speeds (else it is spindle_on again), so its power is in W
    at the top speed; 'c_axis_on' the C axis's duty where it turns (0 in a record without one)."""
    from validate.localise import schedules
    sc = Scenario("s", ((600.0, 3000.0), (600.0, 6000.0), (600.0, 0.0)), Ambient("constant", mean=20.0), 60.0)
    one = Scenario("one", ((600.0, 6000.0), (600.0, 0.0)), Ambient("constant", mean=20.0), 60.0)
    rest = Scenario("rest", ((600.0, 0.0),), Ambient("constant", mean=20.0), 60.0)
    t = np.array([300.0, 900.0, 1500.0])
    s = schedules([sc])
    assert list(s) == ["constant", "spindle_on", "speed"]
    np.testing.assert_allclose(s["speed"](sc, t), [0.5, 1.0, 0.0])
    np.testing.assert_allclose(s["spindle_on"](sc, t), [1.0, 1.0, 0.0])
    np.testing.assert_allclose(s["constant"](sc, t), [1.0, 1.0, 1.0])
    assert list(schedules([one])) == ["constant", "spindle_on"]
    assert list(schedules([rest])) == ["constant"]
    c = replace(rest, c_axis=RotarySchedule(((300.0, 2500.0, 0.4), (300.0, 0.0, 1.0))))
    s = schedules([c, rest])
    assert list(s) == ["constant", "c_axis_on"]
    np.testing.assert_allclose(s["c_axis_on"](c, np.array([100.0, 400.0])), [0.4, 0.0])
    np.testing.assert_allclose(s["c_axis_on"](rest, np.array([100.0, 400.0])), [0.0, 0.0])


def test_region_columns_leave_sensors_in_the_air_unheated(monkeypatch):
    """region_columns: a sensor in the air reads the room, so a generic heat input on the machine
    gives it no response (its column is 0) while a sensor on the structure keeps its response;
    the integration grid covers the record with at most max_steps steps."""
    import validate.localise as L
    sc = Scenario("s", ((1800.0, 6000.0),), Ambient("constant", mean=20.0), 60.0)
    monkeypatch.setattr(L, "partition_sources", lambda mm: [("saddle", "volume", np.array([0]))])
    monkeypatch.setattr(L, "shaped_load", lambda name, kind, where, shape, scenario: (name, shape))
    grids = []

    def responses(scenario, spec, observers, loads, times):
        grids.append(np.asarray(times))
        return {"temperature": np.full((len(times), 2, len(loads)), 0.7)}

    eng = NS(observers=lambda: [], temperature=NS(air=np.array([False, True])),
             readings=lambda one, spec, dt, bias=True: one["temperature"])
    rec = NS(scenario=sc, times=np.arange(31) * 60.0, columns=np.array([0, 1]), engine=eng)
    cols, labels = L.region_columns(NS(records=[rec]), None, NS(mm=None, responses=responses), max_steps=100)
    assert labels == [("saddle", "volume", "constant"), ("saddle", "volume", "spindle_on")]
    block = cols.reshape(2, 31, 2)
    assert np.all(block[:, :, 1] == 0.0) and np.allclose(block[:, :, 0], 0.7)
    assert grids[0][-1] >= rec.times[-1] and len(grids[0]) <= 101


# --- validate.diagnosis_text: reasoning, the printed factors and nuisance, the JSON -------------

def test_reasoning_ranks_channels_by_the_share_they_explain_on_the_logs_clock():
    """reasoning: per channel share = sum e_before / SSE_0 and explained = 1 - sum e_after /
    sum e_before; channels ranked by share x explained. r = 2 on channel a, 1 on b, g = 1 on both:
    a holds 24/30 = 0.8 and loses 75 % (0.6), b holds 0.2 and loses all of it (0.2): a first,
    though b's explained fraction is larger. Phases are on the log's clock (t0 = 2 h)."""
    from validate.diagnosis_text import reasoning
    phases = [Phase("spindle", "spindle on 9000 rpm", 0.0, 180.0),
              Phase("spindle", "spindle off", 180.0, 300.0, closed=True)]
    rec = _record("m", np.zeros((6, 2)), ["temperature"] * 2, ["temperature:a", "temperature:b"], phases=phases,
                  t0=7200.0)
    ev = Evidence([rec])
    r = np.tile([2.0, 1.0], 6)
    d = NS(evidence=ev, residual_after=lambda g: r - g, weights_flat=np.ones(12))
    why = reasoning(d, np.ones(12))
    chans = why["channels"]
    assert [c["channel"] for c in chans] == ["temperature:a", "temperature:b"]
    assert (chans[0]["share"], chans[0]["explained"]) == pytest.approx((0.8, 0.75), rel=1e-12)
    assert (chans[1]["share"], chans[1]["explained"]) == pytest.approx((0.2, 1.0), rel=1e-12)
    on, off = why["phases"]
    assert (on["start_h"], on["end_h"]) == pytest.approx((2.0, 2.05), rel=1e-12)
    assert (off["start_h"], off["end_h"]) == pytest.approx((2.05, 7500.0 / 3600.0), rel=1e-12)
    assert on["share"] == pytest.approx(0.5, rel=1e-12) and on["explained"] == pytest.approx(0.8, rel=1e-12)


def _diagnosis():
    """A partly_explained diagnosis stand-in: the model error estimated again with the candidate
    (levels_after), the cast iron's expansion at its bound in the baseline, inside it with the
    candidate."""
    rec = NS(label="m", phases=[Phase("spindle", "spindle on 9000 rpm", 0.0, 600.0)], t0=0.0)
    base = {"grey_cast_iron": {"change": 0.1, "band": 0.1, "unit": "fraction of alpha", "at_bound": True,
                               "source": "s"}}
    with_top = {"grey_cast_iron": {"change": 0.04, "band": 0.1, "unit": "fraction of alpha", "at_bound": False,
                                   "source": "s"}}
    return NS(channels=["temperature:a", "probe:Z"], groups=["temperature", "probe"],
              baseline_rmse=np.array([0.2, 0.3]),
              calibrated_rmse=np.array([0.2, 0.25]), expansion={"grey_cast_iron": 0.1},
              model_error_rms=np.array([0.02, 0.1]), error_resolution="default",
              evidence=NS(labels=["m"], records=[rec]), n_eff=40.0, runs=3,
              residual_factor={"temperature": 5.0, "probe": 2.0},
              residual_factor_after={"temperature": 2.5, "probe": 0.5},
              levels={"temperature": (0.05, 0.02), "probe": (0.1, 0.1)},
              levels_after={"temperature": (0.05, 0.3), "probe": (0.1, 0.4)}, beyond_model_error=12.5,
              nuisance_baseline=base, nuisance=with_top, verdict="partly_explained", significant=True, named=True,
              missing_channels=[], not_used=[], candidates=[], test=(10.0, 0.5), regions=[],
              message="partly_explained: x")


def test_the_printed_factors_after_name_the_model_error_estimated_again():
    """format_diagnosis prints, per group, the factor before, the factor after the top candidate
    and the model error of the model with the candidate it was held against (levels_after, the
    JSON's numbers), not the baseline's; and the ratio along the signature."""
    from validate.diagnosis_text import format_diagnosis
    text = format_diagnosis(_diagnosis())
    assert ("  temperature: residual 5.0x noise and model error (noise 0.05 K, model error 0.02 K); 2.5x after the "
            "top candidate (against the model error of the model with it, 0.3 K, estimated again)") in text
    assert ("  probe: residual 2.0x noise and model error (noise 0.1 um, model error 0.1 um); 0.5x after the top "
            "candidate (against the model error of the model with it, 0.4 um, estimated again)") in text
    assert "top candidate's fitted change: 12.5x what the model error alone produces along its signature" in text


def test_the_expansion_nuisance_is_printed_in_percent_of_alpha_and_flagged_at_its_bound():
    """nuisance_text: each material's fitted change of alpha in percent with its band, ', AT ITS
    BOUND' when it sits at the band's end; format_diagnosis prints the baseline's and, when the
    verdict names a candidate, the one fitted with it."""
    from validate.diagnosis_text import format_diagnosis, nuisance_text
    d = _diagnosis()
    assert nuisance_text(d.nuisance_baseline) == "grey_cast_iron +10.0% (band +-10%, AT ITS BOUND)"
    assert nuisance_text(d.nuisance) == "grey_cast_iron +4.0% (band +-10%)"
    text = format_diagnosis(d)
    assert ("Nuisance (thermal expansion within each material's band), baseline: grey_cast_iron +10.0% (band +-10%, "
            "AT ITS BOUND)\n  with the top candidate: grey_cast_iron +4.0% (band +-10%)") in text


def test_the_json_carries_the_factors_after_and_the_levels_they_were_held_against():
    """diagnosis_json: residual_factor_after, beyond_model_error and levels_after (noise, model
    error, estimated, unit per group: the same numbers as the text) when the model error was
    estimated again; levels_after null when it was not."""
    from validate.diagnosis_text import diagnosis_json
    d = _diagnosis()
    doc = diagnosis_json(d)
    assert doc["residual_factor_after"] == {"temperature": 2.5, "probe": 0.5}
    assert doc["beyond_model_error"] == 12.5 and doc["named"] is True and doc["verdict"] == "partly_explained"
    assert doc["levels_after"] == {"temperature": {"noise": 0.05, "model_error": 0.3, "model_error_estimated": True,
                                                   "unit": "K"},
                                   "probe": {"noise": 0.1, "model_error": 0.4, "model_error_estimated": True,
                                             "unit": "um"}}
    assert doc["levels"]["temperature"]["model_error"] == 0.02
    d.levels_after = {}
    assert diagnosis_json(d)["levels_after"] is None


# --- validate.fit and validate.fit_text ---------------------------------------------------------

def test_gauss_newton_never_returns_a_point_worse_than_its_start():
    """gauss_newton keeps p_k + d only if it lowers the weighted SSE, else halves d: y(p) =
    exp(-p t) - 1, truth p = 1.7, from p = 8 in [0, 40] the full first step overshoots to the
    lower bound (worse than the start); one iteration returns the halved step, whose SSE is below
    the start's, and the response returned is that point's."""
    t = np.linspace(0, 1, 200)
    ev = lambda p: np.exp(-p[0] * t) - 1   # noqa: E731
    f = BoundedFitter(ev([1.7]), np.ones_like(t))
    start = f.sse(ev([8.0]))
    p, g, sse, evals = gauss_newton(f, ev, np.array([8.0]), np.array([0.0]), np.array([40.0]), np.array([False]), {}, 1)
    assert sse < start and sse == pytest.approx(f.sse(ev(p)), rel=1e-12)
    np.testing.assert_allclose(g, ev(p), rtol=0, atol=1e-15)
    assert evals == 4 and 0.0 < p[0] < 8.0


def test_a_pairs_statement_names_both_members():
    """statement: each member's text, ' and '-joined: a parameter 'is v, not p_0', an added effect
    '= v'."""
    from validate.fit_text import statement
    pair = Fit((FRONT, CABINET), (210.0, 40.0), np.zeros(3), 0.0)
    assert statement(pair) == ("spindle_bearings.front_power is 210 W, not 150 W and "
                               "electrical_cabinet.power = 40 W")
