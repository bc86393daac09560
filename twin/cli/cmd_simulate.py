"""``twin simulate MACHINE SCENARIO -o OUT.nc [--field FILE] [model options]``."""

from __future__ import annotations

from pathlib import Path

from twin.cli.options import add_model_options
from twin.cli.progress import progress_bar
from twin.errors import InputError
from twin.io.atomic import atomic_write, check_writable


def add_parser(sub) -> None:
    p = sub.add_parser("simulate", help="simulate a scenario on a machine and write a NetCDF result")
    p.add_argument("machine")
    p.add_argument("scenario", help="a bundled scenario name or a path to a TOML file")
    p.add_argument("-o", "--output", required=True, help="result file (.nc)")
    p.add_argument("--field", metavar="FILE", help="also write the temperature field at the hottest moment (.vtu or .xdmf)")
    add_model_options(p)
    p.set_defaults(func=run)


def simulate_with_progress(machine: str, scenario: str, args):
    """``twin.api.simulate`` with the CLI's model options and a progress bar; (Dataset, RunResult)."""
    from twin.api import simulate

    return simulate(machine, scenario, args.effects, args.set, args.mesh, args.seed,
                    progress=progress_bar(f"{machine} / {Path(scenario).stem}"),
                    effects_file=getattr(args, "effects_file", None))


def run(args) -> int:
    from twin.io.results import write_netcdf

    out = Path(args.output)
    check_writable(out)
    if args.field:
        from twin.io.fields import SUFFIXES

        check_writable(Path(args.field))
        if Path(args.field).suffix not in SUFFIXES:
            raise InputError(args.field, "--field", f"unknown field format; use {' or '.join(SUFFIXES)}")
    ds, result = simulate_with_progress(args.machine, args.scenario, args)
    write_netcdf(ds, out)
    if args.field:
        from twin.io.fields import write_temperature_field

        field_path = Path(args.field)
        atomic_write(field_path, lambda tmp: write_temperature_field(result.mm, result.hottest_field, tmp,
                                                                     result.hottest_time))
        print(f"wrote {field_path}: temperature field at the hottest moment, t = {result.hottest_time / 60:.0f} min")
    peak = abs(ds.drift).max("time")
    print(f"wrote {out}: {len(ds.time)} samples, {result.mm.nnodes} nodes; peak |drift| "
          + ", ".join(f"{a} {float(peak.sel(axis=a)):.1f} um" for a in ds.axis.values))
    return 0
