"""``twin diagnose MEAS [MEAS ...]``: the verdict, the ranked candidates and, when something is
left unexplained, where on the machine; optionally add the top candidate and rerun
(:mod:`validate.apply`); registered with ``twin`` through the ``thermal_twin.commands`` entry point.
"""

from __future__ import annotations

import json

from twin import limits
from twin.cli.options import add_model_options
from twin.errors import InputError
from twin.fem.mesh import mesh_machine
from twin.io.atomic import atomic_write_text, output_folder
from twin.io.paths import Files
from validate.inputs import declare_inputs, load_measurements, measurement_labels, measurement_paths


def add_diagnose_parser(subparsers) -> None:
    """``twin diagnose MEAS [MEAS ...] [--machine NAME] [--scenario S] [--effects ..] [--set ..]
    [--effects-file FILE] [--mesh R] [--error-mesh R] [--json FILE] [--apply] [--report DIR]``."""
    p = subparsers.add_parser("diagnose", help="say whether and what the model lacks: a missing effect, a wrong "
                                               "parameter, or a cause outside the library and where it acts")
    p.add_argument("measurements", nargs="+", metavar="MEAS",
                   help="twin NetCDF results or CSV files with TOML column mappings; several are fitted together")
    p.add_argument("--mapping", help="TOML column mapping of a single CSV (default: the CSV's name with .toml)")
    p.add_argument("--machine", help="the measured machine (default: the one the measurements name)")
    p.add_argument("--scenario", help="drive the twin by this scenario instead of the measured inputs (one measurement)")
    add_model_options(p, mesh_default="coarse", mesh_help="mesh of the diagnosing model (coarse: it makes many runs)",
                      effects_help="the diagnosing model's effects: '+a,-b' edits the default set, 'a,b' replaces it",
                      seed=False)     # the diagnosing model reads true values: a noise seed would change nothing
    p.add_argument("--error-mesh", default="auto", choices=["auto", "none", "coarse", "default", "fine"],
                   help="mesh on which the baseline is rerun once to estimate the diagnosing model's discretisation "
                        "error per channel: a finer one estimates it, a coarser one usually overestimates it (default auto: the next "
                        "finer than --mesh, else the next coarser; none: no estimate)")
    p.add_argument("--no-parameters", action="store_true",
                   help="do not try the uncertain parameters of the model's own effects, only missing effects")
    p.add_argument("--json", metavar="FILE", help="write the verdict, candidates, nuisance and regions as JSON")
    p.add_argument("--apply", action="store_true", help="rerun with the top candidate at its fitted value")
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


def suggested_effect(region: dict) -> str:
    """A custom-effect TOML table for a localised region (``d.regions`` entry)."""
    kind = "heat_source" if region["kind"] == "volume" else "heat_flux"
    return (f'[effects.missing_heat]\nkind = "{kind}"\nregion = "{region["region"]}"\n'
            f'power = "{region["power_W"]:.3g} W"\nschedule = "{region["schedule"]}"\n')


def run_diagnose(args) -> int:
    """CLI body of ``twin diagnose``: prints the verdict and ranking (and before/after with --apply)."""
    from twin.cli.progress import progress_bar
    from validate.apply import apply_top, format_before_after
    from validate.diagnose import diagnose_many, diagnosis_json, format_diagnosis

    files = Files()
    declare_inputs(files, args)
    if args.json:
        files.output(args.json, "--json", (".json",))
    if args.report:
        files.folder(args.report, "--report", ("index.html",))
    runs, machine, spec, custom = load_measurements(args)
    err_mesh = error_resolution(args, machine)
    mm = mesh_machine(machine, args.mesh)
    sizes = [mm.nheat] + ([mesh_machine(machine, err_mesh).nheat] if err_mesh else [])
    for _, _, sc in runs:
        for n in sizes:
            limits.check_run_size(sc, n)
    paths = measurement_paths(args)
    typed = dict(zip(measurement_labels(paths), paths))   # label -> the file as typed
    try:
        d = diagnose_many(runs, machine, spec, mm=mm, error_resolution=err_mesh, parameters=not args.no_parameters,
                          progress=progress_bar(f"diagnose {machine.name}", "fit"), custom=custom)
    except InputError as err:    # the library names a measurement by its label: name the file as typed
        raise InputError(typed.get(err.source, err.source), err.field, err.message) from None
    except ValueError as err:
        raise InputError(" ".join(typed.values()), "time", str(err)) from None
    print(format_diagnosis(d))
    after = calibrated = None
    named = d.verdict in ("explained", "partly_explained")
    if (args.apply or args.report) and named:
        after, calibrated, extra = apply_top(d)
        if args.apply:
            extra = [args.effects_file if x == "FILE" else x for x in extra]
            print(f"\nApplied {d.candidates[0]['effect']} ({' '.join(extra)}):")
            print(format_before_after(d, after, calibrated))
    elif args.apply:
        print(f"\nnothing to apply: the verdict is {d.verdict}")
        if d.regions:
            print("the best region as a custom effect, to add with --effects-file (twin.effects.custom):\n"
                  + suggested_effect(d.regions[0]))
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
