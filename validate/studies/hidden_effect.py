"""The diagnosis study: hidden library effects, wrong parameters, causes outside the library, pairs
and nothing hidden; does ``twin diagnose`` say the right thing?

``python -m validate.studies.hidden_effect [--machine M] [--classes hidden,parameter,...]
[--quick] [--jobs N] [--out DIR]`` writes ``hidden_effect.md`` and ``hidden_effect.csv`` into
``DIR`` (default ``validate-out/hidden_effect/<machine>``); the cases are those of
:mod:`validate.studies.diagnosis_cases`.

Truth (:mod:`validate.synthetic`) on the ``fine`` mesh with half the sample interval, perturbed
materials, noise, quantisation and bias; the diagnosing model on ``default``, with its
discretisation error estimated against ``coarse`` (never the truth's mesh; ``--truth``,
``--model``, ``--error-mesh`` change them). ``--quick`` halves the spindle scenarios and samples
them every 20 s (the day-night scenario is kept whole: its excitation is the 24 h cycle).
"""

from __future__ import annotations

import csv
import io
import time
from pathlib import Path

import numpy as np

from geometries import MACHINES, build_machine
from geometries.axes import with_feed_drives
from twin.effects import EFFECTS
from twin.fem.mesh import mesh_machine
from twin.errors import InputError
from twin.io.atomic import atomic_write_text
from twin.io.comma_list import comma_items
from validate.studies import diagnosis_cases as cases_
from validate.studies.common import cli_parser
from validate.studies.diagnosis_cases import BARS, CLASSES, all_cases, run_case, score

_WORKER: dict = {}


def _run_planned(args) -> dict:
    """Pool worker: one case, with the machine and the model's mesh built once per process."""
    case, quick, truth_mesh, model_mesh, error_mesh, machine = args
    if _WORKER.get("key") != (machine, model_mesh):
        m = build_machine(machine)
        _WORKER.update(key=(machine, model_mesh), machine=m, mm=mesh_machine(m, model_mesh))
    row = run_case(case, _WORKER["machine"], _WORKER["mm"], quick, truth_mesh, error_mesh)
    row.update(truth_mesh=truth_mesh, model_mesh=model_mesh, error_mesh=error_mesh or "none")
    return row


def _rate(rows, key) -> float:
    vals = [bool(r[key]) for r in rows if key in r]
    return float(np.mean(vals)) if vals else float("nan")


def class_rates(rows: list[dict]) -> list[tuple[str, str, float, float, int]]:
    """(class, criterion, rate, bar, n) per criterion of every class present (:data:`BARS`)."""
    out = []
    for cls in CLASSES:
        rs = [r for r in rows if r["class"] == cls]
        if not rs:
            continue
        n = len(rs)
        bar = BARS[cls]
        if cls in ("hidden", "parameter", "pair"):
            what = {"hidden": "hidden effect named first", "parameter": "wrong parameter named first",
                    "pair": "the pair is the top candidate"}[cls]
            out.append((cls, what + " (and the verdict names it)",
                        float(np.mean([r["first"] and r["verdict"] in ("explained", "partly_explained") for r in rs])),
                        bar["first"], n))
            out.append((cls, "fitted within 25 %" + (" (each member)" if cls == "pair" else ""), _rate(rs, "within"),
                        bar["strength"], n))
            if cls == "hidden":
                out.append((cls, "probe RMSE reduced >= 70 % (plain -> after)",
                            float(np.mean([r["probe_reduction"] >= cases_.PROBE_REDUCTION for r in rs])),
                            bar["probe_reduction"], n))
        elif cls == "outside":
            out.append((cls, "verdict unexplained or partly_explained",
                        float(np.mean([r["verdict"] in ("unexplained", "partly_explained") for r in rs])), bar["verdict"], n))
            out.append((cls, "no library candidate named with confidence > 0.5", _rate(rs, "no_library"),
                        bar["no_library"], n))
            out.append((cls, "true region among the top two", _rate(rs, "top2"), bar["region_top2"], n))
        else:
            out.append((cls, "verdict nothing_missing", float(np.mean([r["verdict"] == "nothing_missing" for r in rs])),
                        bar["nothing_missing"], n))
    return out


