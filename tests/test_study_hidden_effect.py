"""The hidden-effect study's scoring and rendering (the study itself is a long run behind its own
command: ``python -m validate.studies.hidden_effect``)."""

from __future__ import annotations

import pytest

from validate.studies import hidden_effect as study


def _row(hidden, scenario, rank, significant, true, fitted, plain, calibrated, after):
    return study.score({
        "hidden": hidden, "scenario": scenario, "rank": rank, "top": hidden if rank == 1 else "other",
        "significant": significant, "parameter": "power", "unit": "W", "true": true, "fitted": fitted,
        "probe_rmse_uncalibrated_um": plain, "probe_rmse_before_um": calibrated, "probe_rmse_after_um": after,
        "temperature_rmse_before_K": 0.5, "temperature_rmse_after_K": 0.1,
        "explained": 0.9, "delta_bic": 50.0, "confidence": 1.0,
        "truth_mesh": "fine", "model_mesh": "default", "error_mesh": "coarse", "_reasoning": {}})


def test_bar_and_failure_analysis_follow_the_numbers():
    """score(): strength error |fitted/true - 1|, reduction 1 - after/plain (the bar) and
    1 - after/calibrated (the effect's own share), pass only if all hold. The bar table counts
    exactly the rows that meet each criterion; the failure analysis gives signal =
    sqrt(plain^2 - floor^2) against the nothing-hidden (calibrated) floor of the scenario."""
    nan = float("nan")
    rows = [_row("spindle_motor", "s", 1, True, 60.0, 57.0, 1.0, 0.8, 0.1),
            _row("test_bar_contact", "s", 1, True, 20.0, 12.0, 0.5, 0.4, 0.3),
            _row("(none)", "s", None, False, nan, nan, 0.35, 0.3, nan)]
    assert rows[0]["strength_error"] == pytest.approx(0.05) and rows[0]["probe_reduction"] == pytest.approx(0.9)
    assert rows[0]["probe_reduction_effect"] == pytest.approx(0.875) and rows[0]["pass"]
    assert not rows[1]["pass"] and rows[2]["pass"]
    md = study.markdown(rows, False, "python -m validate.studies.hidden_effect")
    assert "| hidden effect ranked first | 100% of 2 |" in md
    assert "| fitted strength within 25 % | 50% |" in md and "| probe RMSE reduced >= 70 % (plain -> after) | 50% |" in md
    assert "| nothing hidden -> nothing significant | 100% of 1 scenarios |" in md
    assert "`fine` mesh" in md and "on\n`default`" not in md and "`default`; every" in md and "`coarse`" in md
    fa = study.failure_analysis(rows)
    assert "test_bar_contact" in fa and "spindle_motor" not in fa
    assert "signal 0.4 um vs floor 0.3 um" in fa   # sqrt(plain 0.5^2 - floor 0.3^2) = 0.4


@pytest.mark.parametrize("argv, needle", [
    (["--truth", "huge"], "unknown mesh resolution 'huge'"),
    (["--truth", "coarse", "--model", "default"], "coarser than --model"),
    (["--effects", "nonsense"], "unknown effects: nonsense"),
])
def test_bad_options_are_one_clear_error(capsys, argv, needle):
    with pytest.raises(SystemExit) as e:
        study.main(argv)
    assert e.value.code == 2
    assert needle in capsys.readouterr().err
