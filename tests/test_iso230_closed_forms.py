"""ISO 230-3 evaluation statistics against hand-computed small examples (validate.iso230): the
segment statistics of the module docstring (min, max, mean, population std, mean -/+ 2 std, the
95th percentile of |value| with np.percentile's linear interpolation), the half-open windows
[start, end) with the last one closed at the last sample, and the default segment lengths."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.fuzz_files import result_dataset
from validate.iso230 import evaluate

TOL = 1e-12


def _record(x: np.ndarray, speed: np.ndarray | None = None, step: float = 60.0):
    """A result-schema record of len(x) samples every ``step`` s whose five-probe drift X is ``x``
    [um] (Y, Z, A, B as the fuzz record has them); ``speed`` [rpm] the spindle's, else stopped."""
    ds = result_dataset(len(x))
    ds = ds.assign_coords(time=("time", np.arange(len(x)) * step, {"units": "s"}))
    drift = ds.probe_drift.values.copy()
    drift[:, 0] = x
    ds["probe_drift"] = (("time", "axis"), drift, {"units": "um"})
    ds["spindle_speed"] = ("time", np.zeros(len(x)) if speed is None else np.asarray(speed, float), {"units": "rpm"})
    return ds


def test_one_segments_statistics_are_the_hand_computed_numbers():
    """X = [3, -1, 4, 1, -5, 9, 2] in one segment (the default 24 h is longer than the test):
    min -5 (not the first sample), max 9 (not the last), mean 13/7 (the median is 2), population
    std sqrt(sum x^2 / n - mean^2) = sqrt(137/7 - 169/49) = sqrt(790)/7 (the sample std, ddof 1,
    would be sqrt(790/42)), low/high = mean -/+ 2 std, and the 95th percentile of |X| =
    [1, 1, 2, 3, 4, 5, 9] sorted, linear at rank 0.95 x 6 = 5.7: 5 + 0.7 (9 - 5) = 7.8 (the
    nearest rank would give 9; the signed values [-5, -1, 1, 2, 3, 4, 9] would give
    4 + 0.7 x 5 = 7.5)."""
    x = np.array([3.0, -1.0, 4.0, 1.0, -5.0, 9.0, 2.0])
    ev = evaluate(_record(x), "etve")
    assert ev.segments == [(0.0, 360.0)]
    (s,) = ev.segment_stats()["X"]
    mean, std = 13.0 / 7.0, math.sqrt(790.0) / 7.0
    assert s["min"] == -5.0 and s["max"] == 9.0
    assert abs(s["mean"] - mean) < TOL
    assert abs(s["std"] - std) < TOL
    assert abs(s["low"] - (mean - 2 * std)) < TOL and abs(s["high"] - (mean + 2 * std)) < TOL
    assert abs(s["p95_abs"] - 7.8) < TOL
    assert ev.channels[0].range == 14.0


def test_windows_are_half_open_and_the_last_one_holds_the_last_sample():
    """Seven samples every 60 s, segment 180 s: windows [0, 180) and [180, 360] (the last closed
    at the last sample). X = [0, 1, 2, 10, 4, 5, -7]: the first window holds samples 0-2 (max 2:
    the 10 at t = 180 s belongs to the second), the second samples 3-6 (min -7: the last sample,
    which a window open at its end would drop). The spindle at 6000 rpm for the first three
    samples gives the speed steps [0, 180) and [180, 360]: ranges 2 - 0 = 2 and 10 - (-7) = 17."""
    x = np.array([0.0, 1.0, 2.0, 10.0, 4.0, 5.0, -7.0])
    speed = np.array([6000.0] * 3 + [0.0] * 4)
    ev = evaluate(_record(x, speed), "etve", segment=180.0)
    assert ev.segments == [(0.0, 180.0), (180.0, 360.0)]
    first, second = ev.segment_stats()["X"]
    assert (first["min"], first["max"]) == (0.0, 2.0) and abs(first["mean"] - 1.0) < TOL
    assert (second["min"], second["max"]) == (-7.0, 10.0) and abs(second["mean"] - 3.0) < TOL
    spindle = evaluate(_record(x, speed), "spindle", segment=180.0)
    assert [(a, b, n) for a, b, n in spindle.steps] == [(0.0, 180.0, 6000.0), (180.0, 360.0, 0.0)]
    assert [r["X"] for r in spindle.step_ranges()] == [2.0, 17.0]


def test_default_segments_are_24_h_for_etve_and_1_h_otherwise():
    """Module docstring of evaluate: the statistics' segment is 24 h for an ETVE test and 1 h for
    the others. Two days sampled hourly give the ETVE two 24 h segments; three hours every
    10 min with the spindle turning give the spindle test three 1 h segments."""
    two_days = _record(np.sin(np.arange(49.0)), step=3600.0)
    assert evaluate(two_days, "etve").segments == [(0.0, 86400.0), (86400.0, 172800.0)]
    three_hours = _record(np.cos(np.arange(19.0)), np.full(19, 3000.0), step=600.0)
    assert evaluate(three_hours, "spindle").segments == [(0.0, 3600.0), (3600.0, 7200.0), (7200.0, 10800.0)]


def test_a_segment_of_two_sampling_intervals_is_accepted():
    """evaluate: a segment needs at least two sampling intervals (60 s here): 120 s is accepted,
    and one interval is refused on --segment."""
    from twin.errors import InputError
    ds = _record(np.arange(7.0))
    assert len(evaluate(ds, "etve", segment=120.0).segments) == 3
    with pytest.raises(InputError) as err:
        evaluate(ds, "etve", segment=60.0)
    assert err.value.field == "--segment"


def test_a_record_one_segment_long_has_one_segment_whatever_its_start_time():
    """A 30 min record in 30 min segments is one segment, whatever its clock: from 31304.8 s the
    quotient (t1 - t0) / length rounds a hair above 1, and np.arange's edges gave a second, empty
    segment (t1, t1) holding the last sample alone (its max left out of the first)."""
    ds = result_dataset(31)                       # 30 min at 1 min
    ds = ds.assign_coords(time=("time", 31304.8 + 60.0 * np.arange(31), {"units": "s"}))
    ds["spindle_speed"] = ("time", np.full(31, 3000.0), {"units": "rpm"})
    ev = evaluate(ds, "spindle", segment=1800.0)
    assert ev.segments == [(31304.8, 33104.8)]
    (s,) = ev.segment_stats()["X"]
    assert s["max"] == ds.probe_drift.sel(axis="X").values.max()
