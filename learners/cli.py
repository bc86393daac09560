"""``twin learn``: fit thermal-error learners on one table and score them on others.

Usage::

    twin learn --train A --test B [--test C ...] --target NAME --learner L1,L2,...
               [--select METHOD[:K]] [--inputs NAMES|all] [--time-column NAME] [-o scores.csv] [--seed N]

The training table is loaded (CSV or twin NetCDF, see :mod:`learners.table`), the selector picks
inputs on it (``--select correlation:4``; default ``all``), each learner is fitted on the selected
inputs and scored on every test table (which must carry the same input columns) with
:func:`learners.metrics.score_all`. One row per learner and test set is printed as an aligned text
table; ``-o`` writes the same rows as CSV (to a temporary file in the same folder, then renamed, so
no half-written file is left). ``--seed`` is given to every learner and selector that has a
``random_state``. Bad names and bad tables raise :class:`twin.errors.InputError`, as do
degenerate problems (:func:`learners.table.check_problem`: the target among the inputs, a
constant target or input, a selector asking for more inputs than there are), a learner or
selector that refuses the data with a ``ValueError`` (too few rows for it, too many grid rules,
...) and predictions that are not finite; the ``twin`` entry point turns it into
``error: <file>: <field>: <message>`` and exit status 2. ``--train`` takes one table (a second
``--train`` is refused rather than silently replacing the first); ``--test`` may be repeated,
each file once. Every file is checked before any learner is fitted; ``-o`` never replaces an
input (:class:`twin.io.paths.Files`).
"""

from __future__ import annotations

import contextlib
import csv
import time

import numpy as np

from learners.metrics import score_all
from learners.registry import LEARNERS, SELECTORS, make_learner, make_selector
from learners.table import check_problem, load_table
from twin.cli.options import add_seed_option
from twin.errors import InputError
from twin.io.atomic import atomic_write
from twin.io.paths import Files

__all__ = ["add_learn_parser", "run_learn", "COLUMNS"]

COLUMNS = ["learner", "test", "rmse", "nse", "r", "max_abs_residual", "improvement_pct", "mre_pct",
           "inputs", "fit_time_s"]
_HEADINGS = ["learner", "test file", "RMSE", "NSE", "R", "max|res|", "improv. %", "MRE %", "inputs", "fit s"]


def add_learn_parser(subparsers):
    """Add the ``learn`` sub-command to an argparse ``subparsers`` object; returns its parser."""
    p = subparsers.add_parser(
        "learn", help="fit thermal-error learners on one table and score them on others",
        description="Fit thermal-error learners on a training table and score them (RMSE, NSE, R, "
                    "max|res|, improvement %, MRE %) on one or more test tables.")
    p.add_argument("--train", required=True, metavar="FILE", help="training table (CSV or NetCDF), given once")
    p.add_argument("--test", required=True, action="append", metavar="FILE",
                   help="test table; repeat for several (each file once)")
    p.add_argument("--target", required=True, metavar="NAME",
                   help="target column (CSV) or address such as drift:Z (NetCDF)")
    p.add_argument("--learner", required=True, metavar="L1,L2",
                   help=f"comma-separated learners: {', '.join(sorted(LEARNERS))}")
    p.add_argument("--select", default="all", metavar="METHOD[:K]",
                   help=f"sensor selection: {', '.join(sorted(SELECTORS))} (default all)")
    p.add_argument("--inputs", default="all", metavar="NAMES|all",
                   help="comma-separated candidate inputs (default: all but time and target)")
    p.add_argument("--time-column", default="time", metavar="NAME", help="time column in s (default time)")
    p.add_argument("-o", "--output", metavar="FILE", help="also write the scores as CSV")
    add_seed_option(p, "random_state for learners and selectors")
    p.set_defaults(func=run_learn)
    return p


def _split_names(text, option):
    names = [s.strip() for s in str(text).split(",") if s.strip()]
    if not names:
        raise InputError("command line", option, "no names given")
    return names


def _seeded(estimator, seed):
    if "random_state" in estimator.get_params(deep=False):
        estimator.set_params(random_state=seed)
    return estimator


