"""Figures: drift/tilt/temperature traces of a result, and a 3-D picture of a temperature field.

matplotlib only (headless 'Agg' backend), so pictures work on machines without a display.
"""

from __future__ import annotations

import contextlib
import gzip
import io
import os
import threading
from pathlib import Path

import numpy as np

from twin.errors import InputError
from twin.io.paths import output_file


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


# formats matplotlib writes by itself (pgf needs LaTeX; the others need an optional Pillow codec)
_PICTURES = ("png", "pdf", "svg", "svgz", "eps", "ps", "jpg", "jpeg", "tif", "tiff", "webp")


def save_figure(fig, path, **options) -> None:
    """``fig.savefig(path, **options)``, the same bytes for the same figure: the formats that stamp
    the time of writing (PDF and PostScript's CreationDate, SVG's date, gzip's header of SVGZ)
    are written without it or with a fixed one, PostScript without the file's name as its title,
    and SVG's element ids are drawn from a fixed salt instead of a random one."""
    import matplotlib

    kind = str(options.get("format") or Path(str(path)).suffix.lstrip(".")).lower()
    metadata = {"pdf": {"CreationDate": None}, "svg": {"Date": None}, "svgz": {"Date": None}}.get(kind)
    if metadata is not None:
        options = {"metadata": metadata, **options}
    with matplotlib.rc_context({"svg.hashsalt": "thermal-twin"}), _fixed_postscript_date(kind in ("ps", "eps")):
        if kind not in ("ps", "eps", "svgz"):
            fig.savefig(path, **options)
            return
        # PostScript titles itself with the file's name (a command's temporary name) and gzip
        # stamps the name and the time: write to memory, then the bytes
        buffer = io.BytesIO()
        fig.savefig(buffer, **{**options, "format": "svg" if kind == "svgz" else kind})
        data = buffer.getvalue()
        if kind == "svgz":
            data = gzip.compress(data, mtime=0)
        Path(path).write_bytes(data)


_DATE_LOCK = threading.Lock()


@contextlib.contextmanager
def _fixed_postscript_date(active: bool):
    """PostScript's %%CreationDate from SOURCE_DATE_EPOCH (the reproducible-builds convention
    matplotlib's PostScript writer reads; it takes no metadata date), set to 0 while writing
    unless the caller's environment already sets it."""
    if not active or "SOURCE_DATE_EPOCH" in os.environ:
        yield
        return
    with _DATE_LOCK:
        os.environ["SOURCE_DATE_EPOCH"] = "0"
        try:
            yield
        finally:
            del os.environ["SOURCE_DATE_EPOCH"]


def picture_suffixes() -> tuple[str, ...]:
    """The picture suffixes ``twin plot`` writes (".png", ".pdf", ".svg", ...): those matplotlib
    supports that need no external program."""
    from matplotlib.backend_bases import FigureCanvasBase

    supported = FigureCanvasBase.get_supported_filetypes()
    return tuple(f".{k}" for k in _PICTURES if k in supported)


NEEDED = ("drift", "temperature", "temperature_true", "spindle_speed", "ambient_temperature")
# the test bar's instruments: the ISO 230-3 probes, or (a machine without them) laser triangulation
PROBES, LASERS = ("tilt", "probe_drift"), ("laser", "laser_tilt")


def check_plottable(ds, source: str) -> None:
    """``ds`` is a twin result :func:`plot_result` can draw: a Dataset with :data:`NEEDED` and the
    test bar's instruments (:data:`PROBES`, or :data:`LASERS` on a machine without probes)."""
    import xarray as xr

    if not isinstance(ds, xr.Dataset):
        raise InputError(source, "result", f"expected a twin result (an xarray.Dataset), got {type(ds).__name__}")
    missing = [v for v in NEEDED + (LASERS if "laser" in ds else PROBES) if v not in ds]
    if missing:
        raise InputError(source, missing[0], "missing variable; is this a twin result?")


