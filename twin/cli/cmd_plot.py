"""``twin plot RESULT.nc -o PICTURE.png``."""

from __future__ import annotations

from pathlib import Path

from twin.errors import InputError
from twin.io.atomic import atomic_write, check_writable


def add_parser(sub) -> None:
    p = sub.add_parser("plot", help="plot drift, tilts and temperatures of a result")
    p.add_argument("result")
    p.add_argument("-o", "--output", required=True, help="picture file (.png)")
    p.set_defaults(func=run)


def run(args) -> int:
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
