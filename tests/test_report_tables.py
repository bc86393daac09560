"""Report tables whose numbers were printed but never read back (mutation audit, item 10): the
ISO 230-3 "Maximum range over the test" table, the conditions' room-air range and apply's
before/after "change" column, each against a hand-computed cell."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from tests.test_iso230 import _piecewise_air, synthetic
from validate.iso230 import evaluate


def test_maximum_range_table_reads_range_min_max_unit_per_channel():
    """synthetic()'s ETVE: X steps 0 -> 1 um at 1 h (min 0, max 1), Y = 6 sin^2(pi t / 4 h) (0 at
    both ends, 6 exactly at t = 2 h where the argument is pi / 2), Z = -12 ramp + 4 (t > 3 h) (0 at
    t = 0, -12 from 2 h to 3 h, -8 after: min -12, max 0), A = 3 ramp (0 .. 3 urad), B = -5 ramp
    (-5 .. -0, written 0.000); the air 20 + 2.5 ramp. Each row reads name, max - min, min, max,
    unit in that order (a table with min and max swapped wrote "| Z | 12.000 | 0.000 | -12.000 |")."""
    from validate.iso230_report import sections

    lines = dict(sections(evaluate(synthetic(), "etve")))["Maximum range over the test"]
    assert lines == ["| channel | maximum range | min | max | unit |",
                     "|---|---|---|---|---|",
                     "| X | 1.000 | 0.000 | 1.000 | um |",
                     "| Y | 6.000 | 0.000 | 6.000 | um |",
                     "| Z | 12.000 | -12.000 | 0.000 | um |",
                     "| A | 3.000 | 0.000 | 3.000 | urad |",
                     "| B | 5.000 | -5.000 | 0.000 | urad |",
                     "",
                     "Room air range over the test: 2.500 K (20.00 to 22.50 degC)."]


def test_conditions_room_air_range_is_max_minus_min_not_last_minus_first():
    """The conditions' "room air" row states min, max and max - min of the whole record's air.
    A piecewise-linear room through 20, 22.5, 20, 19, 20.5 degC at 0, 1, 2, 3, 4 h (knots on the
    1-min samples, so the extremes are sampled exactly): min 19.00, max 22.50, range 3.50 K,
    where last - first would read 0.50 K."""
    ds = synthetic()
    t = ds.time.values
    air = np.interp(t, [0.0, 3600.0, 7200.0, 10800.0, 14400.0], [20.0, 22.5, 20.0, 19.0, 20.5])
    assert air[0] == 20.0 and air[-1] == 20.5 and air.min() == 19.0 and air.max() == 22.5
    ds["ambient_temperature"] = ("time", air, {"units": "degC"})
    row = dict(evaluate(ds, "etve").conditions)["room air"]
    assert row.split(", mean ")[0] == "19.00 to 22.50 degC (range 3.50 K"
    assert f"(range {np.ptp(air):.2f} K" in row


def _diagnosis(residual: np.ndarray):
    """A Diagnosis on stand-in evidence (the style of tests/test_diagnosis_closed_forms.py): one
    record with the channels temperature:T0 [K], probe:X1 and probe:Y1 [um]; the baseline
    residual ``residual`` (n_t, 3) and no material nuisance; measured 10 everywhere."""
    from validate.diagnose import Diagnosis
    from validate.evidence import Evidence
    from validate.fit import BoundedFitter

    measured = np.full(residual.shape, 10.0)
    rec = SimpleNamespace(label="m", measured=measured, groups=["temperature", "probe", "probe"],
                          channels=["temperature:T0", "probe:X1", "probe:Y1"], phases=[],
                          times=np.arange(residual.shape[0]) * 60.0, noise={}, model_error=None)
    ev = Evidence([rec])
    r = residual.ravel()
    return Diagnosis(ev, None, np.zeros_like(r), np.ones_like(r), BoundedFitter(r, np.ones_like(r)), [])


def test_apply_change_column_is_after_over_before_minus_one():
    """format_before_after's "change" is after / before - 1 of each channel's RMSE. Constant
    residuals over 4 samples (RMS = the constant): T0 2 K before, 0.5 K after -> 0.5 / 2 - 1 =
    -75 % (before / after - 1 would print +300 %); X1 1 um before, 3 um after -> +200 %; Y1 0
    before (no change to divide by) -> +0 %. With the calibrated rerun (no nuisance: before+a is
    the baseline) leaving 1 K and 0.5 um: T0 -50 %, X1 -50 %."""
    from validate.apply import format_before_after

    n = 4
    before = np.tile([2.0, 1.0, 0.0], (n, 1))
    d = _diagnosis(before)
    np.testing.assert_array_equal(d.baseline_rmse, [2.0, 1.0, 0.0])
    meas = d.evidence.measured
    after = meas - np.tile([0.5, 3.0, 0.25], (n, 1)).ravel()
    lines = format_before_after(d, after).splitlines()
    assert lines[0].split() == ["channel", "unit", "before", "after", "change"]
    assert [ln.split() for ln in lines[1:]] == [["temperature:T0", "K", "2", "0.5", "-75%"],
                                                ["probe:X1", "um", "1", "3", "+200%"],
                                                ["probe:Y1", "um", "0", "0.25", "+0%"]]
    calibrated = meas - np.tile([1.0, 0.5, 0.0], (n, 1)).ravel()
    rows = [ln.split() for ln in format_before_after(d, after, calibrated).splitlines()[1:4]]
    assert [r[4:] for r in rows] == [["-75%", "2", "1", "-50%"], ["+200%", "1", "0.5", "-50%"],
                                     ["+0%", "0", "0", "+0%"]]


def test_report_room_air_range_line_is_max_minus_min():
    """The report's "Room air range over the test" line is max - min of the room (20, 22.5, 20, 19,
    20.5 degC: 3.5 K), not max - first (2.5 K)."""
    from validate.iso230_report import sections

    lines = dict(sections(evaluate(_piecewise_air(synthetic(speed=False)), "etve")))["Maximum range over the test"]
    assert lines[-1] == "Room air range over the test: 3.500 K (19.00 to 22.50 degC)."
