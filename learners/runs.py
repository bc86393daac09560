"""Learners on several runs: each run keeps its own time sequence.

A *run* is one table (one simulation or one measurement): rows in time order. Several runs are
never simply stacked for a time-ordered learner (grey models, AR, GNNMCI, the combination, whose
``time_ordered`` class attribute is True): the jump from one run's end to the next run's start is
not a step in time. So:

* a pooled learner (regressions, networks, ANFIS, LS-SVM) is fitted on all rows of all runs;
* a time-ordered learner is fitted on the runs as separate sequences by its
  ``fit_runs([(X, y), ...])`` method (every one of this package has it: ``gm11``, ``gm1n``,
  ``gmc1n``, ``gmc1n-pso`` and ``gnnmci`` accumulate and simulate each run from its own start and
  sum the runs' squared errors; ``ar-temp`` takes no lag pair across a run boundary;
  ``combination`` fits its members so and reads its weights on each run's own clock); a
  time-ordered learner without it (someone else's) accepts one run only
  (:class:`twin.errors.InputError` otherwise);
* predictions are always made run by run, each from its own start;
* a time-ordered learner's coefficients are per sample, so each of its runs must be equally
  spaced in time (:func:`check_equal_steps`: a run with a gap is two runs, to be given as two
  files) and its runs must share one sample interval: :func:`resample` thins a run to a coarser
  one (``twin learn --interval``). A pooled learner reads each row on its own: a run with a gap,
  or runs of different intervals, are rows all the same (a NetCDF table is refused with a gap of
  more than 3 median steps whatever the learner, as every command reads a twin result);
* a selector with ``fit_runs`` (the grey ones, ``gm0n-fcm`` and ``gra-fcm``, which read rows as
  time) picks its sensors on the runs as sequences, any other on all rows (:func:`select_runs`).

:func:`dataset_runs` lists the case files of one split of a ``twin dataset`` folder.
"""

from __future__ import annotations

import csv
from pathlib import Path, PurePosixPath

import numpy as np

from learners.table import MIN_ROWS, Table
from twin.errors import InputError
from twin.io.csv_rows import data_rows
from twin.io.paths import read_text, same_file

__all__ = ["is_time_ordered", "fit_runs", "select_runs", "resample", "check_equal_steps", "check_one_interval",
           "dataset_runs"]

# a run is equally spaced in time when every step is within this fraction of its median step
STEP_TOLERANCE = 1e-6


def is_time_ordered(estimator) -> bool:
    """Whether ``estimator`` reads its rows as one time sequence."""
    return bool(getattr(estimator, "time_ordered", False))


def fit_runs(estimator, runs: list, name: str = "learner"):
    """Fit ``estimator`` on ``runs`` = [(X, y), ...] (module doc); returns it."""
    _check_run_list(runs, name)
    if len(runs) == 1:
        return estimator.fit(*runs[0])
    if not is_time_ordered(estimator):
        return estimator.fit(np.vstack([X for X, _ in runs]), np.concatenate([y for _, y in runs]))
    if hasattr(estimator, "fit_runs"):
        return estimator.fit_runs(runs)
    raise InputError("command line", "--learner", f"{name} fits one run's time sequence and cannot be trained on "
                                                  f"{len(runs)} runs (it has no fit_runs method); give it one "
                                                  "training run")


def _check_run_list(runs, name: str) -> None:
    """``runs`` a non-empty list of (X, y) pairs whose tables have one width, else one
    :class:`InputError` naming ``runs``."""
    if not isinstance(runs, (list, tuple)) or not runs:
        raise InputError("data", "runs", f"{name} needs a list of one or more (X, y) runs, got {runs!r}")
    widths = set()
    for i, run in enumerate(runs):
        if not isinstance(run, (list, tuple)) or len(run) != 2:
            raise InputError("data", f"runs[{i}]", "expected an (X, y) pair")
        shape = np.shape(run[0])
        widths.add(shape[1] if len(shape) == 2 else None)
    if len(widths) > 1:
        raise InputError("data", "runs", f"the runs' tables differ in width ({', '.join(map(str, sorted(widths, key=str)))} "
                                         "columns): every run needs the same inputs")


def select_runs(selector, runs: list):
    """Fit the sensor ``selector`` on ``runs`` = [(X, y), ...] (module doc); returns it."""
    _check_run_list(runs, "selector")
    if len(runs) > 1 and hasattr(selector, "fit_runs"):
        return selector.fit_runs(runs)
    return selector.fit(np.vstack([X for X, _ in runs]), np.concatenate([y for _, y in runs]))


def resample(table: Table, interval: float | None, source: str, field: str = "--interval") -> Table:
    """Every k-th row of the run ``table`` (from its first), k = ``interval`` [s] / the run's sample
    interval; ``None`` keeps the run. A run that is not equally spaced in time, or whose interval
    does not divide ``interval``, is an :class:`InputError` on ``source``."""
    if interval is None or len(table.time) < 2:
        return table
    step = _median_step(table.time)
    if _uneven_step(table.time, step) is not None:
        raise InputError(source, field, "the run is not equally spaced in time; it cannot be thinned")
    k = interval / step
    if round(k) < 1 or abs(k - round(k)) > 1e-6 * k:
        raise InputError(source, field, f"{interval:g} s is not a whole multiple of the run's sample interval "
                                        f"{step:g} s")
    k = int(round(k))
    kept = len(table.time[::k])
    if kept < MIN_ROWS:
        raise InputError(source, field, f"thinned to {interval:g} s the run keeps {kept} row(s) of {len(table.time)}; "
                                        f"at least {MIN_ROWS} are needed: choose a shorter interval")
    return table._replace(time=table.time[::k], X=table.X[::k], y=table.y[::k])