def _make_selector(spec, seed):
    """(selector, requested count or None) from ``METHOD[:K]``."""
    method, sep, count = str(spec).partition(":")
    method = method.strip()
    params = {}
    if sep:
        try:
            k = int(count)
        except ValueError:
            k = 0
        if k < 1:
            raise InputError("command line", "--select", f"count must be a positive integer, got {count!r}")
        params["n_select"] = k
    if method not in SELECTORS:
        raise InputError("command line", "--select",
                         f"unknown selector {method!r}; known: {', '.join(sorted(SELECTORS))}")
    if params and "n_select" not in SELECTORS[method]().get_params():
        raise InputError("command line", "--select", f"selector {method!r} takes no count")
    return _seeded(make_selector(method, **params), seed), params.get("n_select")


@contextlib.contextmanager
def _as_input_error(source, field):
    """A learner or selector refusing the user's data (ValueError) becomes an InputError."""
    try:
        yield
    except ValueError as exc:
        text = exc.message if isinstance(exc, InputError) else str(exc).strip()
        raise InputError(source, field, text.splitlines()[0] if text else type(exc).__name__) from None


def _fmt(value, digits=4):
    if isinstance(value, float):
        return "nan" if np.isnan(value) else f"{value:.{digits}g}"
    return str(value)


def _text_table(rows):
    cells = [_HEADINGS] + [[_fmt(r[c]) if c not in ("improvement_pct", "mre_pct", "fit_time_s")
                            else (f"{r[c]:.2f}" if np.isfinite(r[c]) else "nan") for c in COLUMNS]
                           for r in rows]
    widths = [max(len(row[i]) for row in cells) for i in range(len(COLUMNS))]
    numeric = {2, 3, 4, 5, 6, 7, 9}
    lines = []
    for row in cells:
        parts = [cell.rjust(w) if i in numeric else cell.ljust(w) for i, (cell, w) in enumerate(zip(row, widths))]
        lines.append("  ".join(parts).rstrip())
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def _write_csv(path, rows):
    def write(tmp):
        with open(tmp, "w", newline="", encoding="utf-8") as fh:
            writer = csv.writer(fh)
            writer.writerow(COLUMNS)
            for r in rows:
                writer.writerow([f"{r[c]:.10g}" if isinstance(r[c], float) else r[c] for c in COLUMNS])

    atomic_write(path, write, field="-o")


def _declare_files(args) -> Files:
    """Every file of the command checked before any work: tables readable, each test once, the
    scores not an input."""
    files = Files()
    files.input(args.train, "--train", "table")
    for path in args.test:
        if args.test.count(path) > 1:
            raise InputError(path, "--test", "given more than once")
        files.input(path, "--test", "table")
    if args.output:
        files.output(args.output, "-o", (".csv",))
    return files


def run_learn(args) -> int:
    """Run ``twin learn`` for a parsed namespace; prints the score table; returns 0."""
    from twin.cli.progress import progress_bar

    seed = args.seed
    _declare_files(args)
    learner_names = _split_names(args.learner, "--learner")
    learners = {name: _seeded(make_learner(name), seed) for name in learner_names}
    selector, n_select = _make_selector(args.select, seed)
    inputs = None if str(args.inputs).strip() in ("", "all") else _split_names(args.inputs, "--inputs")
    if inputs and args.target in inputs:
        raise InputError("command line", "--inputs", f"the target {args.target} is also an input")

    train = load_table(args.train, args.target, inputs=inputs, time_column=args.time_column, field="--train")
    check_problem(train, args.train, args.target, n_select=n_select)
    tests = [(path, load_table(path, args.target, inputs=train.input_names, time_column=args.time_column,
                               field="--test")) for path in args.test]
    for path, tab in tests:
        check_problem(tab, path, args.target, training=False)
    with _as_input_error(args.train, args.select):
        selector.fit(train.X, train.y)
    cols = list(selector.selected_)
    used = [train.input_names[i] for i in cols]

    rows = []
    progress = progress_bar("learn", "fit")
    for done, (name, est) in enumerate(learners.items(), start=1):
        start = time.perf_counter()
        with _as_input_error(args.train, name):
            est.fit(train.X[:, cols], train.y)
        fit_s = time.perf_counter() - start
        for path, tab in tests:
            with _as_input_error(path, name):
                pred = est.predict(tab.X[:, cols])
            if not np.all(np.isfinite(pred)):
                raise InputError(str(path), name, "the learner's predictions are not finite (it diverged on "
                                                  "these data); no scores are written")
            scores = score_all(tab.y, pred)
            rows.append({"learner": name, "test": str(path), **{k: float(v) for k, v in scores.items()},
                         "inputs": ";".join(used), "fit_time_s": float(fit_s)})
        progress(done, len(learners))
    print(_text_table(rows))
    if args.output:
        _write_csv(args.output, rows)
    return 0