def _fmt(v, digits=3) -> str:
    try:
        v = float(v)
    except (TypeError, ValueError):
        return str(v) if v is not None else ""
    return "" if not np.isfinite(v) else f"{v:.{digits}g}"


def markdown(rows: list[dict], command: str, quick: bool) -> str:
    first = rows[0] if rows else {}
    verdict = lambda ok: "**pass**" if ok else "**FAIL**"
    md = ["# Diagnosis study" + (" (quick)" if quick else ""), "",
          f"Command: `{command}`. Truth on the `{first.get('truth_mesh', '?')}` mesh with half the time step, cast "
          "iron and steel perturbed by 2-4 % (conductivity, heat capacity, expansion), sensor noise 0.05 K, probe "
          "noise 0.05 um (laser triangulation and FBG gauges at their instruments' defaults, `twin list "
          "instruments`; interferometer readings 0.1 um), quantisation, 0.03 K sensor bias (`validate.synthetic`); diagnosing model on "
          f"`{first.get('model_mesh', '?')}` with its discretisation error estimated against "
          f"`{first.get('error_mesh', '?')}`. Candidates: every library effect the model lacks and every declared "
          "uncertain parameter of its effects; each material's expansion fitted within its band. Verdicts from "
          "the residual over noise and model error (`validate.verdict`, within = factor <= 3).", "",
          "## Rates per class against the issue's thresholds", "",
          "| class | criterion | rate | threshold | cases | |", "|---|---|---|---|---|---|"]
    for cls, what, rate, bar, n in class_rates(rows):
        md.append(f"| {cls} | {what} | {rate:.0%} | {bar:.0%} | {n} | {verdict(rate >= bar - 1e-9)} |")
    md += ["", "## Cases", "",
           "| class | case | scenario | verdict | top candidate (kind, confidence) | rank of expected | true | fitted | "
           "error | residual factor T / probe | probe RMSE plain -> after [um] | top regions | pass |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append(f"| {r['class']} | {r['case']} | {r['scenario']} | {r['verdict']} | {r['top']} ({r['top_kind']}, "
                  f"{_fmt(r['top_confidence'], 2)}) | {r['rank'] or ''} | {r['true']} | {r['fitted']} | "
                  f"{_fmt(100 * float(r['strength_error']), 2) + ' %' if _fmt(r['strength_error']) else ''} | "
                  f"{_fmt(r['factor_temperature'], 2)} / {_fmt(r['factor_probe'], 2)} | "
                  f"{_fmt(r['probe_rmse_uncalibrated_um'])} -> {_fmt(r['probe_rmse_after_um'])} | {r['regions']} | "
                  f"{verdict(r['pass'] in (True, 'True'))} |")
    md += ["", "## Why these cases", ""]
    seen = set()
    for c in all_cases(build_machine(first.get("machine", "cframe-vmc"))) if rows else []:
        ran = any(r["case"] == c.label and r["class"] == c.cls and str(r["scenario"]).startswith(c.scenario)
                  for r in rows)              # the scenario too: "(none)" runs on several (quick names add a suffix)
        if (c.cls, c.label, c.scenario) in seen or not ran:
            continue
        seen.add((c.cls, c.label, c.scenario))
        md.append(f"- **{c.cls}: {c.label}** ({c.scenario}): {c.why}")
    return "\n".join(md) + "\n"


def failure_analysis(rows: list[dict]) -> str:
    """Each failing case with the criteria it misses and the numbers behind them."""
    out = ["## Failure analysis", ""]
    for r in rows:
        if r["pass"] in (True, "True"):
            continue
        why = []
        cls = r["class"]
        if cls in ("hidden", "parameter", "pair"):
            if str(r["rank"]) != "1":
                why.append(f"ranked {r['rank'] or 'nowhere'} behind {r['top']} ({r['top_kind']})")
            if r["verdict"] not in ("explained", "partly_explained"):
                why.append(f"verdict {r['verdict']} (residual factor T {_fmt(r['factor_temperature'], 2)}, probe "
                           f"{_fmt(r['factor_probe'], 2)})")
            if not r["within"] in (True, "True"):
                why.append(f"strength off by {_fmt(100 * float(r['strength_error']), 2)} % ({r['fitted']} vs {r['true']})")
            if cls == "hidden" and not float(r["probe_reduction"]) >= cases_.PROBE_REDUCTION:
                why.append(f"probe RMSE reduced {_fmt(100 * float(r['probe_reduction']), 2)} %")
        elif cls == "outside":
            if r["verdict"] not in ("unexplained", "partly_explained"):
                why.append(f"verdict {r['verdict']}")
            if r.get("no_library") not in (True, "True"):
                why.append(f"library candidate {r['top']} named with confidence {_fmt(r['top_confidence'], 2)}")
            if r.get("top2") not in (True, "True"):
                why.append(f"true region {r['expected']} ranked {r['region_rank'] or 'outside the top 8'} "
                           f"(top: {r['regions']})")
        else:
            why.append(f"verdict {r['verdict']}: {r['message']}")
        out.append(f"- **{cls}: {r['case']}** on `{r['scenario']}`: " + "; ".join(why) + ".")
    if len(out) == 2:
        out.append("- none: every case passes.")
    return "\n".join(out) + "\n"


def _typed(row: dict) -> dict:
    out = dict(row)
    for k in ("rank", "region_rank"):
        out[k] = int(row[k]) if row.get(k) not in ("", None) else None
    for k, v in row.items():
        if v in ("True", "False"):
            out[k] = v == "True"
    return out


def _parser():
    from twin.cli.options import whole_number

    ap = cli_parser("python -m validate.studies.hidden_effect", __doc__)
    ap.add_argument("--machine", default="cframe-vmc", help="machine (default: %(default)s)")
    ap.add_argument("--classes", default=",".join(CLASSES), help=f"comma-separated classes (default: all: {', '.join(CLASSES)})")
    ap.add_argument("--effects", help="hidden class: comma-separated hidden effects (default: spindle_motor and every "
                                      "library effect the model lacks)")
    ap.add_argument("--cases", help="only the cases whose label contains one of these comma-separated texts "
                                    "(e.g. 'front_power x0.7,(none)'), to rerun a few")
    ap.add_argument("--scenarios", help="only the cases on these comma-separated scenarios (a scenario name's "
                                        "text, e.g. 'etve-day-night')")
    ap.add_argument("--quick", action="store_true", help="shortened spindle scenarios")
    ap.add_argument("-o", "--output", "--out", dest="out",
                    help="folder for hidden_effect.md/.csv (default: validate-out/hidden_effect/MACHINE)")
    ap.add_argument("--jobs", type=whole_number("processes", 1), default=1,
                    help="cases run in parallel processes (default 1)")
    ap.add_argument("--analyse", action="store_true", help="re-render hidden_effect.md from an existing hidden_effect.csv")
    ap.add_argument("--truth", default="fine", help="mesh resolution of the truth (default: %(default)s)")
    ap.add_argument("--model", default="default", help="mesh resolution of the diagnosing model (default: %(default)s)")
    ap.add_argument("--error-mesh", default="coarse", help="mesh of the model-error estimate, or 'none' (default: %(default)s)")
    return ap


def main(argv=None) -> int:
    """The study; bad options and files exit (SystemExit, code 2) with one line ``error: <source>:
    <field>: <message>``, before any case runs or any file is written."""
    ap = _parser()
    a = ap.parse_args(argv)
    try:
        return _analyse(a) if a.analyse else _study(a)
    except InputError as err:
        ap.exit(2, f"error: {err}\n")


def _analyse(a) -> int:
    """--analyse: hidden_effect.md re-rendered from the hidden_effect.csv beside it; it runs no
    case, so an option that chooses cases or meshes would be ignored: refused."""
    from twin.io.paths import input_file, output_file, read_text

    defaults = vars(_parser().parse_args([]))       # the parser's own, not a copy that could drift
    given = [k for k, v in defaults.items() if k not in ("machine", "out", "analyse") and getattr(a, k) != v]
    if given:
        raise InputError("command line", "--analyse", f"re-renders an existing table and runs no case: it takes "
                                                      f"-o and --machine only; leave out --{given[0].replace('_', '-')}")

    out = Path(a.out or f"validate-out/hidden_effect/{a.machine}")
    table = input_file(out / "hidden_effect.csv", "--output", "study table (hidden_effect.csv)")
    old = read_text(out / "hidden_effect.md", "--output", "study report (hidden_effect.md)")
    output_file(out / "hidden_effect.md", "--output")
    try:
        rows = [score(_typed(r)) for r in csv.DictReader(io.StringIO(read_text(table, "--output")))]
    except (KeyError, ValueError, TypeError) as err:
        raise InputError(str(table), "--output", f"not a table this study wrote ({type(err).__name__}: {err})") from None
    if not rows:
        raise InputError(str(table), "--output", "holds no case")
    cmd = old.split("Command: `", 1)[1].split("`", 1)[0] if "Command: `" in old else "?"
    text = markdown(rows, cmd, "(quick)" in old.splitlines()[0]) + "\n" + failure_analysis(rows)
    atomic_write_text(out / "hidden_effect.md", text)
    print(text.split("## Cases")[0])
    return 0


def _study(a) -> int:
    from validate.studies.common import check_output_folder

    if a.machine not in MACHINES:
        raise InputError("command line", "--machine", f"unknown machine {a.machine!r} (known: {', '.join(sorted(MACHINES))})")
    default_out = f"validate-out/hidden_effect/{a.machine}"
    out = check_output_folder(a.out or default_out, ("hidden_effect.csv", "hidden_effect.md"), field="--output",
                              default=default_out)
    machine = build_machine(a.machine)
    classes = comma_items(a.classes, "command line", "--classes", "class")
    unknown = [c for c in classes if c not in CLASSES]
    if unknown:
        raise InputError("command line", "--classes", f"unknown class {unknown[0]!r} (known: {', '.join(CLASSES)})")
    if not classes or len(set(classes)) < len(classes):
        raise InputError("command line", "--classes", "no class given" if not classes else
                         f"{', '.join(sorted({c for c in classes if classes.count(c) > 1}))} given more than once")
    hidden = comma_items(a.effects, "command line", "--effects", "effect") if a.effects is not None else None
    if hidden is not None:
        bad = [h for h in hidden if h not in EFFECTS]
        if bad or not hidden:
            raise InputError("command line", "--effects", f"unknown effects: {', '.join(bad)}" if bad else
                             "no effect given")
        twice = sorted({h for h in hidden if hidden.count(h) > 1})
        if twice:
            raise InputError("command line", "--effects", f"{', '.join(twice)} given more than once")
        if "hidden" not in classes:
            raise InputError("command line", "--effects", "names the hidden class's effects: add hidden to --classes")
        refused = [h for h in hidden if not EFFECTS[h].applies_to(with_feed_drives(machine))]
        if refused:
            raise InputError("command line", "--effects", f"effects that do not apply to {machine.name}: "
                                                          f"{', '.join(refused)}")
    sizes = machine.resolutions
    for opt in ("truth", "model", "error_mesh"):
        v = getattr(a, opt)
        if v not in sizes and not (opt == "error_mesh" and v == "none"):
            raise InputError("command line", f"--{opt.replace('_', '-')}",
                             f"unknown mesh resolution {v!r} (known: {', '.join(sizes)})")
    if a.error_mesh == a.model:
        raise InputError("command line", "--error-mesh", f"{a.error_mesh} is the model's own mesh: it must be another "
                                                         "resolution")
    if sizes[a.truth] > sizes[a.model]:
        raise InputError("command line", "--truth", f"{a.truth} is coarser than --model {a.model}: the truth must be at "
                                                    "least as fine")
    error = None if a.error_mesh == "none" else a.error_mesh
    plan = all_cases(machine, classes, hidden)
    for option, text, key in (("--cases", a.cases, lambda c: c.label), ("--scenarios", a.scenarios, lambda c: c.scenario)):
        if not text:
            continue
        wanted = comma_items(text, "command line", option, "text")
        unmatched = [w for w in wanted if not any(w in key(c) for c in plan)]
        if unmatched or not wanted:      # a text that matches nothing is a typo, even beside one that matches
            raise InputError("command line", option, f"no case of the classes {', '.join(classes)}"
                                                     f"{' on the cases chosen' if option == '--scenarios' and a.cases else ''}"
                                                     f" matches {', '.join(map(repr, unmatched or [text]))}")
        plan = [c for c in plan if any(w in key(c) for w in wanted)]
    work = [(c, a.quick, a.truth, a.model, error, machine.name) for c in plan]
    cmd = (f"python -m validate.studies.hidden_effect --machine {machine.name} --classes {','.join(classes)}"
           + (" --quick" if a.quick else "") + (f" --effects {a.effects}" if a.effects else "")
           + (f" --cases '{a.cases}'" if a.cases else "")
           + (f" --scenarios {a.scenarios}" if a.scenarios else "")
           + (f" --jobs {a.jobs}" if a.jobs > 1 else "")
           + "".join(f" --{o.replace('_', '-')} {v}" for o, v, d in (("truth", a.truth, "fine"), ("model", a.model, "default"),
                                                                       ("error_mesh", a.error_mesh, "coarse")) if v != d))
    t0 = time.perf_counter()
    rows: list[dict] = []

    def done(r: dict) -> None:   # the files after every case: a stopped run keeps what it finished
        r["machine"] = machine.name
        _say(r)
        r.pop("seconds", None)   # wall clock: printed, not written (the same inputs write the same files)
        rows.append(r)
        _write(out, rows, cmd, a.quick, len(work))

    if a.jobs > 1:
        from multiprocessing import Pool
        with Pool(a.jobs, maxtasksperchild=4) as pool:
            for r in pool.imap(_run_planned, work):
                done(r)
    else:
        for w in work:
            done(_run_planned(w))
    print(_write(out, rows, cmd, a.quick, len(work)).split("## Cases")[0])
    print(f"wall time {(time.perf_counter() - t0) / 60:.0f} min")
    return 0


def _write(out: Path, rows: list[dict], cmd: str, quick: bool, planned: int) -> str:
    """Write hidden_effect.csv and .md for the ``rows`` done so far (of ``planned``); the Markdown."""
    out.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(rows[0]), extrasaction="ignore")
    w.writeheader()
    w.writerows(rows)
    atomic_write_text(out / "hidden_effect.csv", buf.getvalue())
    text = markdown(rows, cmd, quick) + "\n" + failure_analysis(rows)
    if len(rows) < planned:
        text += f"\n{len(rows)} of {planned} cases done so far.\n"
    atomic_write_text(out / "hidden_effect.md", text)
    return text


def _say(r: dict) -> dict:
    print(f"{r['class']:<9} {r['case']:<44} {r['scenario']:<26} {r['verdict']:<16} top {r['top']:<36} "
          f"rank {r['rank']} err {_fmt(r['strength_error'], 2)} regions {r['regions']} "
          f"{'pass' if r['pass'] else 'FAIL'} ({r['seconds']:.0f} s)", flush=True)
    return r


if __name__ == "__main__":
    raise SystemExit(main())
