"""``twin diagnose MEAS``: rank the missing effects, optionally add the top one and rerun.

The lead wires :func:`add_diagnose_parser` / :func:`run_diagnose` into ``twin/cli.py``.
"""

from __future__ import annotations

import json

import numpy as np

from twin.io.atomic import atomic_write_text
from twin.cli.options import add_measurement_options, add_model_options
from twin.errors import InputError
from twin.fem.mesh import mesh_machine


def add_diagnose_parser(subparsers) -> None:
    """``twin diagnose MEAS --machine NAME [--scenario S] [--effects ..] [--set ..] [--mesh R]
    [--json FILE] [--apply] [--report DIR]``."""
    p = subparsers.add_parser("diagnose", help="rank the physical effects the model lacks by how much residual each explains")
    add_measurement_options(p)
    add_model_options(p, mesh_default="coarse", mesh_help="mesh of the diagnosing model (coarse: it makes many runs)",
                      effects_help="the diagnosing model's effects: '+a,-b' edits the default set, 'a,b' replaces it")
    p.add_argument("--error-mesh", default="auto", choices=["auto", "none", "coarse", "default", "fine"],
                   help="mesh on which the baseline is rerun once to estimate the diagnosing model's discretisation "
                        "error per channel: a finer one estimates it, a coarser one bounds it (the difference to the "
                        "next coarser level) (default auto: the next finer than --mesh, else the next coarser; "
                        "none: no estimate)")
    p.add_argument("--json", metavar="FILE", help="write baseline and ranked candidates as JSON")
    p.add_argument("--apply", action="store_true", help="rerun with the top candidate at its fitted strength")
    p.add_argument("--report", metavar="DIR", help="write an HTML report with figures into DIR")
    p.set_defaults(func=run_diagnose)


def load_inputs(args):
    """(measurement Dataset, machine, Scenario, ModelSpec) from the parsed arguments."""
    from twin.api import machine_by_name
    from twin.model import model_spec
    from twin.scenario import load_scenario
    from twin.io.measured_inputs import scenario_from_measurement
    from twin.io.measurement import read_measurement

    meas = read_measurement(args.measurement, getattr(args, "mapping", None), args.machine)
    machine = machine_by_name(args.machine)
    if args.mesh not in machine.resolutions:
        raise InputError("command line", "--mesh", f"unknown resolution {args.mesh!r}")
    sc = load_scenario(args.scenario) if args.scenario else scenario_from_measurement(meas)
    return meas, machine, sc, model_spec(machine, args.effects, args.set)


def apply_top(d, machine, scenario, mm=None):
    """Rerun the twin with the top candidate(s) at the fitted strength.

    Returns (model after, model after with the material expansion fitted, the equivalent
    ``--effects``/``--set`` arguments); model arrays are (nt, nch) on the measurement's grid. The
    second is the same rerun with each material's expansion coefficient scaled by the nuisance
    the diagnosis fitted together with the candidate (None when it fitted none), from the same
    run's exact expansion sensitivities; the first is what the printed arguments reproduce."""
    from validate.diagnose import _interpolator
    from validate.signatures import Engine, with_effect

    top = d.candidates[0]
    spec = d.spec
    for eff, vals in top["values_si"].items():
        spec = with_effect(spec, eff, vals)
    fit = next((f for f in d.fits if set(f.effects) == set(top["values_si"])), None)
    coef = d.expansion_fit(fit.response) if d.expansion_fit is not None and fit is not None and d.expansion else {}
    engine = Engine(machine, scenario, mm=mm, sensors=d.sensor_points)
    observed, responses = engine.observe_with_expansion(spec, list(coef))
    interp = _interpolator(engine.times, d.times)
    after = interp(observed)
    # drift is linear in each alpha for the rerun's temperatures: the calibrated rerun is exact
    calibrated = after + sum(c * interp(r) for c, r in zip(coef.values(), responses)) if coef else None
    args = ["--effects", ",".join(f"+{e}" for e in top["values_si"])]
    for eff, vals in top["parameters"].items():
        args += [f"--set {eff}.{p}={v.replace(' ', '')}" for p, v in vals.items()]
    return after, calibrated, args


def format_before_after(d, after: np.ndarray, calibrated: np.ndarray | None = None) -> str:
    """Per-channel RMSE before and after applying the top candidate; with ``calibrated`` (the
    rerun with the fitted material expansion) two more columns: the baseline and the rerun, each
    with the expansion the diagnosis fitted."""
    from validate.diagnose import UNITS
    rms = lambda model: np.sqrt(np.mean((d.measured - model) ** 2, axis=0))
    rms_after = rms(after)
    head = f"{'channel':<32} {'unit':>4} {'before':>9} {'after':>9} {'change':>8}"
    extra = calibrated is not None and d.calibrated_rmse is not None
    if extra:
        head += f" {'before+a':>9} {'after+a':>9} {'change':>8}"
        rms_cal = rms(calibrated)
    lines = [head]
    for i, (c, g, b, a) in enumerate(zip(d.channels, d.groups, d.baseline_rmse, rms_after)):
        line = f"{c:<32} {UNITS[g]:>4} {b:>9.4g} {a:>9.4g} {(a / b - 1) if b else 0:>+8.0%}"
        if extra:
            bc, ac = d.calibrated_rmse[i], rms_cal[i]
            line += f" {bc:>9.4g} {ac:>9.4g} {(ac / bc - 1) if bc else 0:>+8.0%}"
        lines.append(line)
    if extra:
        lines.append("+a: with the thermal expansion of each material fitted as the diagnosis did ("
                     + ", ".join(f"{m} {c:+.1%}" for m, c in d.expansion.items()) + " for the baseline)")
    return "\n".join(lines)


def error_resolution(args, machine) -> str | None:
    """The ``--error-mesh`` choice resolved against the machine (None: no estimate)."""
    from validate.diagnose import coarser_resolution, finer_resolution
    choice = getattr(args, "error_mesh", "auto")
    if choice == "none":
        return None
    if choice == "auto":
        return finer_resolution(machine, args.mesh) or coarser_resolution(machine, args.mesh)
    if choice not in machine.resolutions or choice == args.mesh:
        raise InputError("command line", "--error-mesh", f"{choice!r} is not another resolution than --mesh "
                         f"{args.mesh!r} (known: {', '.join(machine.resolutions)})")
    return choice


def run_diagnose(args) -> int:
    """CLI body of ``twin diagnose``: prints the ranking (and before/after with --apply)."""
    from validate.diagnose import diagnose, diagnosis_json, format_diagnosis

    meas, machine, sc, spec = load_inputs(args)
    mm = mesh_machine(machine, args.mesh)
    try:
        d = diagnose(meas, machine, sc, spec, mm=mm, error_resolution=error_resolution(args, machine))
    except ValueError as err:
        if isinstance(err, InputError):
            raise
        raise InputError(args.measurement, "time", str(err)) from None
    print(format_diagnosis(d))
    after = calibrated = None
    if args.apply or args.report:
        if not d.candidates:
            print("nothing to apply: no candidate effects")
        else:
            after, calibrated, extra = apply_top(d, machine, sc, mm)
            if args.apply:
                print(f"\nApplied {d.candidates[0]['effect']} ({' '.join(extra)}):")
                print(format_before_after(d, after, calibrated))
    if args.json:
        atomic_write_text(args.json, json.dumps(diagnosis_json(d), indent=2))
    if args.report:
        from validate.report import write_report
        print(f"report: {write_report(d, machine, args.report, after, calibrated=calibrated)}")
    return 0
