"""Thermal-camera frames out of a result: the counts, radiometric TIFFs, PNG/GIF sequences.

* :func:`camera_names` lists a result's cameras (name and variable suffix), checking their
  attributes; :func:`check_frames` checks a camera's frames before anything is written (present,
  finite: a NaN pixel is refused with its frame time); :func:`export_files` names the files the
  writers below make, so that a command declares them first (:class:`twin.io.paths.Files`);
* :func:`camera_counts` gives a camera's 14-bit counts: the stored ``counts`` when present, else
  recovered exactly from the thermogram through the camera's look-up table (the thermogram is
  stored with integers finer than the table's steps, :mod:`twin.observe.camera_output`);
* :func:`write_tiff_frames`: one 16-bit TIFF per frame in centikelvin (value = round(100 (T_app +
  273.15))), each with a JSON sidecar of the frame time and the radiometric settings;
* :func:`write_png_frames` and :func:`write_gif`: colour frames on one fixed scale for teaching.

Files are written atomically (:mod:`twin.io.atomic`).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from twin.errors import InputError
from twin.limits import is_file_name
from twin.io.atomic import atomic_write, atomic_write_text

KINDS = ("tiff", "png", "gif")
# what a TIFF's sidecar copies from the camera attribute
CAMERA_KEYS = ("name", "suffix", "settings", "band_um", "intrinsics", "pose")


def camera_names(ds, source: str = "result") -> list[tuple[str, str]]:
    """(name, variable suffix) of every camera in result ``ds``, in the run's order. Each camera
    attribute (``camera``, ``camera_<name>``) must be a JSON object with :data:`CAMERA_KEYS`, its
    name a plain file name (it names folders and files), else :class:`InputError` naming
    ``source`` and the attribute."""
    out = []
    for key, value in ds.attrs.items():
        if key == "camera" or key.startswith("camera_"):
            try:
                info = json.loads(value)
            except (TypeError, ValueError) as err:
                raise InputError(source, key, f"malformed camera attribute, not JSON ({err})") from None
            if not isinstance(info, dict):
                raise InputError(source, key, "malformed camera attribute, expected a JSON object")
            missing = [k for k in CAMERA_KEYS if k not in info]
            if missing:
                raise InputError(source, key, f"malformed camera attribute, no {missing[0]!r}")
            name, suffix = info["name"], info["suffix"]
            if not is_file_name(name):
                raise InputError(source, key, f"camera name {name!r} cannot name a file")
            if any(name == other for other, _ in out):
                raise InputError(source, key, f"a second camera named {name!r}: its frames would replace the "
                                              "first's")
            if not isinstance(suffix, str):
                raise InputError(source, key, f"variable suffix {suffix!r} is not text")
            out.append((name, suffix))
    return out


def check_frames(ds, suffix: str = "", source: str = "result") -> int:
    """The number of frames of the camera with ``suffix`` after checking its variables: a
    ``thermogram`` (frame_time, v, u) of at least one frame, finite ``frame_time`` and every
    pixel of every frame finite (checked frame by frame; a NaN names the frame and its time).
    :class:`InputError` naming ``source`` and the variable otherwise."""
    thermo, times = "thermogram" + suffix, "frame_time" + suffix
    for name in (thermo, times):
        if name not in ds.variables:
            raise InputError(source, name, "missing variable; is this a twin result with a camera?")
    var = ds[thermo]
    if var.ndim != 3 or var.dims[0] != times or ds[times].ndim != 1 or var.shape[0] < 1:
        raise InputError(source, thermo, f"expected frames ({times}, v, u), at least one; got dims {var.dims} "
                                         f"of shape {var.shape}")
    t = np.asarray(ds[times].values, dtype=float)
    if not np.all(np.isfinite(t)):
        first = int(np.flatnonzero(~np.isfinite(t))[0])
        raise InputError(source, times, f"holds NaN or infinite values at frame {first}")
    for i in range(var.shape[0]):
        frame = np.asarray(var[i].values, dtype=float)
        if not np.all(np.isfinite(frame)):
            bad = int(np.count_nonzero(~np.isfinite(frame)))
            raise InputError(source, thermo, f"holds NaN or infinite values ({bad} pixel(s)) in frame {i}, "
                                             f"t = {t[i]:g} s")
    try:
        int(ds.attrs.get("seed", 0))
    except (TypeError, ValueError):
        raise InputError(source, "seed", f"expected a whole number, got {ds.attrs.get('seed')!r}") from None
    return var.shape[0]


def frame_file(i: int, ext: str, prefix: str = "frame") -> str:
    """The name of frame ``i``'s file: ``{prefix}_{i:05d}.{ext}``."""
    return f"{prefix}_{i:05d}.{ext}"


