"""``twin plot RESULT.nc -o PICTURE.png``."""

from __future__ import annotations

from twin.errors import InputError
from twin.io.atomic import atomic_write
from twin.io.paths import Files

NEEDED = ("drift", "temperature", "temperature_true", "spindle_speed", "ambient_temperature")
# the test bar's instruments: the ISO 230-3 probes, or (a machine without them) laser triangulation
PROBES, LASERS = ("tilt", "probe_drift"), ("laser", "laser_tilt")


def add_parser(sub) -> None:
    p = sub.add_parser("plot", help="plot drift, tilts and temperatures of a result")
    p.add_argument("result")
    p.add_argument("-o", "--output", required=True, help="picture file (.png, or another format matplotlib writes)")
    p.set_defaults(func=run)


def run(args) -> int:
    from twin.io.results import read_result
    from twin.plotting import picture_suffixes, plot_result

    files = Files()
    src = files.input(args.result, "result", "result file")
    out = files.output(args.output, "-o", picture_suffixes())
    ds = read_result(src, "result", NEEDED)
    missing = [v for v in (LASERS if "laser" in ds else PROBES) if v not in ds]
    if missing:
        raise InputError(str(src), missing[0], "missing variable; is this a twin result?")
    atomic_write(out, lambda tmp: plot_result(ds, tmp), "-o")
    print(f"wrote {out}")
    return 0
