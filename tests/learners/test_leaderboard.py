"""The leaderboard (learners.leaderboard) and thinning runs (learners.runs.resample).

Known answers: a learner that predicts 0 has residual -y, so RMSE = RMS(y), max |r| = max |y| and
p95 |r| = the 95th percentile of |y|, on exactly the rows of each time segment of every run.
"""

import numpy as np
import pytest
from sklearn.base import BaseEstimator, RegressorMixin

from learners.leaderboard import leaderboard, markdown
from learners.runs import resample
from learners.table import Table
from twin.errors import InputError


class Zero(RegressorMixin, BaseEstimator):
    time_ordered = True

    def fit_runs(self, runs):
        self.n_runs_ = len(runs)
        return self

    def fit(self, X, y):
        return self.fit_runs([(X, y)])

    def predict(self, X):
        return np.zeros(len(X))


def test_leaderboard_scores_whole_runs_and_segments_on_the_right_rows():
    """Zero predictions: RMSE = RMS(y) and max/p95 of |y| over the test runs' rows; segment k of
    2 holds rows [0, n/2) or [n/2, n) of each run, pooled."""
    rng = np.random.default_rng(0)
    runs = [(rng.normal(size=(m, 2)), rng.normal(size=m)) for m in (10, 21)]
    rows = leaderboard({"zero": Zero()}, runs, [("two runs", runs)], segments=2, inputs="a;b")
    assert [r["test"] for r in rows] == ["two runs", "two runs [segment 1/2]", "two runs [segment 2/2]"]
    for row, pick in zip(rows, ([slice(None)] * 2, [slice(0, 5), slice(0, 10)], [slice(5, 10), slice(10, 21)])):
        y = np.concatenate([r[1][s] for r, s in zip(runs, pick)])
        assert row["rmse"] == pytest.approx(np.sqrt(np.mean(y ** 2)), rel=1e-12)
        assert row["max_abs_residual"] == pytest.approx(np.max(np.abs(y)), rel=1e-12)
        assert row["p95_abs_residual"] == pytest.approx(np.percentile(np.abs(y), 95), rel=1e-12)
        assert row["inputs"] == "a;b" and row["unit"] == "" and "fit_time_s" not in row


def test_leaderboard_fits_time_ordered_learners_on_runs_and_refuses_divergence():
    runs = [(np.ones((6, 1)), np.arange(6.0)), (np.ones((6, 1)), np.arange(6.0))]
    est = Zero()
    leaderboard({"zero": est}, runs, [("t", runs[:1])])
    assert est.n_runs_ == 2

    class Inf(Zero):
        def predict(self, X):
            return np.full(len(X), np.inf)

    with pytest.raises(InputError, match="not finite") as err:
        leaderboard({"inf": Inf()}, runs, [("t", runs[:1])])
    assert (err.value.source, err.value.field) == ("t", "inf")     # the test set and the learner, not "data"


def test_markdown_has_one_table_per_test_set_sorted_by_rmse_and_escapes_bars():
    rows = [{"learner": n, "test": "set", "rmse": e, "nse": 0.5, "r": 0.9, "max_abs_residual": 2.0,
             "p95_abs_residual": 1.0, "improvement_pct": 10.0, "mre_pct": 5.0, "unit": "urad", "inputs": "x"}
            for n, e in (("b", 2.0), ("a", 1.0))]
    text = markdown(rows, title="T")
    lines = text.splitlines()
    assert lines[0] == "# T" and "## set" in lines
    body = [ln for ln in lines if ln.startswith("| a") or ln.startswith("| b")]
    assert [ln.split()[1] for ln in body] == ["a", "b"]
    assert all(ln.count("|") - ln.count("\\|") == 9 for ln in lines if ln.startswith("|"))   # 8 columns
    assert "RMSE urad" in text and "max\\|res\\| urad" in text     # the rows' unit in the headings
    assert "RMSE (target's unit)" in markdown([{**r, "unit": ""} for r in rows])
    with pytest.raises(ValueError, match="different units"):
        markdown([rows[0], {**rows[1], "unit": "um"}])


def test_resample_thins_to_a_whole_multiple_and_refuses_others():
    t = np.arange(13) * 10.0
    tab = Table(t, np.arange(26.0).reshape(13, 2), np.arange(13.0), ["a", "b"])
    thin = resample(tab, 60.0, "run.nc")
    np.testing.assert_array_equal(thin.time, [0.0, 60.0, 120.0])
    np.testing.assert_array_equal(thin.y, [0.0, 6.0, 12.0])
    assert resample(tab, None, "run.nc") is tab
    with pytest.raises(InputError, match="whole multiple"):
        resample(tab, 25.0, "run.nc")
    with pytest.raises(InputError, match="equally spaced"):
        resample(tab._replace(time=t ** 1.5), 60.0, "run.nc")


def test_leaderboard_rows_carry_the_unit_and_no_wall_time_so_repeats_write_the_same_bytes(tmp_path):
    """The same learners on the same runs give the same CSV bytes twice: the rows hold the target's
    unit and the scores, and each fit's wall-clock time goes only to ``timings``."""
    from learners.leaderboard import write_csv

    rng = np.random.default_rng(1)
    runs = [(rng.normal(size=(12, 2)), rng.normal(size=12))]
    files = []
    for k in range(2):
        timings = {}
        rows = leaderboard({"zero": Zero()}, runs, [("t", runs)], unit="um", timings=timings)
        assert rows[0]["unit"] == "um" and set(timings) == {"zero"} and timings["zero"] >= 0
        files.append(write_csv(tmp_path / f"b{k}.csv", rows))
    assert (tmp_path / "b0.csv").read_bytes() == (tmp_path / "b1.csv").read_bytes()
    assert "unit" in (tmp_path / "b0.csv").read_text().splitlines()[0].split(",")


def test_resample_refuses_an_interval_just_off_a_whole_multiple():
    """60 s samples thinned to 61 s: k = 61/60 = 1.0167, |k - round(k)| = 0.0167 > 1e-6 k, so not a
    whole multiple and refused (a loose 0.1 k tolerance would let it pass as k = 1)."""
    t = np.arange(30) * 60.0
    tab = Table(t, np.arange(60.0).reshape(30, 2), np.arange(30.0), ["a", "b"])
    with pytest.raises(InputError, match="whole multiple"):
        resample(tab, 61.0, "run.nc")
