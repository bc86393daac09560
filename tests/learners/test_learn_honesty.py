"""What `twin learn` and the learners refuse or report so that a score means what it says: no
scores of a model on its own training runs, a coefficient pinned at its search bound reported
beside the scores, no values that no unit of a measurement reaches, and one clear error for data a
learner cannot take (text, a model not fitted yet)."""

from __future__ import annotations

import os

import numpy as np
import pytest

from learners import make_learner
from learners.cli import run_learn
from tests.learners.test_table_cli import _args, _write_csv
from twin.errors import InputError


def _static(path, rows: int = 100):
    """A static relation err = 3 (T1 - 20): nothing for a grey model's dynamics to fit."""
    t = np.arange(rows) * 10.0
    T1, T2 = 20.0 + np.linspace(0.0, 5.0, rows), 20.0 + 2.0 * (1.0 - np.exp(-t / 300.0))
    lines = ["time,T1,T2,err"] + [f"{a:g},{b:.6f},{c:.6f},{3 * (b - 20):.6f}" for a, b, c in zip(t, T1, T2)]
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_a_training_run_is_never_also_a_test_run(tmp_path):
    """--train a.csv --test a.csv, by another spelling or a hard link: refused before any fit,
    naming the test file (scores on a model's own training data say nothing of new runs)."""
    a = _write_csv(tmp_path / "a.csv")
    os.link(a, tmp_path / "hard.csv")
    for test in (a, str(tmp_path / "." / "a.csv"), str(tmp_path / "hard.csv")):
        with pytest.raises(InputError, match="is also a training run") as err:
            run_learn(_args("--train", a, "--test", test, "--target", "drift_z", "--learner", "mlr"))
        assert err.value.field == "--test" and err.value.source == test


def test_a_coefficient_at_its_search_bound_is_reported_beside_the_scores(tmp_path, capsys):
    """gm1n on a static relation: its development coefficient ends at the search range's lower
    end (at_bound_); the terminal, the CSV's note column and the Markdown page say so, and a
    learner fitted inside its range has no note."""
    train, test = _static(tmp_path / "train.csv"), _static(tmp_path / "test.csv", rows=60)
    md, csv = tmp_path / "s.md", tmp_path / "s.csv"
    assert run_learn(_args("--train", train, "--test", test, "--target", "err", "--learner", "gm1n,mlr",
                           "-o", str(md), "-o", str(csv))) == 0
    out = capsys.readouterr().out
    assert "note: gm1n: its development coefficient sits at the search range's lower end" in out
    assert "note: mlr" not in out
    header, *rows = csv.read_text().splitlines()
    assert header.split(",")[-1] == "note"
    assert "pinned at the bound" in rows[0] and rows[1].endswith(",")
    assert "Note: gm1n: its development coefficient sits" in md.read_text()


def test_values_no_unit_of_a_measurement_reaches_are_refused(tmp_path):
    """A CSV cell of 1e300 (its squares overflow: an infinite RMSE, R 0) is refused at load,
    naming file, column and line; from Python every learner refuses X or y beyond 1e12."""
    rows = _write_csv(tmp_path / "ok.csv")
    text = open(rows).read().splitlines()
    text[5] = ",".join(text[5].split(",")[:-1] + ["1e300"])
    bad = tmp_path / "huge.csv"
    bad.write_text("\n".join(text) + "\n")
    with pytest.raises(InputError, match="line 6: 1e300 is beyond") as err:
        run_learn(_args("--train", str(bad), "--test", rows, "--target", "drift_z", "--learner", "mlr"))
    assert (err.value.source, err.value.field) == (str(bad), "drift_z")
    X, y = np.random.default_rng(0).random((40, 3)), np.linspace(0.0, 1.0, 40)
    for name in ("mlr", "anfis-grid", "gm1n", "lssvm"):
        with pytest.raises(InputError, match="beyond"):
            make_learner(name).fit(X, y * 1e300)
        with pytest.raises(InputError, match="beyond"):
            make_learner(name).fit(X * 1e200, y)


