"""Full 3-D fields to files a viewer reads (ParaView, pyvista): VTU or XDMF via meshio."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from twin.errors import InputError

SUFFIXES = (".vtu", ".xdmf")


def write_temperature_field(mm, field: np.ndarray, path, time_s: float) -> Path:
    """Write the nodal temperature [degC] (temperature dofs mapped to mesh nodes; at a split
    contact the first copy is kept) and each cell's part index on the hexahedral mesh."""
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
    mesh.write(path)
    return path
