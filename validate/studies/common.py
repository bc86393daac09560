"""Shared pieces of the learner studies: command line, learner presets, fit-and-score, output files."""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np

from learners import make_learner, make_selector
from learners.metrics import score_all

__all__ = ["parse_args", "preset", "fit_score", "select", "write_csv", "markdown_table", "fmt", "table_main"]

# Seed-like hyper-parameters (seed 001: ANFIS-FCM 6 rules for 1-5 inputs; ANN 4-10-1).
# ANFIS: MATLAB anfis with checking data, as seed 001 split its training test into training and
# checking (ratio not stated): every 5th block of 30 samples (5 min at 10 s) checks, and the epoch of
# least checking error is kept.
PRESETS = {
    "anfis-fcm": {"n_rules": 6, "epochs": 100, "validation_fraction": 0.2, "validation_block": 30},
    "anfis-grid": {"n_mfs": 2, "epochs": 50, "validation_fraction": 0.2, "validation_block": 30},
    "ann": {"shape": "4-10-1"},
}


def parse_args(name: str, doc: str, argv=None) -> argparse.Namespace:
    """``[--quick] [-o DIR] [--seed N] [--camera [POSE]]``; the default folder is
    ``validate-out/<name>/``."""
    p = argparse.ArgumentParser(prog=f"python -m validate.studies.{name}", description=doc.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="coarse mesh (smoke run); default: the default mesh")
    p.add_argument("-o", "--output", help=f"output folder (default validate-out/{name}, or validate-out/{name}-camera "
                                          "with --camera)")
    p.add_argument("--seed", type=int, default=0, help="noise seed and random_state (default 0)")
    p.add_argument("--camera", nargs="?", const="carrier-front", metavar="POSE",
                   help="take the inputs from a thermal camera at POSE (default carrier-front): seed 001's 525 "
                        "virtual spots on the frames, instead of the dense surface-sensor grid")
    args = p.parse_args(argv)
    args.output = args.output or f"validate-out/{name}{'-camera' if args.camera else ''}"
    return args


def start(name: str, doc: str, argv=None):
    """Common start of a study's ``main``: parse the options, create the output folder and build
    (or read cached) training and test data. Returns (args, output folder, StudyData)."""
    from validate.studies.learner_data import build_camera_data, build_data

    args = parse_args(name, doc, argv)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    print(f"simulating (or reading cached runs) in {out} ...", flush=True)
    resolution = "coarse" if args.quick else "default"
    if args.camera:
        return args, out, build_camera_data(out, resolution=resolution, pose=args.camera, seed=args.seed)
    return args, out, build_data(out, resolution=resolution, seed=args.seed)


def preset(name: str, seed: int = 0, **override):
    """A registered learner with the studies' seed-like presets and ``random_state=seed``."""
    est = make_learner(name, **{**PRESETS.get(name, {}), **override})
    if "random_state" in est.get_params(deep=False):
        est.set_params(random_state=seed)
    return est


def select(X, y, k: int, names: list[str], method: str = "gm0n-fcm", seed: int = 0) -> list[int]:
    """Indices (into ``names``/columns of ``X``) of the ``k`` inputs a selector picks on (X, y)."""
    sel = make_selector(method, n_select=k)
    if "random_state" in sel.get_params(deep=False):
        sel.set_params(random_state=seed)
    sel.fit(X, y)
    return [int(i) for i in sel.selected_]


def fit_score(est, X_train, y_train, X_test, y_test) -> tuple[dict, np.ndarray]:
    """Fit on train, predict both; returns (row of train_/test_ metrics + fit_time_s, test prediction)."""
    start = time.perf_counter()
    est.fit(X_train, y_train)
    fit_s = time.perf_counter() - start
    tr = score_all(y_train, est.predict(X_train))
    pred = np.asarray(est.predict(X_test), dtype=float)
    te = score_all(y_test, pred)
    row = {**{f"train_{k}": float(v) for k, v in tr.items()}, **{f"test_{k}": float(v) for k, v in te.items()},
           "fit_time_s": fit_s}
    return row, pred


def table_main(name: str, doc: str, argv, rows_for, markdown) -> int:
    """``main`` of a study that writes one table: parse ``[--quick] [-o DIR]``, compute
    ``rows_for(resolution)`` (coarse mesh with ``--quick``, else default), write ``<name>.csv`` and
    ``<name>.md`` (``markdown(rows, command, resolution)``) into the output folder and print it."""
    from twin.io.atomic import atomic_write_text

    args = parse_args(name, doc, argv)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    resolution = "coarse" if args.quick else "default"
    rows = rows_for(resolution)
    write_csv(out / f"{name}.csv", rows)
    command = f"python -m validate.studies.{name}{' --quick' if args.quick else ''}"
    atomic_write_text(out / f"{name}.md", markdown(rows, command, resolution))
    print(markdown(rows, command, resolution))
    return 0


def write_csv(path: Path, rows: list[dict]) -> Path:
    """Write dict rows (union of keys, in first-seen order) to ``path``."""
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    return path


def fmt(v, digits: int = 3) -> str:
    if isinstance(v, float):
        if np.isnan(v):
            return ""
        return f"{v:.3g}" if abs(v) >= 1e5 else f"{v:.{digits}f}"
    return "" if v is None else str(v)


def markdown_table(rows: list[dict], columns: list[str], headers: list[str] | None = None) -> str:
    """A GitHub Markdown table of ``columns`` of ``rows``."""
    headers = headers or columns
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(fmt(r.get(c)) for c in columns) + " |" for r in rows]
    return "\n".join(lines)