@pytest.mark.parametrize("name", ["mlr", "pcr", "gm1n", "anfis-fcm"])
def test_text_data_and_an_unfitted_learner_are_one_clear_error(name):
    """A target of text and a prediction before fit are InputErrors naming the argument, not
    numpy's or scikit-learn's own exceptions."""
    X = np.random.default_rng(1).random((40, 2))
    with pytest.raises(InputError) as err:
        make_learner(name).fit(X, np.array(["a"] * 40))
    assert err.value.field == "y"
    with pytest.raises(InputError, match="not fitted|fit"):
        make_learner(name).predict(X)


def test_names_and_numbers_are_read_as_written(tmp_path):
    """--time-column names a coordinate the NetCDF file must have (never another one silently);
    a number written with '_' (Python's int and float read 6_0 as 60) is no number in a CSV cell,
    a --select count or a --seed."""
    from tests.learners.test_table_cli import _write_netcdf
    from twin.cli import main

    train, test = _write_netcdf(tmp_path / "a.nc"), _write_netcdf(tmp_path / "b.nc", seed=1)
    with pytest.raises(InputError, match="missing time coordinate") as err:
        run_learn(_args("--train", train, "--test", test, "--target", "drift:Z", "--learner", "mlr",
                        "--time-column", "bogus"))
    assert err.value.field == "bogus"
    good = _write_csv(tmp_path / "good.csv")
    lines = open(good).read().splitlines()
    lines[3] = ",".join(lines[3].split(",")[:-1] + ["6_0"])
    bad = tmp_path / "underscore.csv"
    bad.write_text("\n".join(lines) + "\n")
    other = _write_csv(tmp_path / "other.csv", seed=1)
    with pytest.raises(InputError, match="non-numeric value '6_0'"):
        run_learn(_args("--train", str(bad), "--test", other, "--target", "drift_z", "--learner", "mlr"))
    with pytest.raises(InputError, match="count must be a positive integer, got '1_0'"):
        run_learn(_args("--train", good, "--test", other, "--target", "drift_z", "--learner", "mlr",
                        "--select", "correlation:1_0"))
    assert main(["learn", "--train", good, "--test", other, "--target", "drift_z", "--learner", "mlr",
                 "--seed", "1_0"]) == 2


@pytest.mark.parametrize("name", ["anfis-fcm", "ann", "pso-bpnn", "gnnmci", "gmc1n-pso", "anfis-grid"])
def test_a_seed_is_a_whole_number_from_0_to_2_32(name):
    """random_state None or a whole number 0 to 2^32 - 1: -1, 0.5, NaN, a text and True are one
    InputError naming random_state (they were numpy's, scikit-learn's or silently ignored)."""
    rng = np.random.default_rng(0)
    X = rng.random((60, 3))
    y = X @ np.array([1.0, 2.0, 3.0])
    for bad in (-1, 0.5, float("nan"), "x", True):
        with pytest.raises(InputError) as err:
            make_learner(name, random_state=bad).fit(X, y)
        assert err.value.field == "random_state", (bad, str(err.value))


def test_python_calls_the_audit_found_raw_are_one_input_error():
    """Each was numpy's, scipy's or LAPACK's own exception, or a silent misreading: a grey model's
    1-D X (one row of p inputs, or p rows of one?), GM(1,1) predicting from a table of another
    width, a selector that ranks against y fitted without it or on a constant sensor, no runs or
    runs of different widths, fuzzy c-means' arguments, scores of text."""
    from learners import make_selector
    from learners.fcm import fuzzy_cmeans
    from learners.metrics import score_all
    from learners.runs import fit_runs

    rng = np.random.default_rng(2)
    X = rng.random((40, 4))
    y = X @ np.array([1.0, 2.0, 3.0, 4.0])
    flat = X.copy()
    flat[:, 2] = 5.0
    calls = [(lambda: make_learner("gm1n").fit(X[:, 0], y), "X"),
             (lambda: make_learner("gm11").fit(X, y).predict(X[:, :1]), "X"),
             (lambda: make_selector("fuzzy-r2").fit(X, None), "y"),
             (lambda: make_selector("gm0n-fcm").fit(X, None), "y"),
             (lambda: make_selector("hier-corr").fit(flat, y), "X"),
             (lambda: make_selector("gm0n-fcm").fit(flat, y), "X"),
             (lambda: fit_runs(make_learner("mlr"), []), "runs"),
             (lambda: fit_runs(make_learner("mlr"), [(X, y), (X[:, :2], y)]), "runs"),
             (lambda: fuzzy_cmeans(X, 2.5), "n_clusters"),
             (lambda: fuzzy_cmeans(X, 2, m=1.0), "m"),
             (lambda: fuzzy_cmeans(X, 2, tol=-1.0), "tol"),
             (lambda: score_all(["a", "b"], [1.0, 2.0]), "y_true, y_pred")]
    for call, field in calls:
        with pytest.raises(InputError) as err:
            call()
        assert err.value.field == field, str(err.value)


