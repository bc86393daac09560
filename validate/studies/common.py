"""Shared pieces of the learner studies: command line, learner presets, fit-and-score, output files."""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

import numpy as np

from twin.io.markdown import fixed, table

__all__ = ["cli_parser", "whole_numbers", "run_cli", "check_output_folder", "check_camera_pose",
           "parse_args", "study_main", "data_main", "table_main", "preset", "fit_score", "select", "write_csv",
           "score_units", "markdown_table", "fmt"]

# Seed-like hyper-parameters (seed 001: ANFIS-FCM 6 rules for 1-5 inputs; ANN 4-10-1).
# ANFIS: MATLAB anfis with checking data, as seed 001 split its training test into training and
# checking (ratio not stated): every 5th block of 30 samples (5 min at 10 s) checks, and the epoch of
# least checking error is kept.
PRESETS = {
    "anfis-fcm": {"n_rules": 6, "epochs": 100, "validation_fraction": 0.2, "validation_block": 30},
    "anfis-grid": {"n_mfs": 2, "epochs": 50, "validation_fraction": 0.2, "validation_block": 30},
    "ann": {"shape": "4-10-1"},
}


# ------------------------------------------------------------------------------------------ command line
# The studies and benchmarks follow the twin CLI's rules (README "Errors"): a usage error or bad input
# is one line ``error: <source>: <field>: <message>`` on stderr and exit code 2, checked before any
# output folder is made or any run starts; an option that takes one value refuses a second.


def cli_parser(prog: str, description: str) -> argparse.ArgumentParser:
    """An argument parser with the twin CLI's usage errors (one line naming the option, exit code 2)
    that refuses a single-valued option given twice (``twin.cli``); its description is the first
    paragraph of ``description`` (a module docstring), whole (its first line alone stopped
    mid-sentence)."""
    from twin.cli import Parser

    return Parser(prog=prog, description=" ".join((description or "").strip().split("\n\n")[0].split()))


def whole_numbers(what: str, lower: int = 1):
    """argparse type of a comma-separated list of distinct whole numbers of at least ``lower``."""
    from twin.cli.options import whole_number

    one = whole_number(what, lower)

    def parse(text: str) -> list[int]:
        items = [t.strip() for t in text.split(",")]
        if not all(items):      # "2,,3" or "2,": a number left out by mistake, never dropped
            raise argparse.ArgumentTypeError(f"expected comma-separated whole numbers of {what}, got {text!r}")
        values = [one(t) for t in items]
        twice = sorted({v for v in values if values.count(v) > 1})
        if twice:
            raise argparse.ArgumentTypeError(f"{', '.join(map(str, twice))} given more than once")
        return values
    return parse


def run_cli(parse, argv, body) -> int:
    """``body(parse(argv))`` as the twin CLI runs a command (``twin.cli.main``): a usage error
    returns 2 (its line printed by the parser; ``--help`` returns 0), an :class:`twin.errors.
    InputError` prints ``error: <source>: <field>: <message>`` and returns 2."""
    from twin.errors import InputError

    try:
        args = parse(argv)
    except SystemExit as exit_:
        return int(exit_.code or 0)
    try:
        return int(body(args) or 0)
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2


def check_output_folder(path, contents: tuple[str, ...] = (), field: str = "-o", default=None, files=None) -> Path:
    """The output folder ``path`` checked as the twin CLI checks one (:meth:`twin.io.paths.Files.folder`:
    a folder, or one that can be made in an existing writable folder, never a file; the files it
    will hold, ``contents``, checked like outputs, never an input declared to ``files``), before
    anything is made or simulated; it is not created here. The ``default`` folder (e.g.
    ``validate-out/NAME``) may lack its parents, made with it: then the nearest missing one is
    checked."""
    from twin.io.paths import Files, output_folder

    path = Path(path)
    top = path
    while default is not None and path == Path(default) and not top.parent.exists() and top.parent != top:
        top = top.parent
    if top != path:
        output_folder(top, field)
        return path
    return (files if files is not None else Files()).folder(path, field, tuple(contents))


