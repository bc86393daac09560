"""``twin learn``: fit thermal-error learners on one or more runs and score them on others.

Usage::

    twin learn --train A [--train A2 ...] --test B [--test C ...] --target NAME --learner L1,L2,...
               [--select METHOD[:K]] [--inputs NAMES|all] [--time-column NAME] [-o scores.csv] [--seed N]
    twin learn --dataset DIR --split NAME [--train-split NAME] --target NAME --learner L1,L2,... [--segments N]
               [--interval TIME] [-o board.csv] [-o board.md]

Every training table is one run (CSV or twin NetCDF, see :mod:`learners.table`); runs stay
separate groups (:mod:`learners.runs`): pooled learners see all rows, time-ordered learners each
run's own sequence. The selector picks inputs on the training runs (``--select correlation:4``;
default ``all``; the grey selectors on each run's sequence), each learner is fitted on the
selected inputs and scored on every test table (which must carry the same input columns), each predicted from its own start, with
:func:`learners.metrics.score_all` and the 95th percentile of |residual|. ``--dataset DIR`` adds
the built cases of a ``twin dataset`` folder: those of ``--train-split`` (default ``train``) as
training runs, those of ``--split`` (default ``test``) as one test set, scored on the residuals
of all its runs together. ``--segments N`` adds a row per time segment (each run cut into N equal
parts; segment k pooled over the runs). ``--interval 60s`` thins every run to that sample interval
(:func:`learners.runs.resample`): time-ordered learners count in samples, so runs sampled at 10 s
and 60 s would otherwise mean different things to them (runs of different intervals are refused
for them without it, and so is a run that is not equally spaced in time,
:func:`learners.runs.check_equal_steps`: split it at its gaps into files; pooled learners take
both). The scoring is
:func:`learners.leaderboard.leaderboard`.

One row per learner and test set (and segment) is printed as an aligned text table; ``-o x.csv``
writes the same rows as CSV, ``-o x.md`` as Markdown (each to a temporary file in the same folder,
then renamed, so no half-written file is left). ``--seed`` is given to every learner and selector that has a
``random_state``. Bad names and bad tables raise :class:`twin.errors.InputError`, as do
degenerate problems (:func:`learners.table.check_problem`: the target among the inputs, a
constant target or input, a selector asking for more inputs than there are), a learner or
selector that refuses the data with a ``ValueError`` (too few rows for it, too many grid rules,
...) and predictions that are not finite; the ``twin`` entry point turns it into
``error: <file>: <field>: <message>`` and exit status 2. ``--train`` and ``--test`` may be
repeated, each file once. Every file is checked before any learner is fitted; ``-o`` never
replaces an input (:class:`twin.io.paths.Files`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from learners.leaderboard import COLUMNS, as_input_error, check_segments, leaderboard, notes, write_csv, write_markdown
from learners.registry import LEARNERS, SELECTORS, make_learner, make_selector
from learners.runs import (check_equal_steps, check_one_interval, dataset_runs, is_time_ordered,
                           refuse_training_on_test, resample, select_runs)
from learners.table import Table, check_problem, load_table, target_unit
from twin.cli.options import add_seed_option, positive_quantity_value, whole_number
from twin.limits import plain_int
from twin.errors import InputError
from twin.io.comma_list import comma_items
from twin.io.paths import Files, within

__all__ = ["add_learn_parser", "run_learn", "COLUMNS"]

_HEADINGS = ["learner", "test file", "RMSE", "NSE", "R", "max|res|", "p95|res|", "improv. %", "MRE %", "unit", "inputs",
             "fit s"]


def add_learn_parser(subparsers):
    """Add the ``learn`` sub-command to an argparse ``subparsers`` object; returns its parser."""
    p = subparsers.add_parser(
        "learn", help="fit thermal-error learners on one or more runs and score them on others",
        description="Fit thermal-error learners on a training table and score them (RMSE, NSE, R, "
                    "max|res|, improvement %, MRE %) on one or more test tables.")
    p.add_argument("--train", action="append", default=[], metavar="FILE",
                   help="training run (CSV or NetCDF); repeat for several runs (each file once)")
    p.add_argument("--test", action="append", default=[], metavar="FILE",
                   help="test table; repeat for several (each file once)")
    p.add_argument("--dataset", metavar="DIR", help="a twin dataset folder: train on its --train-split cases, "
                                                     "score on its --split cases")
    p.add_argument("--split", metavar="NAME", help="with --dataset: the split to score on (default test)")
    p.add_argument("--train-split", metavar="NAME", help="with --dataset: the split to train on (default train)")
    p.add_argument("--target", required=True, metavar="NAME",
                   help="target column (CSV) or address such as drift:Z (NetCDF)")
    p.add_argument("--learner", required=True, metavar="L1,L2",
                   help=f"comma-separated learners: {', '.join(sorted(LEARNERS))}")
    p.add_argument("--select", default="all", metavar="METHOD[:K]",
                   help=f"sensor selection: {', '.join(sorted(SELECTORS))} (default all)")
    p.add_argument("--inputs", default="all", metavar="NAMES|all",
                   help="comma-separated candidate inputs (default: all but time and target)")
    p.add_argument("--time-column", default="time", metavar="NAME", help="time column in s (default time)")
    p.add_argument("--segments", type=whole_number("segments", 1, 100), default=1, metavar="N",
                   help="also score each test set's N time segments (each run cut into N equal parts, "
                        "segment k pooled over the runs); default 1: whole runs only")
    p.add_argument("--interval", metavar="TIME",
                   help="thin every run to this sample interval (e.g. '60 s'; a whole multiple of each run's "
                        "interval) so that time-ordered learners see one time step in all runs")
    p.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                   help="also write the scores: FILE.csv (CSV) or FILE.md (Markdown, one table per test set, "
                        "learners by RMSE); repeat for both")
    add_seed_option(p, "random_state for learners and selectors")
    p.set_defaults(func=run_learn)
    return p


def _split_names(text, option):
    names = comma_items(text, "command line", option)     # "mlr," or "a,,b": refused, never dropped
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise InputError("command line", option, f"{', '.join(repeated)} given more than once")
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
            k = plain_int(count)
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


def _fmt(value, digits=4):
    if isinstance(value, float):
        return "nan" if np.isnan(value) else f"{value:.{digits}g}"
    return str(value)


def _text_table(rows, timings):
    """The terminal's leaderboard: the rows (``COLUMNS``) and each learner's fit time [s, wall
    clock], which only the terminal shows (the written files hold what the inputs determine)."""
    shown = [c for c in COLUMNS if c != "note"]         # the notes follow the table, one line each
    cells = [_HEADINGS] + [[_fmt(r[c]) if c not in ("improvement_pct", "mre_pct")
                            else (f"{r[c]:.2f}" if np.isfinite(r[c]) else "nan") for c in shown]
                           + [f"{timings[r['learner']]:.2f}"] for r in rows]
    widths = [max(len(row[i]) for row in cells) for i in range(len(_HEADINGS))]
    numeric = {2, 3, 4, 5, 6, 7, 8, 11}
    lines = []
    for row in cells:
        parts = [cell.rjust(w) if i in numeric else cell.ljust(w) for i, (cell, w) in enumerate(zip(row, widths))]
        lines.append("  ".join(parts).rstrip())
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines + [f"note: {line}" for line in notes(rows)])


def _declare_files(args) -> Files:
    """Every file of the command checked before any work: tables readable, each test once, the
    scores not an input."""
    files = Files()
    if not args.train and not args.dataset:
        raise InputError("command line", "--train", "give one or more --train runs or a --dataset")
    if not args.test and not args.dataset:
        raise InputError("command line", "--test", "give one or more --test tables or a --dataset")
    for option, paths in (("--train", args.train), ("--test", args.test)):
        for path in paths:
            files.input(path, option, "table", once=True)       # by any spelling, a link included
    for option, value in (("--split", args.split), ("--train-split", args.train_split)):
        if value is not None and not args.dataset:
            raise InputError("command line", option, "names a split of a --dataset: give --dataset, or leave it out")
    args.split, args.train_split = args.split or "test", args.train_split or "train"
    if args.dataset and args.split == args.train_split:      # each of its cases would be named as "also a training run"
        raise InputError("command line", "--split", f"{args.split} is also --train-split: scores on a model's own "
                                                    "training runs say nothing of its error on new runs; test on "
                                                    "another split")
    for path in args.output:
        if args.dataset and within(path, args.dataset):
            raise InputError(path, "-o", f"lies in the input dataset {args.dataset}: write the scores elsewhere")
        files.output(path, "-o", (".csv", ".md"))
    formats = [Path(path).suffix.lower() for path in args.output]
    for path, suffix in zip(args.output, formats):
        if formats.count(suffix) > 1:
            raise InputError(path, "-o", f"a second {suffix} output: give one file per format (.csv, .md)")
    return files


def run_learn(args) -> int:
    """Run ``twin learn`` for a parsed namespace; prints the score table; returns 0."""
    from twin.cli.progress import progress_bar

    seed = args.seed
    files = _declare_files(args)
    learner_names = _split_names(args.learner, "--learner")
    learners = {name: _seeded(make_learner(name), seed) for name in learner_names}
    selector, n_select = _make_selector(args.select, seed)
    interval = _interval(args.interval)
    inputs = None if str(args.inputs).strip() in ("", "all") else _split_names(args.inputs, "--inputs")
    if inputs and "all" in inputs:
        raise InputError("command line", "--inputs", f"'all' keeps every sensor and takes no other name, got "
                                                     f"{args.inputs!r}")
    if inputs and args.target in inputs:
        raise InputError("command line", "--inputs", f"the target {args.target} is also an input")

    train_paths = list(args.train)
    test_sets = [(str(path), [path]) for path in args.test]
    if args.dataset:
        cases = dataset_runs(args.dataset, args.train_split)    # a folder with its index, named as such when not
        files.input(Path(args.dataset) / "index.csv", "--dataset", "dataset index (index.csv)")
        # the splits' cases as --train and --test runs: a case also given by hand is one run, not two
        train_paths += [files.input(p, "--train", "table", once=True) for p in cases]
        runs = [files.input(p, "--test", "table", once=True) for p in dataset_runs(args.dataset, args.split)]
        test_sets.append((f"{args.dataset} [{args.split}: {len(runs)} runs]", runs))
    refuse_training_on_test(train_paths, test_sets)
    first = load_table(train_paths[0], args.target, inputs=inputs, time_column=args.time_column, field="--train")
    runs = [first] + [load_table(path, args.target, inputs=first.input_names, time_column=args.time_column,
                                 field="--train") for path in train_paths[1:]]
    runs = [resample(r, interval, str(path)) for r, path in zip(runs, train_paths)]
    train = Table(np.concatenate([r.time for r in runs]), np.vstack([r.X for r in runs]),
                  np.concatenate([r.y for r in runs]), first.input_names)
    train_label = str(train_paths[0]) if len(train_paths) == 1 else f"{len(train_paths)} training runs"
    check_problem(train, train_label, args.target, n_select=n_select)
    tests = []
    for label, paths in test_sets:
        tabs = [resample(load_table(path, args.target, inputs=train.input_names, time_column=args.time_column,
                                    field="--test"), interval, str(path)) for path in paths]
        for path, tab in zip(paths, tabs):
            check_problem(tab, path, args.target, training=False)
        tests.append((label, tabs))
    ordered = [name for name, est in learners.items() if is_time_ordered(est)]
    check_equal_steps(runs + [tab for _, tabs in tests for tab in tabs],
                      train_paths + [path for _, paths in test_sets for path in paths], ordered, args.time_column)
    check_one_interval(runs + [tab for _, tabs in tests for tab in tabs], ordered)
    check_segments([(label, [(tab.X, tab.y) for tab in tabs]) for label, tabs in tests], args.segments, "command line")
    with as_input_error(train_label, args.select):
        select_runs(selector, [(r.X, r.y) for r in runs])
    cols = list(selector.selected_)
    used = [train.input_names[i] for i in cols]

    timings = {}
    rows = leaderboard(learners, [(r.X[:, cols], r.y) for r in runs],
                       [(label, [(tab.X[:, cols], tab.y) for tab in tabs]) for label, tabs in tests],
                       segments=args.segments, inputs=";".join(used), train_label=train_label,
                       progress=progress_bar("learn", "fit"),
                       unit=target_unit(runs + [tab for _, tabs in tests for tab in tabs], args.target),
                       timings=timings)
    print(_text_table(rows, timings))
    for path in args.output:
        if str(path).lower().endswith(".md"):
            write_markdown(path, rows, title=f"twin learn: {args.target}", note=_note(args, train_label))
        else:
            write_csv(path, rows)
    return 0


def _interval(text):
    """``--interval`` in s (None when not given)."""
    return None if text is None else positive_quantity_value(text, "time", "--interval")


def _note(args, train_label):
    """The Markdown page's first lines: what was trained on what, and what the scores compare."""
    return (f"Trained on {train_label}, selection `{args.select}`"
            + (f", every run thinned to {args.interval}" if args.interval else "")
            + f"; scored against `{args.target}` of each test run, every run predicted from its own start"
            + (f", each run also cut into {args.segments} time segments" if args.segments > 1 else "") + ".")
