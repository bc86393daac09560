"""``twin dataset SPEC.toml -o DIR [--dry-run] [--max-cases N] [--jobs N] [--scheduler ADDRESS|local] [--prune]``.

Builds the cases a dataset spec plans (:mod:`twin.dataset`) into ``DIR/cases/<hash>.nc`` and
writes ``DIR/index.csv``, ``index.parquet``, ``card.json`` and ``README.md``. A rerun skips the
cases already whole; ``--max-cases N`` builds only the plan's first N (the rest later, by rerunning
without it); ``--dry-run`` prints the plan and a calibrated time estimate and writes nothing.
Files of cases no longer in the plan (an edited spec) are kept and reported, or removed with
``--prune``. An interrupt leaves whole case files only and an up-to-date index.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from twin.cli.options import whole_number
from twin.cli.progress import progress_bar


def add_parser(sub) -> None:
    p = sub.add_parser("dataset", help="build a benchmark dataset from a spec: one NetCDF per case, an index, a card",
                       description="Build the cases of a dataset spec (TOML) into a folder; rerun to resume.")
    p.add_argument("spec", help="dataset spec: a .toml file, or a bundled spec's name (twin list scenarios lists them)")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="dataset folder (created if missing)")
    p.add_argument("--dry-run", action="store_true", help="print the plan and an estimated time; write nothing")
    p.add_argument("--max-cases", type=whole_number("cases"), metavar="N", help="build only the plan's first N cases")
    p.add_argument("--jobs", type=whole_number("workers", 1, 1024), default=2, metavar="N", help="worker processes (default 2)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="run the cases on Dask distributed: 'local' for a local "
                   "cluster of --jobs workers, or a scheduler address such as tcp://host:8786")
    p.add_argument("--prune", action="store_true", help="remove case files that the spec no longer plans")
    p.set_defaults(func=run)


def run(args) -> int:
    from twin.dataset import CASES, INDEX_FILES, build, executor, is_whole, load_spec, plan, write_index
    from twin.dataset.card import check_dataset_folder
    from twin.dataset.spec import spec_path as bundled_or_path
    from twin.dataset.runner import check_scheduler
    from twin.io.atomic import output_folder
    from twin.io.paths import Files

    check_scheduler(args.scheduler)
    files = Files()
    spec_path = files.input(bundled_or_path(args.spec), "spec", "dataset spec")
    spec = load_spec(spec_path)
    for i, f in enumerate(spec.families):      # the families keep the order of [[scenarios]]
        for path, key, what in f.inputs:
            files.input(path, f"scenarios[{i}].{key}", what)
    folder = files.folder(args.output, "-o", INDEX_FILES)
    check_dataset_folder(folder)           # -o . beside a user's own README.md: not replaced
    cases = plan(spec)
    chosen = cases if args.max_cases is None else cases[:args.max_cases]
    case_dir = Path(folder) / CASES
    whole = {c.hash for c in chosen if is_whole(case_dir / c.file, c.hash)}
    todo = [c for c in chosen if c.hash not in whole]
    if args.dry_run:
        return _dry_run(spec, cases, chosen, todo, args)
    planned = {c.hash for c in cases}
    others = sorted(p for p in case_dir.glob("*.nc") if p.stem not in planned) if case_dir.is_dir() else []
    stale = [p for p in others if is_whole(p, p.stem)]      # case files of an earlier spec: ours to prune
    foreign = [p for p in others if p not in stale]         # anything else is the user's, never removed
    with output_folder(folder):
        if args.prune:
            for p in stale:
                p.unlink()
        t0 = time.perf_counter()
        built: dict = {}
        info = {"scheduler": args.scheduler or "process pool", "jobs": args.jobs}
        try:
            with executor(args.scheduler, args.jobs) as pool:
                built = build(chosen, folder, pool, progress_bar(f"dataset {spec.name}", unit="case"))
        except KeyboardInterrupt as err:
            rows = write_index(spec, cases, folder, {**info, "interrupted": True})
            done = sum(r["built"] for r in rows)
            print(f"{_fresh()}interrupted: {done} of {len(cases)} cases whole in {case_dir}, index and card "
                  f"up to date; rerun the same command to resume", file=sys.stderr)
            from twin.cli import Terminated

            return 143 if isinstance(err, Terminated) else 130
        wall = time.perf_counter() - t0
        rows = write_index(spec, cases, folder, {**info, "seconds": round(wall, 3), "cases_built": len(built)})
    done = sum(r["built"] for r in rows)
    mb = sum(r["bytes"] for r in rows) / 1e6
    print(f"wrote {folder}: built {len(built)} case(s) in {wall:.1f} s, {len(whole)} already there; "
          f"{done} of {len(cases)} planned cases whole ({mb:.2f} MB); index.csv, index.parquet, card.json, README.md")
    if stale:
        what = "removed" if args.prune else "kept (not in the index; --prune removes them)"
        print(f"{len(stale)} case file(s) from an earlier spec {what}")
    if foreign:
        print(f"{len(foreign)} other file(s) in {case_dir} kept, not case files of a twin dataset (--prune leaves "
              f"them): {', '.join(p.name for p in foreign[:3])}{' ...' if len(foreign) > 3 else ''}")
    return 0


def _fresh() -> str:
    return "\n" if sys.stderr.isatty() else ""


def _dry_run(spec, cases, chosen, todo, args) -> int:
    from twin.dataset import estimate
    from twin.units import format_quantity

    by = {}
    for c in cases:
        key = (c.info["machine"], c.info["family"])
        by.setdefault(key, {}).setdefault(c.split, 0)
        by[key][c.split] += 1
    print(f"dataset {spec.name}: {len(cases)} case(s) planned, {len(chosen) - len(todo)} of the "
          f"{len(chosen)} to build already whole; mesh {spec.mesh}, solver {spec.solver}, seed {spec.seed}")
    for (machine, family), splits in by.items():
        print(f"  {machine} / {family}: " + ", ".join(f"{n} {s}" for s, n in splits.items()))
    for k, d in spec.parameters.items():
        print(f"  parameter {k}: {d.kind.replace('_', '-')} {', '.join(format_quantity(v, d.dimension) for v in d.values)}")
    if todo:
        from twin.physics.parallel import processors

        here = args.scheduler in (None, "local")       # the workers share this machine's processors
        cores = processors()
        e = estimate(todo, 1 if args.scheduler is None and args.jobs == 1 else args.jobs, cores=cores if here else None)
        rates = ", ".join(f"{k} {v * 1e3:.1f} ms" for k, v in e["per_step_s"].items())
        print(f"estimated time: {_duration(e['seconds'])} for {e['cases']} case(s), {e['steps']} time steps on "
              f"{args.jobs} worker(s)" + (f", {cores} core(s) here, taken as free" if here else "")
              + f" (calibrated here: per step {rates}; preparing {e['prepare_s']:.1f} s per worker)")
    else:
        print("nothing to build")
    return 0


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"
