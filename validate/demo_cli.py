"""``twin demo``: the seeds' spindle test on the C-frame VMC, then the story of holding the twin
against a generated measurement (:mod:`validate.demo_story`), written to ``demo-out/``."""

from __future__ import annotations

from pathlib import Path

from twin.cli.options import add_model_options
from twin.cli.cmd_simulate import simulate_with_progress
from twin.io.atomic import atomic_write, output_folder
from twin.io.paths import Files

MACHINE, SCENARIO = "cframe-vmc", "spindle-heat-cool-9000"
RUN_FILES = (f"{SCENARIO}.nc", "drift.png", "temperature-3d.png")
STORY_FILES = ("measurement/spindle-test.csv", "measurement/spindle-test.toml", "report/index.html",
               "report/diagnosis.json")


def add_demo_parser(sub) -> None:
    p = sub.add_parser("demo", help="the seeds' spindle test on the C-frame VMC, written to demo-out/")
    p.add_argument("-o", "--output", default="demo-out", help="output folder (default demo-out)")
    p.add_argument("--no-story", action="store_true",
                   help="only the spindle test: skip the measurement / compare / diagnose / report story "
                        "(which always uses the default effects)")
    add_model_options(p)
    p.set_defaults(func=run_demo)


def run_demo(args) -> int:
    from twin.api import machine_by_name, model_from_options
    from twin.cli.options import declare_effects_file

    # bad --effects / --set / --effects-file: before any folder, as twin simulate checks them
    model_from_options(machine_by_name(MACHINE), args.effects, args.set, getattr(args, "effects_file", None))
    files = Files()
    if getattr(args, "effects_file", None):
        declare_effects_file(files, args.effects_file)     # never replaced by what the demo writes
    out = files.folder(args.output, "-o", RUN_FILES + (() if args.no_story else STORY_FILES))
    with output_folder(out):
        _run_demo(out, args)
    return 0


def _run_demo(out: Path, args) -> None:
    from twin.io.results import write_netcdf
    from twin.plotting import plot_field_3d, plot_result

    print(f"demo: {MACHINE} runs {SCENARIO} (9000 rpm for 120 min, then 70 min stopped), mesh {args.mesh}")
    ds, result = simulate_with_progress(MACHINE, SCENARIO, args)
    write_netcdf(ds, out / f"{SCENARIO}.nc")
    atomic_write(out / "drift.png", lambda tmp: plot_result(ds, tmp))
    hot = result.hottest_time / 60
    atomic_write(out / "temperature-3d.png",
                 lambda tmp: plot_field_3d(result.mm, result.hottest_field, tmp,
                                           f"temperature at the hottest moment, t = {hot:.0f} min"))
    d = ds.drift
    for axis in ("X", "Y", "Z"):
        s = d.sel(axis=axis).values
        i = abs(s).argmax()
        print(f"  {axis} drift: peak {s[i]:+.1f} um at {ds.time.values[i] / 60:.0f} min, "
              f"{s[720] if len(s) > 720 else s[-1]:+.1f} um at 120 min, {s[-1]:+.1f} um at the end")
    rise = (ds.temperature_true.max("time") - ds.temperature_true.isel(time=0)).to_series().sort_values(ascending=False)
    print("  hottest sensors: " + ", ".join(f"{k} +{v:.1f} K" for k, v in rise.head(4).items()))
    print(f"wrote {out}/{SCENARIO}.nc, {out}/drift.png, {out}/temperature-3d.png")
    if not args.no_story:
        from validate.demo_story import run_story

        run_story(out, args.mesh, args.seed, print)
