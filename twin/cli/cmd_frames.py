"""``twin frames RESULT.nc -o DIR [--camera NAME] [--every N] [--tiff] [--png] [--gif]``.

Before anything is written, the result is checked (a NetCDF file with well-formed camera
attributes and finite frames, :mod:`twin.io.thermography`) and the output folder and every file
the export makes in it are declared (:class:`twin.io.paths.Files`): the folder is a folder, or
can be made in an existing one; nothing in it is the result or a non-regular file; each file is
written atomically (:mod:`twin.io.atomic`).
"""

from __future__ import annotations

import re
from pathlib import Path

from twin.errors import InputError


def add_parser(sub) -> None:
    p = sub.add_parser("frames", help="export a result's thermal-camera frames (16-bit TIFF + JSON, PNG, GIF)")
    p.add_argument("result", help="a result file (.nc) of a run with a camera (twin simulate --camera ...)")
    p.add_argument("-o", "--output", required=True, metavar="DIR",
                   help="output folder (created if missing; its parent folder must exist)")
    p.add_argument("--camera", help="which camera, by name (default: every camera of the result)")
    p.add_argument("--every", type=int, default=1, help="every N-th frame (default 1)")
    p.add_argument("--tiff", action="store_true", help="16-bit TIFFs in centikelvin with JSON sidecars")
    p.add_argument("--png", action="store_true", help="colour PNG frames")
    p.add_argument("--gif", action="store_true", help="an animated GIF")
    p.set_defaults(func=run)


def open_result(path: Path, field: str = "result"):
    """The NetCDF result ``path`` opened lazily (frames are read one by one), each variable the
    twin writes in the twin's unit (:func:`twin.io.results.check_result_units`: a thermogram in K
    exported as degC would be 273 K off); anything xarray cannot open is one :class:`InputError`."""
    import xarray as xr

    from twin.io.results import check_result_units

    try:
        ds = xr.open_dataset(path)
    except Exception:  # noqa: BLE001 - any reader failure is a bad file for the user
        raise InputError(str(path), field, "not a NetCDF result file") from None
    try:
        check_result_units(ds, str(path))
    except InputError:
        ds.close()
        raise
    return ds


def declare_output(files, output: str, layout: list[str], field: str = "-o", cameras: dict | None = None) -> Path:
    """Declare the output folder and the files ``layout`` (relative paths) to ``files``. The
    first file of each kind in each subfolder is declared as any output (which checks the
    subfolder, the suffix and the clashes with the inputs); declaring thousands of frames that
    way would take minutes, so the rest are checked for clashes without being recorded
    (:meth:`twin.io.paths.Files.check_output`) and, where they exist already (a rerun), checked
    as outputs. A subfolder that is in the way (a file, a link to nothing) is refused as well, and
    so is an earlier export of another camera that this one would replace file for file
    (``cameras``: each camera's folder prefix, ``""`` or ``"NAME/"``, to its name)."""
    from twin.io.paths import output_file
    from twin.io.thermography import exported_camera

    firsts: dict[tuple[str, str], str] = {}
    for rel in layout:
        firsts.setdefault((str(Path(rel).parent), Path(rel).suffix), rel)
    out = files.folder(output, field, tuple(firsts.values()))
    for sub in sorted({p for rel in layout for p in Path(rel).parents if str(p) != "."}, key=lambda p: len(p.parts)):
        path = out / sub
        if (path.is_symlink() or path.exists()) and not path.is_dir():
            raise InputError(str(path), field, "is in the way: the frames go in a folder of that name")
    stale = earlier_frames(out, layout)
    if stale:
        raise InputError(str(out / stale[0]), field, f"the folder holds {len(stale)} frame file(s) of another export "
                                                     "(another camera, --every or kind) that this one would not "
                                                     "replace, so the two would mix: export into an empty folder "
                                                     "(or, if the other export left out a camera, every camera at "
                                                     "once with the same --every)")
    for prefix, name in (cameras or {}).items():
        for rel in (f"{prefix}tiff/frame_00000.json", f"{prefix}png/frame_00000.png"):
            other = exported_camera(out / rel) if rel in layout and (out / rel).is_file() else None
            if other is not None and other != name:
                raise InputError(str(out / rel), field, f"the folder holds an export of camera {other!r} that this "
                                                        f"export of {name!r} would replace: export into another "
                                                        "folder, or every camera at once")
    chosen = set(firsts.values())
    for rel in layout:
        if rel in chosen:
            continue
        path = out / rel
        files.check_output(path, field)
        if path.is_symlink() or path.exists():
            output_file(path, field)
    return out


# what an export writes, relative to its folder: [NAME/]tiff/frame_N.tiff|json, [NAME/]png/frame_N.png, [NAME/]NAME.gif
_EXPORTED = re.compile(r"^(?:[^/]+/)?(?:tiff/frame_\d{5}\.(?:tiff|json)|png/frame_\d{5}\.png|[^/]+\.gif)$")


def earlier_frames(out: Path, layout: list[str]) -> list[str]:
    """Files under ``out`` (relative, sorted) that look like an export's (:data:`_EXPORTED`) and
    are not among ``layout``, the files this export writes: an earlier export they would mix with."""
    if not out.is_dir():
        return []
    keep = set(layout)
    found = (p.relative_to(out).as_posix() for depth in ("*", "*/*", "*/*/*") for p in out.glob(depth))
    return sorted(rel for rel in found if _EXPORTED.match(rel) and rel not in keep and (out / rel).is_file())


def run(args) -> int:
    from twin.io.atomic import output_folder
    from twin.io.paths import Files
    from twin.io.thermography import (KINDS, camera_names, check_frames, export_files, write_gif, write_png_frames,
                                      write_tiff_frames)

    if args.every < 1:
        raise InputError("command line", "--every", f"must be a whole number >= 1, got {args.every}")
    files = Files()
    path = files.input(args.result, "result", "result file")
    source = str(path)
    with open_result(path) as ds:
        known = camera_names(ds, source)
        if not known:
            raise InputError(source, "camera", "the result has no camera (simulate with --camera NAME)")
        chosen = [c for c in known if args.camera in (None, c[0])]
        if not chosen:
            raise InputError("command line", "--camera", f"no camera {args.camera!r} in {path}; "
                                                          f"known: {', '.join(n for n, _ in known)}")
        kinds = [k for k in KINDS if getattr(args, k)] or list(KINDS)
        many = len(chosen) > 1
        counts = {suffix: check_frames(ds, suffix, source) for _, suffix in chosen}
        layout = [f"{name}/{rel}" if many else rel
                  for name, suffix in chosen for rel in export_files(counts[suffix], args.every, kinds, name)]
        out = declare_output(files, args.output, layout,
                             cameras={(f"{name}/" if many else ""): name for name, _ in chosen})
        with output_folder(out):
            for name, suffix in chosen:
                folder = out / name if many else out
                if "tiff" in kinds:
                    n = len(write_tiff_frames(ds, folder / "tiff", suffix, args.every))
                    print(f"wrote {n} 16-bit TIFFs (centikelvin) with JSON sidecars to {folder / 'tiff'}")
                if "png" in kinds:
                    n = len(write_png_frames(ds, folder / "png", suffix, args.every))
                    print(f"wrote {n} PNG frames to {folder / 'png'}")
                if "gif" in kinds:
                    print(f"wrote {write_gif(ds, folder / f'{name}.gif', suffix, args.every)}")
    return 0
