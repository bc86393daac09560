"""The seeds' learners and sensor selections on a ``twin dataset``: a leaderboard and a placement benchmark.

``python -m validate.studies.dataset_learners DIR [-o OUT] [--split test] [--train-split train]
[--target drift:Z] [--learners L1,L2] [--select gm0n-fcm:4] [--interval "60 s"] [--segments 4]
[--n-random 20] [--no-exhaustive] [--seed N]`` reads the built cases of the dataset folder DIR
(``twin dataset SPEC -o DIR``; the bundled example is ``scenarios/datasets/spindle-ambient-100.toml``)
and writes under OUT (default ``validate-out/dataset_learners/``):

- ``leaderboard.csv`` / ``leaderboard.md``: every learner fitted on the training split's runs
  (pooled learners on all rows, time-ordered ones on each run's sequence, :mod:`learners.runs`) on
  the sensors ``--select`` picks there, scored against the known truth of the test split's runs
  (the noise-free ``drift``; the inputs are the *measured* temperatures, absolute degC), on the
  whole split and on each scenario family in it, whole runs and ``--segments`` time segments
  (:mod:`learners.leaderboard`);
- ``placement.csv`` / ``placement.md``: k-sensor sets (k from ``--select``, 4 with ``--select
  all``, which puts every sensor into the leaderboard) scored by the placement learners (``mlr``,
  ``gm1n``): each registered selection method that picks k (``learners/selection_*.py``) picking
  on the training runs; the machine's intuitive sites (the
  first k of ``motor``, ``spindle_boss``, ``column_front_top``, ``test_bar``); ``--n-random``
  random sets; the truth-greedy set and the optimum for least squares found by
  exhaustive search over all C(p, k) sets with the test truth
  (:mod:`validate.studies.placement_search`; it is the optimum of the ``mlr`` row only). Its
  RMSE and |residual| columns are in the target's unit, the rows' ``unit`` (as the leaderboard's).

Every run is thinned to ``--interval`` (default 60 s, the coarsest sample interval of the bundled
example: time-ordered learners count in samples, so all runs must share one).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from learners.leaderboard import check_segments, leaderboard, unit_heading, write_csv, write_markdown
from learners.registry import LEARNERS, SELECTORS, make_selector
from learners.runs import dataset_runs, refuse_training_on_test, resample, select_runs
from learners.table import load_table, target_unit
from twin.cli.options import add_seed_option, positive_quantity, whole_number
from twin.errors import InputError
from twin.io.atomic import atomic_write_text
from twin.io.comma_list import comma_items
from twin.io.paths import Files, read_text, within
from validate.studies.common import (check_output_folder, cli_parser, markdown_table, preset, run_cli,
                                     write_csv as write_rows)
from validate.studies.placement_search import exhaustive_best, greedy_oracle
from validate.studies.sensor_placement import INTUITIVE

NAME = "dataset_learners"
SEED_LEARNERS = ("mlr", "pcr", "ann", "anfis-fcm", "lssvm", "pso-bpnn", "ar-temp", "combination", "gm1n", "gmc1n",
                 "gmc1n-pso", "gnnmci")
ALL_SENSORS = "all"     # the registry's selector that keeps every sensor: no count, not a placement method
PLACEMENT_LEARNERS = ("mlr", "gm1n")

__all__ = ["load_split", "run_leaderboard", "placement_sets", "run_placement", "main"]


def _families(folder: Path) -> dict[str, str]:
    """{case file path: scenario family} from the dataset's index.csv."""
    index = folder / "index.csv"
    rows = csv.DictReader(read_text(index, "dataset", "dataset index (index.csv)").splitlines())
    return {str(folder / r["file"]): r["family"] for r in rows}


def load_split(folder, split: str, target: str, interval: float | None, inputs=None):
    """[(family, Table), ...] of the built cases of ``split``, each thinned to ``interval`` [s]."""
    folder = Path(folder)
    families = _families(folder)
    out = []
    for path in dataset_runs(folder, split):
        table = load_table(path, target, inputs=inputs, field="dataset")
        out.append((families.get(str(path), split), resample(table, interval, str(path))))
    return out


def _test_sets(tests, split):
    """The whole split, then each family of it when it has several: [(label, [(X, y), ...])]."""
    sets = [(f"{split}: all {len(tests)} runs", [(t.X, t.y) for _, t in tests])]
    families = list(dict.fromkeys(f for f, _ in tests))
    if len(families) > 1:
        for fam in families:
            runs = [(t.X, t.y) for f, t in tests if f == fam]
            sets.append((f"{split}: {fam} ({len(runs)} runs)", runs))
    return sets