def check_camera_pose(pose: str, machine: str = "cframe-vmc") -> str:
    """``--camera POSE`` checked: a camera pose of ``machine`` aimed at a part (the part the spots
    are laid on, :func:`validate.studies.learner_data.build_camera_data`)."""
    from twin.api import machine_by_name
    from twin.errors import InputError
    from twin.observe.camera import CameraConfig

    m = machine_by_name(machine)
    aimed = [p.name for p in m.camera_poses if p.subject]
    if not CameraConfig(pose=pose, source="command line", where="--camera").resolve_pose(m).subject:
        raise InputError("command line", "--camera", f"pose {pose!r} is aimed at no part of machine {m.name}, so it "
                                                     f"has no spots; use one of {', '.join(aimed)}")
    return pose


def parse_args(name: str, doc: str, argv=None, camera: bool = False, seed: bool = True,
               folder: str | None = None) -> argparse.Namespace:
    """``[--quick] [-o DIR] [--seed N] [--camera [POSE]]`` (``--seed`` only with ``seed``, for the
    studies that draw noise or seed a learner; ``--camera`` only with ``camera``, for those that read
    camera frames); the default folder is ``validate-out/<folder>`` (``folder`` defaults to ``name``;
    ``validate-out/<folder>-camera`` with --camera). A usage error exits (SystemExit 2) with one
    line, like the twin CLI."""
    from twin.cli.options import seed as seed_type

    p = cli_parser(f"python -m validate.studies.{name}", doc)
    p.add_argument("--quick", action="store_true", help="coarse mesh (smoke run); default: the default mesh")
    folder = folder or name
    p.add_argument("-o", "--output", help=f"output folder (default validate-out/{folder}"
                                          + (f", or validate-out/{folder}-camera with --camera)" if camera else ")"))
    if seed:
        p.add_argument("--seed", type=seed_type, default=0, help="noise seed and random_state (0 to 2**32-1, default 0)")
    if camera:
        p.add_argument("--camera", nargs="?", const="carrier-front", metavar="POSE",
                       help="take the inputs from a thermal camera at POSE (default carrier-front): seed 001's 525 "
                            "virtual spots on the frames, instead of the dense surface-sensor grid")
    args = p.parse_args(argv)
    args.default_output = f"validate-out/{folder}{'-camera' if getattr(args, 'camera', None) else ''}"
    args.output = args.output or args.default_output
    return args


def study_main(name: str, doc: str, argv, body, contents: tuple[str, ...] = (), camera: bool = False,
               seed: bool = True, folder: str | None = None) -> int:
    """``main`` of a study on the common options (:func:`parse_args`, whose ``camera``, ``seed`` and
    ``folder`` it passes on): parse ``argv``, check the camera pose and the output folder with the
    files it will hold (``contents``) before anything is made or simulated, then return
    ``body(args, out)`` (``out`` not yet made: the body makes it when it writes). Bad input: one
    line ``error: <source>: <field>: <message>``, exit code 2."""
    def run(args):
        if getattr(args, "camera", None) is not None:
            check_camera_pose(args.camera)
        out = check_output_folder(args.output, contents, default=args.default_output)
        return body(args, out)
    return run_cli(lambda a: parse_args(name, doc, a, camera=camera, seed=seed, folder=folder), argv, run)


def data_main(name: str, doc: str, argv, body, contents: tuple[str, ...] = ()) -> int:
    """``main`` of a study on the seed-001 runs (:mod:`validate.studies.learner_data`): the options
    of :func:`study_main` with ``--camera``, checked; then the output folder is made, the training
    and test data built (or read cached from it) and ``body(args, out, StudyData)`` returned."""
    def run(args, out):
        from validate.studies.learner_data import build_camera_data, build_data

        out.mkdir(parents=True, exist_ok=True)
        print(f"simulating (or reading cached runs) in {out} ...", flush=True)
        resolution = "coarse" if args.quick else "default"
        if args.camera:
            data = build_camera_data(out, resolution=resolution, pose=args.camera, seed=args.seed)
        else:
            data = build_data(out, resolution=resolution, seed=args.seed)
        return body(args, out, data)
    return study_main(name, doc, argv, run, contents, camera=True)


