"""``twin frames RESULT.nc -o DIR [--camera NAME] [--every N] [--tiff] [--png] [--gif]``."""

from __future__ import annotations

from pathlib import Path

from twin.errors import InputError


def add_parser(sub) -> None:
    p = sub.add_parser("frames", help="export a result's thermal-camera frames (16-bit TIFF + JSON, PNG, GIF)")
    p.add_argument("result", help="a result file (.nc) of a run with a camera (twin simulate --camera ...)")
    p.add_argument("-o", "--output", required=True, help="output folder (created)")
    p.add_argument("--camera", help="which camera, by name (default: every camera of the result)")
    p.add_argument("--every", type=int, default=1, help="every N-th frame (default 1)")
    p.add_argument("--tiff", action="store_true", help="16-bit TIFFs in centikelvin with JSON sidecars")
    p.add_argument("--png", action="store_true", help="colour PNG frames")
    p.add_argument("--gif", action="store_true", help="an animated GIF")
    p.set_defaults(func=run)


def run(args) -> int:
    import xarray as xr

    from twin.io.thermography import camera_names, write_gif, write_png_frames, write_tiff_frames

    if args.every < 1:
        raise InputError("command line", "--every", f"must be a whole number >= 1, got {args.every}")
    path = Path(args.result)
    if not path.is_file():
        raise InputError(str(path), "result", "no such file")
    try:
        ds = xr.open_dataset(path)
    except (OSError, ValueError) as err:
        raise InputError(str(path), "result", f"cannot read it as NetCDF: {err}") from None
    with ds:
        known = camera_names(ds)
        if not known:
            raise InputError(str(path), "camera", "the result has no camera (simulate with --camera NAME)")
        chosen = [c for c in known if args.camera in (None, c[0])]
        if not chosen:
            raise InputError("command line", "--camera", f"no camera {args.camera!r} in {path}; "
                                                          f"known: {', '.join(n for n, _ in known)}")
        kinds = [k for k in ("tiff", "png", "gif") if getattr(args, k)] or ["tiff", "png", "gif"]
        out = Path(args.output)
        out.mkdir(parents=True, exist_ok=True)
        for name, suffix in chosen:
            folder = out / name if len(chosen) > 1 else out
            if "tiff" in kinds:
                n = len(write_tiff_frames(ds, folder / "tiff", suffix, args.every))
                print(f"wrote {n} 16-bit TIFFs (centikelvin) with JSON sidecars to {folder / 'tiff'}")
            if "png" in kinds:
                n = len(write_png_frames(ds, folder / "png", suffix, args.every))
                print(f"wrote {n} PNG frames to {folder / 'png'}")
            if "gif" in kinds:
                print(f"wrote {write_gif(ds, folder / f'{name}.gif', suffix, args.every)}")
    return 0
