"""The checks of the arguments around a prepared twin (:class:`twin.physics.prepared.PreparedTwin`;
:func:`twin.physics.prepared.check_prepared` checks the twin itself): that a mesh resolution is one
the machine has, that values given beside a prepared twin are the ones it was prepared with (never
silently ignored), and the name a mesh is labelled with."""

from __future__ import annotations

from dataclasses import fields as fields_of

import numpy as np

from twin.errors import InputError
from twin.physics.options import as_options
from twin.physics.part_materials import part_materials

SOURCE = "PreparedTwin"     # the source named in errors about a PreparedTwin's arguments


def check_beside_prepared(prepared, source: str, mm=None, resolution=None, materials=None, solver=None,
                          fields: dict | None = None) -> None:
    """Arguments given beside a prepared twin are the ones it was prepared with, or an
    :class:`InputError` naming the argument (``fields`` renames them: the CLI's ``--mesh``): its
    mesh, resolution, materials and solver are the run's, so another value would be ignored."""
    name = {"mm": "mm", "resolution": "resolution", "materials": "materials", "solver": "solver", **(fields or {})}
    keep = "leave it out, the prepared twin's is used"
    if mm is not None and mm is not prepared.mm:
        raise InputError(source, name["mm"], f"is not the prepared twin's mesh ({prepared.resolution!r}, "
                                             f"{prepared.mm.nnodes} nodes): {keep}")
    if resolution is not None and resolution != prepared.resolution:
        check_resolution(prepared.machine, resolution, source, name["resolution"])
        raise InputError(source, name["resolution"], f"the prepared twin's mesh is {prepared.resolution!r} "
                                                     f"({prepared.mm.nnodes} nodes), not {resolution!r}: {keep}, or "
                                                     f"prepare the twin on {resolution!r}")
    if materials is not None and part_materials(prepared.machine, materials, source, name["materials"]) != prepared.materials:
        raise InputError(source, name["materials"], f"differ from the prepared twin's (the materials it was assembled "
                                                    f"with): {keep}")
    options = as_options(solver) if solver is not None else prepared.options
    differ = [f"{f.name} {getattr(options, f.name)!r} (the prepared twin's: {getattr(prepared.options, f.name)!r})"
              for f in fields_of(options) if getattr(options, f.name) != getattr(prepared.options, f.name)]
    if differ:
        raise InputError(source, name["solver"], f"differs from the prepared twin's: {', '.join(differ)}; {keep}")


def coarse_unless_given(mm=None, resolution=None):
    """The resolution a study prepares its twin on: the coarse mesh unless the caller gave a mesh
    ``mm`` or a ``resolution`` (a study repeats many runs; the caller opts into finer meshes)."""
    return "coarse" if mm is None and resolution is None else resolution


def check_resolution(machine, resolution, source: str = SOURCE, field: str = "resolution") -> str:
    """``resolution`` is the name of one of ``machine``'s meshes."""
    if not isinstance(resolution, str) or resolution not in machine.resolutions:
        raise InputError(source, field, f"unknown resolution {resolution!r}; known: {', '.join(machine.resolutions)}")
    return resolution


def mesh_label(machine, mm) -> str:
    """The name of ``machine``'s resolution ``mm`` was built at, else its spacing (``"12 mm"``)."""
    names = [name for name, h in machine.resolutions.items() if np.isclose(h, mm.spacing, rtol=1e-9, atol=0.0)]
    return names[0] if names else f"{mm.spacing * 1e3:.6g} mm"
