"""The ``twin`` command line: list, simulate, plot, demo, learn (and the validation commands).

Bad input prints one line ``error: <file>: <field>: <message>`` on stderr and exits with code 2;
no partial output file is left behind (results are written to a temporary file, then renamed).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from twin.atomic import atomic_write, check_writable
from twin.cli_options import add_model_options
from twin.errors import InputError


def _progress_bar(label: str):
    from tqdm import tqdm

    bar = {"tqdm": None}

    def update(done: int, total: int):
        if bar["tqdm"] is None:
            bar["tqdm"] = tqdm(total=total, desc=label, unit="step", leave=False, file=sys.stderr,
                               disable=not sys.stderr.isatty())
        bar["tqdm"].update(done - bar["tqdm"].n)
        if done >= total:
            bar["tqdm"].close()

    return update


def cmd_list(args) -> int:
    from geometries import MACHINES, build_machine
    from twin.effects import DEFAULT_EFFECTS, EFFECTS
    from twin.instruments import INSTRUMENTS
    from twin.scenario import available, load_scenario

    if args.what == "machines":
        for name in sorted(MACHINES):
            m = build_machine(name)
            print(f"{name}: {m.description}\n  parts: {', '.join(p.name for p in m.parts)}\n"
                  f"  mesh resolutions: {', '.join(f'{k} ({v * 1e3:g} mm)' for k, v in m.resolutions.items())}")
    elif args.what == "scenarios":
        for name in available():
            sc = load_scenario(name)
            print(f"{name}: {sc.duration / 60:g} min, sample interval {sc.sample_interval:g} s\n  {sc.description}")
    elif args.what == "effects":
        for name in sorted(EFFECTS):
            e = EFFECTS[name]
            tag = " (default)" if name in DEFAULT_EFFECTS else ""
            print(f"{name}{tag}: {e.summary}\n  reference: {e.reference}")
            for p in e.parameters:
                print(f"    {p.describe()}")
    else:
        for name, params in INSTRUMENTS.items():
            print(name)
            for p in params:
                print(f"    {p.describe()}")
    return 0


def _simulate(machine: str, scenario: str, args):
    from twin.api import simulate

    return simulate(machine, scenario, args.effects, args.set, args.mesh, args.seed,
                    progress=_progress_bar(f"{machine} / {Path(scenario).stem}"))


def cmd_simulate(args) -> int:
    from twin.results import write_netcdf

    out = Path(args.output)
    check_writable(out)
    if args.field:
        from twin.fields import SUFFIXES

        check_writable(Path(args.field))
        if Path(args.field).suffix not in SUFFIXES:
            raise InputError(args.field, "--field", f"unknown field format; use {' or '.join(SUFFIXES)}")
    ds, result = _simulate(args.machine, args.scenario, args)
    write_netcdf(ds, out)
    if args.field:
        from twin.fields import write_temperature_field

        field_path = Path(args.field)
        atomic_write(field_path, lambda tmp: write_temperature_field(result.mm, result.hottest_field, tmp, result.hottest_time))
        print(f"wrote {field_path}: temperature field at the hottest moment, t = {result.hottest_time / 60:.0f} min")
    peak = abs(ds.drift).max("time")
    print(f"wrote {out}: {len(ds.time)} samples, {result.mm.nnodes} nodes; peak |drift| "
          + ", ".join(f"{a} {float(peak.sel(axis=a)):.1f} um" for a in ds.axis.values))
    return 0


def cmd_plot(args) -> int:
    import xarray as xr

    from twin.plotting import plot_result

    src, out = Path(args.result), Path(args.output)
    if not src.exists():
        raise InputError(str(src), "file", "no such result file")
    check_writable(out)
    try:
        ds = xr.load_dataset(src)
    except Exception as err:  # noqa: BLE001 - any reader failure is a bad file for the user
        raise InputError(str(src), "file", f"not a readable NetCDF result ({type(err).__name__})") from None
    missing = [v for v in ("drift", "tilt", "temperature", "probe_drift", "spindle_speed") if v not in ds]
    if missing:
        raise InputError(str(src), missing[0], "missing variable; is this a twin result?")
    atomic_write(out, lambda tmp: plot_result(ds, tmp))
    print(f"wrote {out}")
    return 0


def cmd_demo(args) -> int:
    from twin.plotting import plot_field_3d, plot_result
    from twin.results import write_netcdf

    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    machine, scenario = "cframe-vmc", "spindle-heat-cool-9000"
    print(f"demo: {machine} runs {scenario} (9000 rpm for 120 min, then 70 min stopped), mesh {args.mesh}")
    ds, result = _simulate(machine, scenario, args)
    write_netcdf(ds, out / "spindle-heat-cool-9000.nc")
    atomic_write(out / "drift.png", lambda tmp: plot_result(ds, tmp))
    hot = result.hottest_time / 60
    atomic_write(out / "temperature-3d.png",
            lambda tmp: plot_field_3d(result.mm, result.hottest_field, tmp, f"temperature at the hottest moment, t = {hot:.0f} min"))
    d = ds.drift
    for axis in ("X", "Y", "Z"):
        s = d.sel(axis=axis).values
        i = abs(s).argmax()
        print(f"  {axis} drift: peak {s[i]:+.1f} um at {ds.time.values[i] / 60:.0f} min, "
              f"{s[720] if len(s) > 720 else s[-1]:+.1f} um at 120 min, {s[-1]:+.1f} um at the end")
    rise = (ds.temperature_true.max("time") - ds.temperature_true.isel(time=0)).to_series().sort_values(ascending=False)
    print("  hottest sensors: " + ", ".join(f"{k} +{v:.1f} K" for k, v in rise.head(4).items()))
    print(f"wrote {out}/spindle-heat-cool-9000.nc, {out}/drift.png, {out}/temperature-3d.png")
    if not getattr(args, "no_story", False):
        from validate.demo_story import run_story

        run_story(out, args.mesh, args.seed, print)
    return 0


class _Parser(argparse.ArgumentParser):
    """Usage errors as one line ``error: command line: ...`` and exit code 2, like bad input."""

    def error(self, message):
        self.exit(2, f"error: command line: {self.prog}: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="twin", description="thermal-twin: digital twin of CNC machine-tool thermal errors")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("list", help="list machines, scenarios, effects or instruments")
    p.add_argument("what", choices=["machines", "scenarios", "effects", "instruments"])
    p.set_defaults(func=cmd_list)

    p = sub.add_parser("simulate", help="simulate a scenario on a machine and write a NetCDF result")
    p.add_argument("machine")
    p.add_argument("scenario", help="a bundled scenario name or a path to a TOML file")
    p.add_argument("-o", "--output", required=True, help="result file (.nc)")
    p.add_argument("--field", metavar="FILE", help="also write the temperature field at the hottest moment (.vtu or .xdmf)")
    add_model_options(p)
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("plot", help="plot drift, tilts and temperatures of a result")
    p.add_argument("result")
    p.add_argument("-o", "--output", required=True, help="picture file (.png)")
    p.set_defaults(func=cmd_plot)

    p = sub.add_parser("demo", help="the seeds' spindle test on the C-frame VMC, written to demo-out/")
    p.add_argument("-o", "--output", default="demo-out", help="output folder (default demo-out)")
    p.add_argument("--no-story", action="store_true",
                   help="only the spindle test: skip the measurement / compare / diagnose / report story "
                        "(which always uses the default effects)")
    add_model_options(p)
    p.set_defaults(func=cmd_demo)

    from learners.cli import add_learn_parser

    add_learn_parser(sub)
    from validate.compare import add_compare_parser
    from validate.diagnose_cli import add_diagnose_parser

    add_compare_parser(sub)
    add_diagnose_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exit_:
        return int(exit_.code or 0)
    try:
        return int(args.func(args) or 0)
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