def plot_result(ds, path) -> None:
    """Three panels against time [min]: drift X, Y, Z [um] (with the ISO 230-3 probes' or the laser
    sensors' readings); tilts [urad] (A, B from the probes, or A from the laser pair); temperatures
    [degC]. ``ds`` is checked (:func:`check_plottable`) and ``path`` must be a picture file name
    (:func:`picture_suffixes`) in an existing folder."""
    check_plottable(ds, "plot_result")
    output_file(path, "path", picture_suffixes())
    plt = _pyplot()
    t = ds.time.values / 60.0
    fig, axes = plt.subplots(3, 1, figsize=(9, 10), sharex=True)
    lasers = "laser" in ds and "probe_drift" not in ds
    for axis in ds.axis.values:
        line, = axes[0].plot(t, ds.drift.sel(axis=axis), label=f"{axis} (true, tool point)")
        if not lasers:
            axes[0].plot(t, ds.probe_drift.sel(axis=axis), ls=":", color=line.get_color(), label=f"{axis} (probes)")
        elif str(axis) in ds.laser_id.values:
            axes[0].plot(t, ds.laser.sel(laser_id=axis), ls=":", color=line.get_color(), label=f"{axis} (laser)")
    axes[0].set_ylabel("drift [um]")
    if lasers:
        axes[1].plot(t, ds.laser_tilt, label="A (laser pair)")
    else:
        for rot in ds.rotation.values:
            axes[1].plot(t, ds.tilt.sel(rotation=rot), label=f"{rot} (probes)")
    axes[1].set_ylabel("tilt [urad]")
    rise = ds.temperature_true.max("time") - ds.temperature_true.isel(time=0)
    for name in ds.sensor.values[np.argsort(-rise.values)][:8]:
        axes[2].plot(t, ds.temperature.sel(sensor=name), label=str(name), lw=1)
    axes[2].plot(t, ds.ambient_temperature, "k--", label="room air")
    axes[2].set_ylabel("temperature [degC]")
    axes[2].set_xlabel("time [min]")
    on = ds.spindle_speed.values > 0
    running = "spindle"
    if "c_axis_speed" in ds:     # a C axis turning heats as a spindle does
        on = on | (ds.c_axis_speed.values * ds.c_axis_duty.values > 0)
        running = "spindle or C axis"
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=2, loc="best")
        if on.any():
            ax.fill_between(t, 0, 1, where=on, color="orange", alpha=0.08, transform=ax.get_xaxis_transform(), step="post")
    shading = f" (shaded: {running} running)" if on.any() else ""
    axes[0].set_title(f"{ds.attrs.get('machine', '')} / {ds.attrs.get('scenario', '')}{shading}")
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def plot_field_3d(mm, field: np.ndarray, path, title: str = "") -> None:
    """Exterior faces of the mesh coloured by the nodal field (e.g. temperature [degC])."""
    plt = _pyplot()
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    mesh = mm.mesh
    facets = mesh.boundary_facets()
    quads = mesh.facets[:, facets]
    xyz = mesh.p.T[quads.T]  # (nf, 4, 3), corner order around the face
    # order the four corners of each axis-aligned face around its perimeter
    centre = xyz.mean(axis=1, keepdims=True)
    rel = xyz - centre
    normal_axis = np.argmin(np.ptp(xyz, axis=1), axis=1)
    a = np.where(normal_axis == 0, 1, 0)
    b = np.where(normal_axis == 2, 1, 2)
    ang = np.arctan2(np.take_along_axis(rel, b[:, None, None].repeat(4, 1), 2)[..., 0],
                     np.take_along_axis(rel, a[:, None, None].repeat(4, 1), 2)[..., 0])
    xyz = np.take_along_axis(xyz, np.argsort(ang, axis=1)[..., None].repeat(3, 2), axis=1)
    values = field[quads].mean(axis=0)
    fig = plt.figure(figsize=(8, 8))
    ax = fig.add_subplot(projection="3d")
    norm = plt.Normalize(values.min(), values.max())
    cmap = plt.get_cmap("coolwarm")
    ax.add_collection3d(Poly3DCollection(xyz * 1e3, facecolors=cmap(norm(values)), edgecolors=(0, 0, 0, 0.08), linewidths=0.2))
    lo, hi = mesh.p.min(axis=1) * 1e3, mesh.p.max(axis=1) * 1e3
    span = (hi - lo).max() / 2
    mid = (hi + lo) / 2
    ax.set_xlim(mid[0] - span, mid[0] + span)
    ax.set_ylim(mid[1] - span, mid[1] + span)
    ax.set_zlim(mid[2] - span, mid[2] + span)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.view_init(elev=20, azim=-130)
    sm = plt.cm.ScalarMappable(norm=norm, cmap=cmap)
    fig.colorbar(sm, ax=ax, shrink=0.6, label="temperature [degC]")
    ax.set_title(title)
    save_figure(fig, path, dpi=110)
    plt.close(fig)