def _pick(X_runs, method: str, k: int, seed: int) -> list[int]:
    sel = make_selector(method, **({"n_select": k} if method != ALL_SENSORS else {}))
    if "random_state" in sel.get_params(deep=False):
        sel.set_params(random_state=seed)
    return [int(i) for i in select_runs(sel, X_runs).selected_]


def run_leaderboard(train, tests, names, learner_names, select: str, split: str, segments: int, seed: int,
                    progress=None, source: str = "training runs", target: str = "y"):
    """Leaderboard rows of ``learner_names`` on the inputs ``select`` ("METHOD:K") picks, in the
    target's unit (the rows' ``unit``). A selector refusing the training runs (a constant target)
    is an :class:`InputError` naming ``source`` and ``target`` (or the inputs)."""
    method, _, k = select.partition(":")
    try:
        cols = _pick([(t.X, t.y) for _, t in train], method, int(k or 4), seed)
    except InputError as err:
        raise InputError(source, {"y": target, "X": "inputs"}.get(err.field, err.field), err.message) from None
    sub = lambda t: (t.X[:, cols], t.y)   # noqa: E731
    learners = {name: preset(name, seed) for name in learner_names}
    return leaderboard(learners, [sub(t) for _, t in train],
                       [(label, [(X[:, cols], y) for X, y in runs]) for label, runs in _test_sets(tests, split)],
                       segments=segments, inputs=";".join(names[c] for c in cols),
                       train_label=f"{len(train)} training runs", progress=progress,
                       unit=_unit(train, tests)), cols


def _unit(train, tests) -> str:
    """The target's unit that the runs' files state ("" when none does)."""
    return target_unit([t for _, t in train + tests], "the target")


def placement_sets(train, tests, names, k: int, seed: int, n_random: int, exhaustive: bool, progress=None):
    """{label: [column sets]} and notes {label: text} of the placement benchmark (module doc)."""
    Xtr = np.vstack([t.X for _, t in train])
    ytr = np.concatenate([t.y for _, t in train])
    Xte = np.vstack([t.X for _, t in tests])
    yte = np.concatenate([t.y for _, t in tests])
    cand = list(range(len(names)))
    sets, notes = {}, {}
    for method in placement_selectors():
        sets[f"selected: {method}"] = [_pick([(t.X, t.y) for _, t in train], method, k, seed)]
        notes[f"selected: {method}"] = "picked on the training runs"
    intuitive = [names.index(s) for s in INTUITIVE[:k] if s in names]
    if len(intuitive) == k:
        sets["intuitive"] = [intuitive]
        notes["intuitive"] = "the machine's own sites, one per major part: " + ", ".join(INTUITIVE[:k])
    rng = np.random.default_rng(seed)
    sets["random"] = [sorted(int(c) for c in rng.choice(cand, size=k, replace=False)) for _ in range(n_random)]
    notes["random"] = f"{n_random} seeded draws: mean, min and max"
    sets["truth-greedy"] = [greedy_oracle(Xtr, ytr, Xte, yte, cand, k)]
    notes["truth-greedy"] = "forward selection on the test truth (least squares): greedy, neither a bound nor an optimum"
    if exhaustive:
        best, rmse, n = exhaustive_best(Xtr, ytr, Xte, yte, cand, k, progress=progress)
        sets["truth-exhaustive"] = [best]
        notes["truth-exhaustive"] = (f"best for least squares over all {n} sets (to the normal equations' screen, "
                                     f"its best rechecked by lstsq), test RMSE {rmse:.4g}")
    return sets, notes


def run_placement(train, tests, names, sets, learner_names, seed: int):
    """One row per set label and learner: test RMSE, NSE, max and p95 |residual| over the test
    runs, in the target's unit (the row's ``unit``, as in the leaderboard); random draws as mean
    with min and max."""
    unit = _unit(train, tests)
    rows = []
    test_set = [(f"{len(tests)} test runs", [(t.X, t.y) for _, t in tests])]
    for label, col_sets in sets.items():
        for name in learner_names:
            scores = [leaderboard({name: preset(name, seed)}, [(t.X[:, c], t.y) for _, t in train],
                                  [(lab, [(X[:, c], y) for X, y in runs]) for lab, runs in test_set])[0]
                      for c in col_sets]
            rmse = np.array([s["rmse"] for s in scores])
            row = {"set": label, "learner": name, "n_sets": len(scores), "rmse": float(rmse.mean()),
                   "rmse_min": float(rmse.min()), "rmse_max": float(rmse.max()),
                   "nse": float(np.mean([s["nse"] for s in scores])),
                   "max_abs_residual": float(np.mean([s["max_abs_residual"] for s in scores])),
                   "p95_abs_residual": float(np.mean([s["p95_abs_residual"] for s in scores])), "unit": unit,
                   "inputs": ";".join(names[c] for c in col_sets[0]) if len(col_sets) == 1 else "(random draws)"}
            rows.append(row)
    return rows


