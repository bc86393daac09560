"""``twin plot RESULT.nc -o PICTURE.png``."""

from __future__ import annotations

from twin.io.atomic import atomic_write
from twin.io.paths import Files


def add_parser(sub) -> None:
    p = sub.add_parser("plot", help="plot drift, tilts and temperatures of a result")
    p.add_argument("result")
    p.add_argument("-o", "--output", required=True, help="picture file (.png, or another format matplotlib writes)")
    p.set_defaults(func=run)


def run(args) -> int:
    from twin.io.measurement import read_checked_result
    from twin.plotting import check_plottable, picture_suffixes, plot_result

    files = Files()
    src = files.input(args.result, "result", "result file")
    out = files.output(args.output, "-o", picture_suffixes())
    ds = read_checked_result(src, "result")
    check_plottable(ds, str(src))
    atomic_write(out, lambda tmp: plot_result(ds, tmp), "-o")
    print(f"wrote {out}")
    return 0
