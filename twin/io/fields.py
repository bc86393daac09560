"""Full 3-D fields to files a viewer reads (ParaView, pyvista): VTU or XDMF via meshio.

An XDMF file is light XML that points into a companion HDF5 file holding the arrays: ``hot.xdmf``
always goes with ``hot.h5`` beside it (the same name, suffix ``.h5``), which the XDMF names by that
final name. A command declares both (:func:`declare_field`) and writes them with
:func:`save_temperature_field`: each appears whole or not at all (:mod:`twin.io.atomic`), no
temporary file stays behind, and the same field gives byte-identical files.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

from twin.errors import InputError
from twin.io.atomic import atomic_write

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
    contact the first copy is kept) and each cell's part index on the hexahedral mesh. An XDMF
    ``path`` also writes :func:`heavy_data_file` beside it (meshio's layout); commands use
    :func:`save_temperature_field`."""
    import meshio

    path = Path(path)
    if path.suffix.lower() not in SUFFIXES:
        raise InputError(str(path), "--field", f"unknown field format {path.suffix!r}; use {' or '.join(SUFFIXES)}")
    node_values = np.asarray(field)[: mm.nnodes]
    # meshio's hexahedron numbers corners counter-clockwise per face; scikit-fem's order differs
    order = [0, 2, 4, 1, 3, 6, 7, 5]
    mesh = meshio.Mesh(mm.mesh.p.T, [("hexahedron", mm.mesh.t[order].T)],
                       point_data={"temperature_degC": node_values},
                       cell_data={"part": [mm.cell_part.astype(np.int32)]},
                       field_data={"time_s": np.array([time_s, 0])})
    mesh.write(path, file_format="xdmf" if path.suffix.lower() == ".xdmf" else "vtu")
    return path


def save_temperature_field(mm, field: np.ndarray, path, time_s: float, field_name: str = "--field") -> list[Path]:
    """:func:`write_temperature_field` to ``path`` atomically; for XDMF the companion HDF5 file
    (:func:`heavy_data_file`) too, written first, the XDMF referring to it by its final name.
    Both are made in a temporary folder beside ``path`` and renamed into place (the folder is
    removed whatever happens). Returns the files written."""
    path = Path(path)
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