DEFAULT_OUTPUT = f"validate-out/{NAME}"
OUTPUTS = ("leaderboard.csv", "leaderboard.md", "placement.csv", "placement.md")
N_RANDOM = 20      # random sensor sets of the placement benchmark (--n-random)


def _parser():
    p = cli_parser(f"python -m validate.studies.{NAME}", __doc__)
    p.add_argument("dataset", help="a twin dataset folder (twin dataset SPEC -o DIR)")
    p.add_argument("-o", "--output", default=DEFAULT_OUTPUT,
                   help=f"output folder (default validate-out/{NAME})")
    p.add_argument("--split", default="test", help="the split scored (default test)")
    p.add_argument("--train-split", default="train", help="the split trained on (default train)")
    p.add_argument("--target", default="drift:Z", help="the target (default drift:Z, the true tool-point drift)")
    p.add_argument("--learners", default=",".join(SEED_LEARNERS), help="comma-separated learners (default: the seeds')")
    p.add_argument("--select", default="gm0n-fcm:4",
                   help="METHOD:K for the leaderboard's inputs, or all: every sensor (default gm0n-fcm:4)")
    p.add_argument("--interval", type=positive_quantity("time"), default="60 s",
                   help="thin every run to this sample interval, with its unit (default '60 s')")
    p.add_argument("--segments", type=whole_number("segments", 1), default=4, help="time segments per run in the leaderboard (default 4)")
    p.add_argument("--n-random", type=whole_number("random sets", 1), default=None,
                   help=f"random sensor sets (default {N_RANDOM})")
    p.add_argument("--no-exhaustive", action="store_true", help="skip the exhaustive search of the placement")
    p.add_argument("--no-placement", action="store_true", help="the leaderboard only")
    add_seed_option(p, "random_state of learners, selectors and draws")
    return p


def _check_names(args) -> list[str]:
    """The learners of ``--learners`` and the selector of ``--select`` exist, K is a whole number >= 1:
    checked before any data is read. Returns the learner names."""
    names = comma_items(args.learners, "command line", "--learners")
    unknown = [n for n in names if n not in LEARNERS]
    if not names or unknown:
        raise InputError("command line", "--learners",
                         f"unknown learner {unknown[0]!r}; known: {', '.join(sorted(LEARNERS))}" if unknown
                         else "no learner given")
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise InputError("command line", "--learners", f"{', '.join(twice)} given more than once")
    if args.no_placement and (args.no_exhaustive or args.n_random is not None):
        raise InputError("command line", "--no-exhaustive" if args.no_exhaustive else "--n-random",
                         "sets the placement benchmark, which --no-placement leaves out: give one or the other")
    method, colon, k = args.select.partition(":")
    if method not in SELECTORS:
        raise InputError("command line", "--select", f"unknown selector {method!r}; known: {', '.join(sorted(SELECTORS))}")
    if method == ALL_SENSORS and colon:
        raise InputError("command line", "--select", f"{ALL_SENSORS} keeps every sensor and takes no count, got {k!r}")
    if colon and (not k.isdigit() or int(k) < 1):
        raise InputError("command line", "--select", f"K must be a whole number >= 1, got {k!r}")
    return names


def placement_selectors() -> list[str]:
    """The registered selectors that pick a given number of sensors (every one but ``all``), in the
    registry's order: a selector registered later joins the placement benchmark."""
    return [name for name in SELECTORS if "n_select" in SELECTORS[name]().get_params()]