def export_files(count: int, every: int, kinds, name: str, prefix: str = "frame") -> list[str]:
    """The files (relative to a camera's folder, in the order written) that exporting ``count``
    frames, every ``every``-th, as ``kinds`` (:data:`KINDS`) makes: ``tiff/`` TIFFs each with a
    JSON sidecar (:func:`write_tiff_frames`), ``png/`` PNGs (:func:`write_png_frames`),
    ``{name}.gif`` (:func:`write_gif`)."""
    idx = range(0, count, every)
    files = []
    if "tiff" in kinds:
        files += [f"tiff/{frame_file(i, ext, prefix)}" for i in idx for ext in ("tiff", "json")]
    if "png" in kinds:
        files += [f"png/{frame_file(i, 'png', prefix)}" for i in idx]
    if "gif" in kinds:
        files.append(f"{name}.gif")
    return files


def check_suffix(ds, suffix: str, source: str = "result") -> str:
    """``suffix`` when a camera of ``ds`` has it, else :class:`InputError` on ``suffix`` listing
    the result's cameras and their suffixes (a run with several cameras has no camera at ``""``)."""
    cameras = camera_names(ds, source)
    if not any(s == suffix for _, s in cameras):
        known = ", ".join(f"{n} (suffix {s!r})" for n, s in cameras) or "none"
        raise InputError(source, "suffix", f"no camera with the variable suffix {suffix!r}; this result's cameras: "
                                           f"{known}")
    return suffix


def camera_info(ds, suffix: str = "") -> dict:
    """The camera's attributes: pose, intrinsics, band, settings, scene, sensor (JSON decoded)."""
    return json.loads(ds.attrs["camera" + check_suffix(ds, suffix)])


def camera_counts(ds, suffix: str = "") -> np.ndarray:
    """(frames, H, W) uint16 counts of the camera with ``suffix`` (``""`` for a run's only camera,
    ``"_<name>"`` for each of several, :func:`camera_names`): stored, or lut^-1(thermogram)
    (nearest look-up value; exact when the result says its counts are recoverable)."""
    check_suffix(ds, suffix)
    if "counts" + suffix in ds:
        return ds["counts" + suffix].values
    lut = ds["camera_lut" + suffix].values.astype(float)
    enc = ds["thermogram" + suffix].encoding
    if "scale_factor" in enc:  # read from a file: compare with the table as stored
        q, off = float(enc["scale_factor"]), float(enc["add_offset"])
        lut = off + q * np.rint((lut.astype(np.float32) - np.float32(off)) / np.float32(q))
    t = ds["thermogram" + suffix].values.astype(float)
    i = np.clip(np.searchsorted(lut, t), 1, len(lut) - 1)
    nearer_below = np.abs(t - lut[i - 1]) <= np.abs(lut[i] - t)
    return np.where(nearer_below, i - 1, i).astype(np.uint16)


def centikelvin(t_degc: np.ndarray) -> np.ndarray:
    """uint16 centikelvin of temperatures [degC] (0.01 K steps, 0 to 655.35 K)."""
    return np.clip(np.rint((np.asarray(t_degc, dtype=float) + 273.15) * 100.0), 0, 65535).astype(np.uint16)


def _frames(ds, suffix: str, every: int):
    thermo = ds["thermogram" + suffix]
    times = ds["frame_time" + suffix].values
    idx = np.arange(0, len(times), every)
    return thermo, times, idx