def preset(name: str, seed: int = 0, **override):
    """A registered learner with the studies' seed-like presets and ``random_state=seed``."""
    from learners import make_learner

    est = make_learner(name, **{**PRESETS.get(name, {}), **override})
    if "random_state" in est.get_params(deep=False):
        est.set_params(random_state=seed)
    return est


def select(X, y, k: int, names: list[str], method: str = "gm0n-fcm", seed: int = 0) -> list[int]:
    """Indices (into ``names``/columns of ``X``) of the ``k`` inputs a selector picks on (X, y)."""
    from learners import make_selector

    sel = make_selector(method, n_select=k)
    if "random_state" in sel.get_params(deep=False):
        sel.set_params(random_state=seed)
    sel.fit(X, y)
    return [int(i) for i in sel.selected_]


def fit_score(est, X_train, y_train, X_test, y_test) -> tuple[dict, np.ndarray]:
    """Fit on train, predict both; returns (row of train_/test_ metrics, test prediction). No wall
    time goes into the row: the same inputs and seed write the same study files."""
    from learners.metrics import score_all

    est.fit(X_train, y_train)
    tr = score_all(y_train, est.predict(X_train))
    pred = np.asarray(est.predict(X_test), dtype=float)
    te = score_all(y_test, pred)
    return {**{f"train_{k}": float(v) for k, v in tr.items()}, **{f"test_{k}": float(v) for k, v in te.items()}}, pred


def table_main(name: str, doc: str, argv, rows_for, markdown, units: dict[str, str] | None = None) -> int:
    """``main`` of a study that writes one table: ``[--quick] [-o DIR]`` checked (:func:`study_main`),
    compute ``rows_for(resolution)`` (coarse mesh with ``--quick``, else default), write ``<name>.csv``
    (the columns of ``units`` named with their unit, :func:`write_csv`) and ``<name>.md``
    (``markdown(rows, command, resolution)``) into the output folder and print it."""
    from twin.io.atomic import atomic_write_text

    def run(args, out):
        resolution = "coarse" if args.quick else "default"
        rows = rows_for(resolution)
        out.mkdir(parents=True, exist_ok=True)
        write_csv(out / f"{name}.csv", rows, units)
        command = f"python -m validate.studies.{name}{' --quick' if args.quick else ''}"
        atomic_write_text(out / f"{name}.md", markdown(rows, command, resolution))
        print(markdown(rows, command, resolution))
        return 0
    return study_main(name, doc, argv, run, (f"{name}.csv", f"{name}.md"), seed=False)


def write_csv(path: Path, rows: list[dict], units: dict[str, str] | None = None) -> Path:
    """Write dict rows (union of keys, in first-seen order) to ``path``. ``units`` = {key: unit}:
    the header of each such column is ``<key>_<unit>`` (results carry units: ``test_rmse`` in um
    is written ``test_rmse_um``); keys the rows lack are ignored."""
    units = units or {}
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    header = {k: f"{k}_{units[k]}" if k in units else k for k in keys}
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=[header[k] for k in keys])
        w.writeheader()
        w.writerows({header[k]: v for k, v in r.items()} for r in rows)
    return path


def score_units(unit: str = "um") -> dict[str, str]:
    """{column: unit} of :func:`fit_score`'s columns in the target's unit (RMSE and max |residual|
    of the training and the test data), for :func:`write_csv`'s ``units``."""
    return {f"{split}_{score}": unit for split in ("train", "test") for score in ("rmse", "max_abs_residual")}


def fmt(v, digits: int = 3) -> str:
    """A table cell: a float to ``digits`` decimals (3 significant digits from 1e5 on), NaN and None
    empty, and a value that rounds to zero written 0, never -0.000."""
    if isinstance(v, float):
        if np.isnan(v):
            return ""
        return f"{v:.3g}" if abs(v) >= 1e5 else fixed(v, digits)
    return "" if v is None else str(v)


def markdown_table(rows: list[dict], columns: list[str], headers: list[str] | None = None) -> str:
    """A GitHub Markdown table of ``columns`` of ``rows`` (cells escaped: :mod:`twin.io.markdown`)."""
    return "\n".join(table(headers or columns, [[fmt(r.get(c)) for c in columns] for r in rows]))


if __name__ == "__main__":
    from validate.studies.not_a_study import not_a_command

    not_a_command("validate.studies.common")
