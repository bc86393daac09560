"""``twin diagnose MEAS``: rank the missing effects, optionally add the top one and rerun
(:mod:`validate.apply`); registered with ``twin`` through the ``thermal_twin.commands`` entry point.
"""

from __future__ import annotations

import json

import numpy as np

from twin import limits
from twin.cli.options import add_measurement_options, add_model_options
from twin.errors import InputError
from twin.fem.mesh import mesh_machine
from twin.io.atomic import atomic_write_text, output_folder
from twin.io.paths import Files
from validate.inputs import declare_inputs, load_inputs


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
    from validate.apply import apply_top, format_before_after
    from validate.diagnose import diagnose, diagnosis_json, format_diagnosis

    from twin.cli.progress import progress_bar

    files = Files()
    declare_inputs(files, args)
    if args.json:
        files.output(args.json, "--json", (".json",))
    if args.report:
        files.folder(args.report, "--report", ("index.html",))
    meas, machine, sc, spec = load_inputs(args)
    error_mesh = error_resolution(args, machine)
    mm = mesh_machine(machine, args.mesh)
    limits.check_run_size(sc, mm.nheat)
    if error_mesh:
        limits.check_run_size(sc, mesh_machine(machine, error_mesh).nheat)
    try:
        d = diagnose(meas, machine, sc, spec, mm=mm, error_resolution=error_mesh,
                     progress=progress_bar(f"diagnose {machine.name}", "fit"))
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
        try:
            text = json.dumps(diagnosis_json(d), indent=2, allow_nan=False)
        except ValueError:
            raise InputError(args.json, "--json", "the diagnosis holds NaN or infinite values; not written") from None
        atomic_write_text(args.json, text, "--json")
    if args.report:
        from validate.report import write_report

        with output_folder(args.report):
            print(f"report: {write_report(d, machine, args.report, after, calibrated=calibrated)}")
    return 0
