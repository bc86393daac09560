"""``twin diagnose MEAS``: rank the missing effects, optionally add the top one and rerun.

The lead wires :func:`add_diagnose_parser` / :func:`run_diagnose` into ``twin/cli.py``.
"""

from __future__ import annotations

import json

import numpy as np

from twin.atomic import atomic_write_text
from twin.cli_options import add_measurement_options, add_model_options
from twin.errors import InputError


def add_diagnose_parser(subparsers) -> None:
    """``twin diagnose MEAS --machine NAME [--scenario S] [--effects ..] [--set ..] [--mesh R]
    [--json FILE] [--apply] [--report DIR]``."""
    p = subparsers.add_parser("diagnose", help="rank the physical effects the model lacks by how much residual each explains")
    add_measurement_options(p)
    add_model_options(p, mesh_default="coarse", mesh_help="mesh of the diagnosing model (coarse: it makes many runs)",
                      effects_help="the diagnosing model's effects: '+a,-b' edits the default set, 'a,b' replaces it")
    p.add_argument("--error-mesh", default="auto", choices=["auto", "none", "coarse", "default", "fine"],
                   help="mesh on which the baseline is rerun once to estimate the diagnosing model's discretisation "
                        "error per channel (default auto: the next finer than --mesh; none: no estimate)")
    p.add_argument("--json", metavar="FILE", help="write baseline and ranked candidates as JSON")
    p.add_argument("--apply", action="store_true", help="rerun with the top candidate at its fitted strength")
    p.add_argument("--report", metavar="DIR", help="write an HTML report with figures into DIR")
    p.set_defaults(func=run_diagnose)


def load_inputs(args):
    """(measurement Dataset, machine, Scenario, ModelSpec) from the parsed arguments."""
    from twin.api import machine_by_name, model_spec
    from twin.scenario import load_scenario
    from validate.measurement import read_measurement, scenario_from_measurement

    meas = read_measurement(args.measurement, getattr(args, "mapping", None), args.machine)
    machine = machine_by_name(args.machine)
    if args.mesh not in machine.resolutions:
        raise InputError("command line", "--mesh", f"unknown resolution {args.mesh!r}")
    sc = load_scenario(args.scenario) if args.scenario else scenario_from_measurement(meas)
    return meas, machine, sc, model_spec(args.effects, args.set)


def apply_top(d, machine, scenario, mm=None):
    """Rerun with the top candidate(s) at the fitted strength: returns (model after (nt, nch),
    the equivalent ``--effects``/``--set`` arguments)."""
    from validate.diagnose import _interpolator
    from validate.signatures import Engine, with_effect

    top = d.candidates[0]
    spec = d.spec
    for eff, vals in top["values_si"].items():
        spec = with_effect(spec, eff, vals)
    engine = Engine(machine, scenario, mm=mm, sensors=d.sensor_points)
    after = _interpolator(engine.times, d.times)(engine.observe(spec))
    args = ["--effects", ",".join(f"+{e}" for e in top["values_si"])]
    for eff, vals in top["parameters"].items():
        args += [f"--set {eff}.{p}={v.replace(' ', '')}" for p, v in vals.items()]
    return after, args


def format_before_after(d, after: np.ndarray) -> str:
    """Per-channel RMSE before and after applying the top candidate."""
    from validate.diagnose import UNITS
    rms_after = np.sqrt(np.mean((d.measured - after) ** 2, axis=0))
    lines = [f"{'channel':<32} {'unit':>4} {'before':>9} {'after':>9} {'change':>8}"]
    for c, g, b, a in zip(d.channels, d.groups, d.baseline_rmse, rms_after):
        lines.append(f"{c:<32} {UNITS[g]:>4} {b:>9.4g} {a:>9.4g} {(a / b - 1) if b else 0:>+8.0%}")
    return "\n".join(lines)


def error_resolution(args, machine) -> str | None:
    """The ``--error-mesh`` choice resolved against the machine (None: no estimate)."""
    from validate.diagnose import finer_resolution
    choice = getattr(args, "error_mesh", "auto")
    if choice == "none":
        return None
    if choice == "auto":
        return finer_resolution(machine, args.mesh)
    if choice not in machine.resolutions or machine.resolutions[choice] >= machine.resolutions[args.mesh]:
        raise InputError("command line", "--error-mesh", f"{choice!r} is not finer than --mesh {args.mesh!r}")
    return choice


def run_diagnose(args) -> int:
    """CLI body of ``twin diagnose``: prints the ranking (and before/after with --apply)."""
    from validate.diagnose import diagnose, diagnosis_json, format_diagnosis

    meas, machine, sc, spec = load_inputs(args)
    mm = machine.mesh(args.mesh)
    try:
        d = diagnose(meas, machine, sc, spec, mm=mm, error_resolution=error_resolution(args, machine))
    except ValueError as err:
        if isinstance(err, InputError):
            raise
        raise InputError(args.measurement, "time", str(err)) from None
    print(format_diagnosis(d))
    after = None
    if args.apply or args.report:
        if not d.candidates:
            print("nothing to apply: no candidate effects")
        else:
            after, extra = apply_top(d, machine, sc, mm)
            if args.apply:
                print(f"\nApplied {d.candidates[0]['effect']} ({' '.join(extra)}):")
                print(format_before_after(d, after))
    if args.json:
        atomic_write_text(args.json, json.dumps(diagnosis_json(d), indent=2))
    if args.report:
        from validate.report import write_report
        print(f"report: {write_report(d, machine, args.report, after)}")
    return 0