def _median_step(time) -> float:
    """The median step [s] of ``time`` [s] (two or more instants)."""
    return float(np.median(np.diff(time)))


def _uneven_step(time, step: float) -> int | None:
    """The index of the first step of ``time`` [s] that differs from its median ``step`` [s] by
    more than :data:`STEP_TOLERANCE` of it (None: equally spaced)."""
    bad = np.flatnonzero(np.abs(np.diff(time) - step) > STEP_TOLERANCE * step)
    return int(bad[0]) if bad.size else None


def check_equal_steps(tables: list, sources: list, names: list[str], field: str = "time") -> None:
    """Refuse (:class:`InputError` naming the run's file and its time column ``field``) a run of
    ``tables`` that is not equally spaced in time, within :data:`STEP_TOLERANCE` of its median step
    as :func:`resample` asks, when a time-ordered learner (``names``) is to see it: it counts in
    samples, and would read a gap as one step. Pooled learners (``names`` empty) take such runs."""
    if not names:
        return
    for table, source in zip(tables, sources):
        t = table.time
        if len(t) < 2:
            continue
        step = _median_step(t)
        i = _uneven_step(t, step)
        if i is not None:
            raise InputError(str(source), field, f"the run is not equally spaced in time ({t[i]:g} s then {t[i + 1]:g} s, "
                                                 f"its median step is {step:g} s) and {', '.join(names)} count(s) in "
                                                 "samples: split the run at its gaps into files, one equally spaced run "
                                                 "each (--train/--test repeated; --interval thins only an equally "
                                                 "spaced run), or leave the time-ordered learners out")


def check_one_interval(tables: list, names: list[str]) -> None:
    """Refuse (:class:`InputError` on ``--interval``) runs sampled at different intervals when a
    time-ordered learner (``names``) is to see them: its coefficients are per sample."""
    steps = sorted({round(float(np.median(np.diff(t.time))), 9) for t in tables if len(t.time) > 1})
    if names and len(steps) > 1:
        raise InputError("command line", "--interval",
                         f"the runs are sampled every {', '.join(f'{s:g}' for s in steps)} s and {', '.join(names)} "
                         f"count(s) in samples; thin them to one interval, e.g. --interval '{steps[-1]:g} s'")


# how twin dataset writes a case's ``built`` flag in index.csv (pandas' spelling of a bool)
BUILT = {"True": True, "False": False}


def dataset_runs(folder: str | Path, split: str, field: str = "--dataset") -> list[Path]:
    """The built case files of ``split`` in the dataset ``folder`` (its ``index.csv``), in index
    order; an unknown split or a split without built cases is an :class:`InputError`, and so is
    an index row that twin dataset would not write (naming index.csv, the column and the line): a
    ``built`` other than ``True`` or ``False`` (which would drop the case without a word), a
    ``file`` outside the folder (absolute, or climbing out with ``..``), a row of another width."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputError(str(folder), field, "is a file, not a dataset folder (the folder twin dataset -o writes, "
                                             "with its index.csv and cases/)")
    index = folder / "index.csv"
    try:
        lines, table = data_rows(read_text(index, field, "dataset index (index.csv)"))
    except csv.Error as exc:
        raise InputError(str(index), "file", f"cannot read CSV: {exc}") from None
    header = [h.strip() for h in table[0]] if table else []
    for key in ("file", "split", "built"):
        if key not in header:
            raise InputError(str(index), key, "missing column: not the index.csv of a twin dataset")
    rows = []
    for line, row in zip(lines[1:], table[1:]):
        if len(row) != len(header):
            raise InputError(str(index), f"line {line}", f"{len(row)} fields, header has {len(header)}")
        r = dict(zip(header, row))
        if r["built"] not in BUILT:
            raise InputError(str(index), "built", f"line {line}: {r['built']!r} is neither True nor False (as twin "
                                                  "dataset writes it)")
        entry = PurePosixPath(r["file"])
        if not r["file"].strip() or entry.is_absolute() or ".." in entry.parts:
            raise InputError(str(index), "file", f"line {line}: {r['file']!r} is not a file inside the dataset folder "
                                                 "(a path relative to it, such as cases/<hash>.nc, as twin dataset "
                                                 "writes it)")
        rows.append(r)
    if not rows:
        raise InputError(str(index), "file", "lists no case: not the index.csv of a built twin dataset")
    splits = sorted({r["split"] for r in rows})
    if split not in splits:
        raise InputError(str(index), "split", f"no split {split!r}; the dataset has {', '.join(splits) or 'none'}")
    files = [folder / r["file"] for r in rows if r["split"] == split and BUILT[r["built"]]]
    if not files:
        raise InputError(str(index), "split", f"split {split!r} has no built case yet; build the dataset first "
                                              "(twin dataset SPEC -o DIR)")
    return files


def refuse_training_on_test(train_paths, test_sets, field: str = "--test") -> None:
    """A test run that is also a training run (the same file by any spelling: ``--train a.nc
    --test a.nc``, a dataset's test case given by hand with ``--train``, ``--split`` equal to
    ``--train-split``) would score a model on its own training data, which says nothing of its
    error on new runs: refused, naming the file (``field``: the option that named the test runs).
    ``test_sets``: [(label, [path, ...])]."""
    for label, paths in test_sets:
        for path in paths:
            for train in train_paths:
                if same_file(path, train):
                    raise InputError(str(path), field, f"is also a training run ({train}): scores on a model's own "
                                                          "training data say nothing of its error on new runs")