@pytest.mark.parametrize("name, setting", [("anfis-fcm", {"epochs": 10 ** 9}), ("pso-bpnn", {"n_particles": 10 ** 9}),
                                           ("gnnmci", {"n_iterations": 10 ** 9}), ("ann", {"max_iter": 10 ** 9})])
def test_training_work_has_an_upper_bound(name, setting):
    """100 to 1000 times the seeds' settings at most (hours on a laptop): a typo of 1e9 epochs,
    particles or iterations is refused before the fit, not run for days or asked of the memory."""
    X = np.random.default_rng(0).random((40, 3))
    with pytest.raises(InputError, match="must be an integer from") as err:
        make_learner(name, **setting).fit(X, X @ np.array([1.0, 2.0, 3.0]))
    assert err.value.field == next(iter(setting))


def test_a_learners_own_limits_are_notes_beside_its_scores():
    """GNNMCI's weights and GMC(1,N)-PSO's coefficients left on the PSO's search box (a bound of
    0.01: far too tight for this relation) and an LS-SVM trained on an evenly spaced max_samples of its rows say so in the
    leaderboard's note; a fit inside its box and on all its rows has none."""
    from learners.leaderboard import fit_note

    X = np.random.default_rng(0).random((80, 2)).cumsum(axis=0)
    y = X @ np.array([1.0, 2.0])
    tight = make_learner("gnnmci", weight_bound=0.01, random_state=0).fit(X, y)
    assert fit_note(tight).startswith("its network weights sit at the search box's bound (")
    tight = make_learner("gmc1n-pso", coef_bound=0.01, random_state=0).fit(X, y)
    assert fit_note(tight).startswith("its coefficients sit at the search box's bound (")
    assert fit_note(make_learner("gmc1n-pso", random_state=0).fit(X, y)) == ""
    assert fit_note(make_learner("lssvm", max_samples=20).fit(X, y)).startswith(
        "trained on 20 evenly spaced of its 80 training rows")
    assert fit_note(make_learner("lssvm").fit(X, y)) == "" and fit_note(make_learner("mlr").fit(X, y)) == ""


def test_an_empty_name_in_a_list_option_is_refused(tmp_path):
    good, other = _write_csv(tmp_path / "a.csv"), _write_csv(tmp_path / "b.csv", seed=1)
    for option, value in (("--learner", "mlr,"), ("--learner", "mlr,,gm1n"), ("--inputs", "T1,")):
        argv = ["--learner", "mlr"] if option == "--inputs" else []
        with pytest.raises(InputError, match="an empty name") as err:
            run_learn(_args("--train", good, "--test", other, "--target", "drift_z", *argv, option, value))
        assert err.value.field == option


def test_gm11s_row_says_it_reads_none_of_the_inputs():
    """GM(1,1) extrapolates the target's own series: the leaderboard row lists the command's
    inputs like every row, and its note says it uses none of them."""
    from learners.leaderboard import fit_note

    X = np.random.default_rng(0).random((80, 2)).cumsum(axis=0)
    note = fit_note(make_learner("gm11").fit(X, X @ np.array([1.0, 2.0])))
    assert note.startswith("uses none of the inputs listed")


def test_too_many_segments_is_an_error_of_the_command_line(tmp_path):
    good, other = _write_csv(tmp_path / "a.csv"), _write_csv(tmp_path / "b.csv", n=8, seed=1)
    with pytest.raises(InputError, match="a scored segment needs at least 3") as err:
        run_learn(_args("--train", good, "--test", other, "--target", "drift_z", "--learner", "mlr",
                        "--segments", "4"))
    assert (err.value.source, err.value.field) == ("command line", "--segments")
