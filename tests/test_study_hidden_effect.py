"""The diagnosis study's cases, scoring and rendering (the study itself is a long run behind its
own command: ``python -m validate.studies.hidden_effect``; one small case of each class runs in
tests/test_diagnose.py)."""

from __future__ import annotations

import pytest

from geometries import build_machine
from validate.studies import hidden_effect as study
from validate.studies.diagnosis_cases import CLASSES, all_cases, score


def _row(cls, case, verdict, top, rank=None, err=float("nan"), conf=1.0, region_rank=None, plain=1.0, after=0.1):
    return score({"class": cls, "case": case, "scenario": "s", "expected": "", "true": "", "fitted": "", "rank": rank,
                  "verdict": verdict, "top": top, "top_kind": "effect", "top_confidence": conf, "explained": 0.9,
                  "delta_bic": 50.0, "strength_error": err, "factor_temperature": 5.0, "factor_probe": 5.0,
                  "probe_rmse_uncalibrated_um": plain, "probe_rmse_before_um": plain, "probe_rmse_after_um": after,
                  "regions": "saddle table", "region_rank": region_rank, "nuisance_at_bound": "", "runs": 40,
                  "seconds": 60.0, "message": "m", "candidates_ranked": top})


def test_cases_cover_every_class_and_every_uncertain_parameter():
    """Every class is present; the parameter class has every declared uncertain parameter of the
    machine's default effects (but the door stream's, which acts only while a door is open and
    no study scenario opens one), each off by 20-60 %, on at least one scenario, and several
    scenarios per class."""
    from twin.effects import EFFECTS
    machine = build_machine("cframe-vmc")
    cases = all_cases(machine)
    assert {c.cls for c in cases} == set(CLASSES)
    declared = {f"{e}.{u.name}" for e in machine.default_effects if e != "door_stream"
                for u in EFFECTS[e].uncertain}
    assert "stratified_swing.growth" in declared and "door_stream" in machine.default_effects
    params = [c for c in cases if c.cls == "parameter"]
    assert {c.expect[0][0] for c in params} == declared
    for c in params:
        name, value = c.expect[0]
        effect, pname = name.split(".")
        assert 0.2 - 1e-9 <= abs(value / EFFECTS[effect].parameter(pname).default - 1) <= 0.6 + 1e-9
    for cls in CLASSES:
        assert len({c.scenario for c in cases if c.cls == cls}) >= 2, cls
    outside = [c for c in cases if c.cls == "outside"]
    assert len({c.region for c in outside}) == 3
    # the outside regions are heated by no library effect: none of them is a role's region
    assert all(c.region not in ("spindle", "motor", "front_bearing", "rear_bearing") for c in outside)


def test_scores_and_rates_follow_the_numbers():
    """Per class: hidden/parameter/pair pass when named first with the verdict naming them and every
    strength within 25 % (hidden: probe RMSE reduced >= 70 %); outside when unexplained or partly
    explained, no library candidate at confidence > 0.5 and the true region in the top two; none
    when nothing_missing. The rates table counts exactly those."""
    rows = [_row("hidden", "a", "explained", "a", rank=1, err=0.05),
            _row("hidden", "b", "explained", "c", rank=2, err=0.05),
            _row("parameter", "p", "explained", "p", rank=1, err=0.3),
            _row("outside", "o1", "unexplained", "x", conf=0.9, region_rank=2),
            _row("outside", "o2", "partly_explained", "x", conf=0.8, region_rank=1),
            _row("pair", "a+b", "explained", "a+b", rank=1, err=0.1),
            _row("none", "(none)", "nothing_missing", "x"),
            _row("none", "(none)", "explained", "x")]
    assert [r["pass"] for r in rows] == [True, False, False, True, False, True, True, False]
    rates = {(c, w.split(" (")[0]): rate for c, w, rate, bar, n in study.class_rates(rows)}
    assert rates[("hidden", "hidden effect named first")] == 0.5
    assert rates[("parameter", "fitted within 25 %")] == 0.0
    assert rates[("outside", "no library candidate named with confidence > 0.5")] == 0.5
    assert rates[("outside", "true region among the top two")] == 1.0
    assert rates[("none", "verdict nothing_missing")] == 0.5
    md = study.markdown(rows, "python -m validate.studies.hidden_effect", False)
    assert "| outside | true region among the top two | 100% | 67% | 2 | **pass** |" in md
    fa = study.failure_analysis(rows)
    assert "hidden: b" in fa and "ranked 2 behind c" in fa and "library candidate x named with confidence 0.8" in fa


@pytest.mark.parametrize("argv, needle", [
    (["--truth", "huge"], "unknown mesh resolution 'huge'"),
    (["--truth", "coarse", "--model", "default"], "coarser than --model"),
    (["--effects", "nonsense"], "unknown effects: nonsense"),
    (["--classes", "hidden,weird"], "unknown class 'weird'"),
    (["--classes", "none", "--scenarios", "no-such-test"], "--scenarios: no case of the classes none matches "
                                                           "'no-such-test'"),
    # a text that matches nothing is refused even beside one that matches (it was dropped)
    (["--classes", "none", "--cases", "(none),zzz"], "--cases: no case of the classes none matches 'zzz'"),
    (["--classes", "none", "--scenarios", "etve,nosuch"], "--scenarios: no case of the classes none matches 'nosuch'"),
    # --analyse runs no case: the options that choose cases or meshes would be ignored
    (["--analyse", "--classes", "bogus"], "--analyse: re-renders an existing table and runs no case"),
    (["--analyse", "--jobs", "8"], "leave out --jobs"),
])
def test_bad_options_are_one_clear_error(capsys, argv, needle, tmp_path):
    argv = argv + ["-o", str(tmp_path / "he")]
    with pytest.raises(SystemExit) as e:
        study.main(argv)
    assert e.value.code == 2
    assert needle in capsys.readouterr().err


def test_room_effects_are_hidden_only_where_the_room_moves():
    """belt-vmc lacks the C-frame's workshop effects, so the study hides them: stratified_swing acts
    only while the room air moves (flux h s (z - z_ref) (T_air(t) - T_air(0))), so it is hidden on
    the day-night record, not on a spindle test in a constant room; door_stream acts only during a
    scenario's door event, which no study scenario has, so it is not hidden at all."""
    from twin.model import parse_settings
    cases = {c.label: c for c in all_cases(build_machine("belt-vmc"), ["hidden"])}
    assert cases["stratified_swing"].scenario == "etve-day-night"
    assert "door_stream" not in cases
    # its truth's setting reads back as the default 1 /m (a unit starting with a digit keeps its space)
    assert cases["stratified_swing"].truth_settings == ("stratified_swing.growth=1 1/m",)
    assert parse_settings(list(cases["stratified_swing"].truth_settings),
                          ("stratified_swing",))["stratified_swing"]["growth"] == 1.0