def write_tiff_frames(ds, outdir, suffix: str = "", every: int = 1, prefix: str = "frame") -> list[Path]:
    """16-bit centikelvin TIFFs ``{prefix}_{i:05d}.tiff`` with JSON sidecars; returns the TIFFs."""
    from PIL import Image

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    info = camera_info(ds, suffix)
    thermo, times, idx = _frames(ds, suffix, every)
    paths = []
    for i in idx:
        path = outdir / frame_file(i, "tiff", prefix)
        image = Image.fromarray(centikelvin(thermo[i].values))  # uint16 -> mode "I;16"
        atomic_write(path, lambda tmp: image.save(tmp, format="TIFF"))
        sidecar = {"frame": int(i), "frame_time_s": float(times[i]), "units": "centikelvin (0.01 K), uint16",
                   "value": "round(100 * (apparent temperature [degC] + 273.15))", "camera": info["name"],
                   "settings": info["settings"], "band_um": info["band_um"], "intrinsics": info["intrinsics"],
                   "pose": info["pose"], "machine": ds.attrs.get("machine"), "scenario": ds.attrs.get("scenario"),
                   "seed": int(ds.attrs.get("seed", 0))}
        atomic_write_text(path.with_suffix(".json"), json.dumps(sidecar, indent=1))
        paths.append(path)
    return paths


def colour_scale(thermo) -> tuple[float, float]:
    """(low, high) [degC]: the 1st and 99.5th percentiles over the first and last frames."""
    ends = np.concatenate([thermo[0].values.ravel(), thermo[-1].values.ravel()])
    lo, hi = np.percentile(ends, [1.0, 99.5])
    return float(lo), float(max(hi, lo + 0.5))


def rgb_frames(ds, suffix: str = "", every: int = 1, scale: int = 2, cmap: str = "inferno"):
    """Yield (frame index, time [s], RGB uint8 image) of the thermogram on one colour scale, each
    pixel ``scale`` x ``scale``, the time and scale written in the top-left corner."""
    import matplotlib
    from PIL import Image, ImageDraw

    thermo, times, idx = _frames(ds, suffix, every)
    lo, hi = colour_scale(thermo)
    colours = (matplotlib.colormaps[cmap](np.linspace(0, 1, 256))[:, :3] * 255).astype(np.uint8)
    for i in idx:
        level = np.clip((thermo[i].values - lo) / (hi - lo) * 255, 0, 255).astype(np.uint8)
        image = Image.fromarray(colours[level]).resize((level.shape[1] * scale, level.shape[0] * scale), Image.NEAREST)
        ImageDraw.Draw(image).text((4, 2), f"t = {times[i] / 60:5.1f} min   {lo:.1f}-{hi:.1f} degC", fill=(255, 255, 255))
        yield i, times[i], image


def write_png_frames(ds, outdir, suffix: str = "", every: int = 1, prefix: str = "frame") -> list[Path]:
    """Colour PNGs ``{prefix}_{i:05d}.png`` (:func:`rgb_frames`), each naming its camera in a
    ``camera`` text chunk (:func:`exported_camera`); returns their paths."""
    from PIL.PngImagePlugin import PngInfo

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    text = PngInfo()
    text.add_text("camera", camera_info(ds, suffix)["name"])
    paths = []
    for i, _, image in rgb_frames(ds, suffix, every):
        path = outdir / frame_file(i, "png", prefix)
        atomic_write(path, lambda tmp: image.save(tmp, format="PNG", pnginfo=text))
        paths.append(path)
    return paths


def exported_camera(path) -> str | None:
    """The camera an exported frame file names: a TIFF's JSON sidecar (``.json``) its ``camera``
    field, a PNG its ``camera`` text chunk; None where the file names none (or is unreadable:
    an export older than the markers, or not an export)."""
    path = Path(path)
    try:
        if path.suffix == ".json":
            name = json.loads(path.read_text(encoding="utf-8")).get("camera")
        else:
            from PIL import Image
            with Image.open(path) as image:
                name = image.text.get("camera")
    except Exception:  # noqa: BLE001 - not a readable export: nothing to compare
        return None
    return name if isinstance(name, str) else None


def write_gif(ds, path, suffix: str = "", every: int = 1, frame_ms: int = 80) -> Path:
    """An animated GIF of the colour frames, ``frame_ms`` per frame."""
    images = [image for _, _, image in rgb_frames(ds, suffix, every)]
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write(path, lambda tmp: images[0].save(tmp, format="GIF", save_all=True,
                                                         append_images=images[1:], duration=frame_ms, loop=0))
