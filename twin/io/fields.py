"""Full 3-D fields to files a viewer reads (ParaView, pyvista): VTU or XDMF via meshio.

An XDMF file is light XML that points into a companion HDF5 file holding the arrays: ``hot.xdmf``
always goes with ``hot.h5`` beside it (the same name, suffix ``.h5``), which the XDMF names by that
final name. A command declares both (:func:`declare_field`) and writes them with
:func:`save_temperature_field`: each appears whole or not at all (:mod:`twin.io.atomic`), no
temporary file stays behind, and the same field gives byte-identical files.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

import numpy as np

from twin.errors import InputError
from twin.io.atomic import atomic_write
from twin.io.paths import as_path
from twin.limits import is_finite_number

SUFFIXES = (".vtu", ".xdmf")
HEAVY_SUFFIX = ".h5"


def heavy_data_file(path: str | os.PathLike) -> Path | None:
    """The companion HDF5 file of an XDMF ``path`` (``hot.xdmf`` -> ``hot.h5``); None for a VTU."""
    path = Path(path)
    return path.with_suffix(HEAVY_SUFFIX) if path.suffix.lower() == ".xdmf" else None


def declare_field(files, path: str | os.PathLike, field: str = "--field") -> Path:
    """Declare the field file ``path`` and, for XDMF, its companion HDF5 file as outputs of
    ``files`` (:class:`twin.io.paths.Files`), so neither can replace an input or another output;
    returns ``path`` checked."""
    path = files.output(path, field, SUFFIXES)
    heavy = heavy_data_file(path)
    if heavy is not None:
        try:
            files.output(heavy, field, (HEAVY_SUFFIX,))
        except InputError as err:
            raise InputError(err.source, err.field, f"{err.message} (it would hold the data of {path})") from None
    return path


def write_temperature_field(mm, field: np.ndarray, path, time_s: float) -> Path:
    """Write the nodal temperature [degC] (temperature dofs mapped to mesh nodes; at a split
    contact the first copy is kept) and each cell's part index on the hexahedral mesh
    (coordinates in m), at the run's instant ``time_s`` [s]: a VTU holds it as the field data
    ``TimeValue`` (the VTK convention ParaView reads; meshio reads it into ``field_data``), an
    XDMF as a temporal collection of one step (``<Time Value=...>``; ParaView shows it, and
    ``meshio.xdmf.TimeSeriesReader`` reads it). An XDMF ``path`` also writes
    :func:`heavy_data_file` beside it (meshio's layout); commands use :func:`save_temperature_field`."""
    import meshio

    path = Path(path)
    if path.suffix.lower() not in SUFFIXES:
        raise InputError(str(path), "--field", f"unknown field format {path.suffix!r}; use {' or '.join(SUFFIXES)}")
    node_values = np.asarray(field)[: mm.nnodes]
    # meshio's hexahedron numbers corners counter-clockwise per face; scikit-fem's order differs
    order = [0, 2, 4, 1, 3, 6, 7, 5]
    points, cells = mm.mesh.p.T, [("hexahedron", mm.mesh.t[order].T)]
    point_data, cell_data = {"temperature_degC": node_values}, {"part": [mm.cell_part.astype(np.int32)]}
    if path.suffix.lower() == ".xdmf":
        # meshio's time-series writer puts its HDF5 file in the working folder: write from the
        # XDMF's own (this changes the process's working folder for the moment: not for threads)
        with contextlib.chdir(path.resolve().parent), meshio.xdmf.TimeSeriesWriter(path.name) as series:
            series.write_points_cells(points, cells)
            series.write_data(float(time_s), point_data=point_data, cell_data=cell_data)
        return path
    meshio.Mesh(points, cells, point_data=point_data, cell_data=cell_data).write(path, file_format="vtu")
    _add_vtu_field_data(path, float(time_s), list(mm.part_names))
    return path


def _add_vtu_field_data(path: Path, time_s: float, part_names: list[str]) -> None:
    """Insert the VTK field data after the ``<UnstructuredGrid>`` tag of a VTU written by meshio
    (whose writer drops ``field_data``): ``TimeValue`` [s], and ``part:NAME`` = the index the cell
    data ``part`` gives that part (the feed drives' parts included), so the file names its parts."""
    from xml.sax.saxutils import quoteattr

    text = path.read_text(encoding="ascii")
    tag = "<UnstructuredGrid>\n"
    arrays = [("Float64", "TimeValue", repr(time_s))] + [("Int32", f"part:{name}", str(i))
                                                          for i, name in enumerate(part_names)]
    field_data = "<FieldData>\n" + "".join(f'<DataArray type="{kind}" Name={quoteattr(name)} NumberOfTuples="1" '
                                          f'format="ascii">\n{value}\n</DataArray>\n'
                                          for kind, name, value in arrays) + "</FieldData>\n"
    if tag not in text:   # pragma: no cover - meshio's layout changed
        raise RuntimeError(f"{path}: no <UnstructuredGrid> tag to put the field's time after")
    path.write_text(text.replace(tag, tag + field_data, 1), encoding="ascii")


def save_temperature_field(mm, field: np.ndarray, path, time_s: float, field_name: str = "--field") -> list[Path]:
    """:func:`write_temperature_field` to ``path`` atomically; for XDMF the companion HDF5 file
    (:func:`heavy_data_file`) too, written first, the XDMF referring to it by its final name.
    Both are made in a temporary folder beside ``path`` and renamed into place (the folder is
    removed whatever happens). Returns the files written. ``field`` is the run's temperature
    [degC] at every temperature dof of ``mm`` (finite), ``time_s`` a finite time >= 0 [s]:
    checked before anything is written, as is the suffix."""
    path = as_path(path, field_name)
    if path.suffix.lower() not in SUFFIXES:
        raise InputError(str(path), field_name, f"unknown field format {path.suffix!r}; use {' or '.join(SUFFIXES)}")
    values = np.asarray(field, dtype=float) if isinstance(field, np.ndarray) else None
    if values is None or values.shape != (mm.nheat,) or not np.all(np.isfinite(values)):
        got = "not an array" if values is None else f"shape {values.shape}" + (
            "" if values.shape != (mm.nheat,) else ", not finite")
        raise InputError(str(path), field_name, f"the field must hold one finite temperature per temperature dof "
                                                f"({mm.nheat}), got {got}")
    if not is_finite_number(time_s) or time_s < 0:
        raise InputError(str(path), field_name, f"the field's time must be a finite number of seconds >= 0, got "
                                                f"{time_s!r}")
    heavy = heavy_data_file(path)
    if heavy is None:
        return [atomic_write(path, lambda tmp: write_temperature_field(mm, field, tmp, time_s), field_name)]
    try:
        scratch = tempfile.TemporaryDirectory(prefix=".twin-", dir=path.parent)
    except OSError as err:
        raise InputError(str(path), field_name, f"could not be written ({err.strerror or err})") from None
    with scratch as folder:
        light = write_temperature_field(mm, field, Path(folder) / path.name, time_s)
        made = heavy_data_file(light)
        return [atomic_write(heavy, lambda tmp: os.replace(made, tmp), field_name),
                atomic_write(path, lambda tmp: os.replace(light, tmp), field_name)]