def _run(args) -> int:
    learner_names = _check_names(args)
    interval = args.interval
    if not Path(args.dataset).is_dir():
        raise InputError(args.dataset, "dataset", "not a dataset folder (twin dataset SPEC -o DIR makes one)")
    files = Files()
    files.input(Path(args.dataset) / "index.csv", "dataset", "dataset index (index.csv)")
    if within(args.output, args.dataset):
        raise InputError(args.output, "-o", f"lies in the input dataset {args.dataset}: write the study elsewhere")
    out = check_output_folder(args.output, OUTPUTS if not args.no_placement else OUTPUTS[:2], default=DEFAULT_OUTPUT,
                              files=files)
    refuse_training_on_test(dataset_runs(args.dataset, args.train_split, "dataset"),
                            [(args.split, dataset_runs(args.dataset, args.split, "dataset"))], "--split")
    print(f"reading {args.dataset} ...", flush=True)
    train = load_split(args.dataset, args.train_split, args.target, interval)
    names = train[0][1].input_names
    tests = load_split(args.dataset, args.split, args.target, interval, inputs=names)
    method, _, count = args.select.partition(":")
    k = int(count or 4)
    if method == ALL_SENSORS and k > len(names) and not args.no_placement:
        raise InputError("command line", "--select", f"the placement benchmark compares sets of {k} sensors (its "
                         f"default with {ALL_SENSORS}), the dataset's runs have {len(names)}: add --no-placement")
    if method != ALL_SENSORS and k > len(names):
        raise InputError("command line", "--select", f"asks for {k} inputs, the dataset's runs have {len(names)} sensors")
    check_segments(_test_sets(tests, args.split), args.segments, f"{args.dataset} (every run thinned to {interval:g} s)")
    print(f"{len(train)} training runs ({sum(len(t.y) for _, t in train)} rows), {len(tests)} test runs "
          f"({sum(len(t.y) for _, t in tests)} rows), {len(names)} sensors", flush=True)

    def progress(done, total):
        print(f"  {done}/{total}", flush=True)

    rows, _ = run_leaderboard(train, tests, names, learner_names, args.select, args.split, args.segments, args.seed,
                              progress, f"{args.dataset} (split {args.train_split})", args.target)
    note = (f"Dataset `{args.dataset}`: trained on the {len(train)} runs of split `{args.train_split}`, scored against "
            f"the noise-free `{args.target}` of the {len(tests)} runs of split `{args.split}` (each run predicted from "
            f"its own start); inputs: the measured temperatures [degC] that `{args.select}` picks on the training "
            f"runs; every run thinned to {interval:g} s. Plausible, not a measured machine.")
    out.mkdir(parents=True, exist_ok=True)      # after the fits: a learner refusing the data leaves no folder
    write_csv(out / "leaderboard.csv", rows)
    write_markdown(out / "leaderboard.md", rows, title=f"Leaderboard: {args.target}", note=note)
    print(f"wrote {out / 'leaderboard.md'}, leaderboard.csv", flush=True)
    if args.no_placement:
        return 0
    print("placement: selecting, drawing, searching ...", flush=True)
    sets, notes = placement_sets(train, tests, names, k, args.seed, args.n_random or N_RANDOM, not args.no_exhaustive,
                                 lambda d, n: print(f"  exhaustive {d}/{n}", flush=True) if d % 5_000_000 < 200_000
                                 else None)
    prow = run_placement(train, tests, names, sets, PLACEMENT_LEARNERS, args.seed)
    for r in prow:
        r["how"] = notes.get(r["set"], "")
    write_rows(out / "placement.csv", prow)
    cols = ["set", "learner", "n_sets", "rmse", "rmse_min", "rmse_max", "nse", "max_abs_residual", "p95_abs_residual",
            "inputs", "how"]
    unit = unit_heading(prow[0]["unit"] if prow else "")
    heads = ["sensor set", "learner", "sets", f"test RMSE {unit}", "min", "max", "NSE", f"max |res| {unit}",
             f"p95 |res| {unit}", "inputs", "how"]
    text = (f"# Sensor placement on `{args.dataset}`, {k} sensors, {args.target}\n\n{note}\n\nCandidates: all "
            f"{len(names)} sensors. The truth-greedy and truth-exhaustive sets use the test runs' truth; the "
            "exhaustive one is the best set for least squares (the `mlr` rows) over every set, to the accuracy of "
            "its normal-equations screen, not for `gm1n`.\n\n"
            + markdown_table(prow, cols, heads) + "\n")
    atomic_write_text(out / "placement.md", text, field="-o")
    print(markdown_table(prow, cols, heads))
    print(f"wrote {out / 'placement.md'}, placement.csv")
    return 0


def main(argv=None) -> int:
    return run_cli(_parser().parse_args, argv, _run)


if __name__ == "__main__":
    raise SystemExit(main())
