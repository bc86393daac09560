"""Regions of a meshed machine: role and region descriptions (:mod:`geometries.regions`) resolved
into cell indices (volumes) or facet indices (surfaces and interfaces) of a :class:`MachineMesh`.

* ``Parts`` -> the cells of those parts, or their boundary facets (faces open to air or floor);
* ``Named`` -> the facets of a named surface;
* ``Facing`` -> the facets of its base whose outward normal is the direction: the facet is flat
  across that axis and the centre of the cell that owns it lies on the other side;
* ``Band`` / ``InBox`` -> the cells or facets of the base whose centre lies in the band or box;
* ``Union`` -> the sorted union.

A role the machine does not declare raises :class:`MissingRole` naming machine and role.
"""

from __future__ import annotations

import numpy as np

from geometries.regions import AXES, ROLES, Band, Facing, InBox, Named, Parts, Union


class MissingRole(KeyError):
    """The machine does not declare a role an effect or observer needs."""

    def __init__(self, machine: str, role: str):
        self.machine, self.role = machine, role
        super().__init__(f"machine {machine!r} has no role {role!r} ({ROLES.get(role, ('', 'unknown role'))[1]})")


def cell_centres(mm, cells: np.ndarray) -> np.ndarray:
    """Centroids (n, 3) [m] of the given cells."""
    return mm.mesh.p[:, mm.mesh.t[:, cells]].mean(axis=1).T


def facet_centres(mm, facets: np.ndarray) -> np.ndarray:
    """Centroids (nf, 3) [m] of the given facets."""
    return mm.mesh.p[:, mm.mesh.facets[:, facets]].mean(axis=1).T


def facing(mm, facets: np.ndarray, direction: str) -> np.ndarray:
    """Boundary facets among ``facets`` whose outward normal is ``direction`` ("+x", "-y", ...)."""
    sign, axis = (1.0 if direction[0] == "+" else -1.0), AXES[direction[1]]
    corners = mm.mesh.p[:, mm.mesh.facets[:, facets]]
    flat = np.ptp(corners[axis], axis=0) < 1e-12
    owner = mm.mesh.f2t[0, facets]
    cell_mid = mm.mesh.p[axis, mm.mesh.t[:, owner]].mean(axis=0)
    outward = np.sign(corners[axis].mean(axis=0) - cell_mid)
    return facets[flat & (outward == sign)]


def exterior_facets(mm, parts: tuple[str, ...]) -> np.ndarray:
    """Boundary facets of the mesh owned by cells of ``parts``."""
    outer = mm.mesh.boundary_facets()
    return np.sort(outer[np.isin(mm.mesh.f2t[0, outer], mm.cells_of(*parts))])


def _in_span(xyz: np.ndarray, region) -> np.ndarray:
    if isinstance(region, Band):
        c = xyz[:, AXES[region.axis]]
        return (c >= region.lo - 1e-9) & (c <= region.hi + 1e-9)
    return region.box.contains(xyz)


def region_cells(mm, region) -> np.ndarray:
    """Sorted cell indices of a volume region."""
    if isinstance(region, Parts):
        return mm.cells_of(*region.names)
    if isinstance(region, (Band, InBox)):
        cells = region_cells(mm, region.base)
        return cells[_in_span(cell_centres(mm, cells), region)]
    if isinstance(region, Union):
        return np.unique(np.concatenate([region_cells(mm, r) for r in region.regions]))
    raise TypeError(f"{region!r} is a surface, not a volume")


def region_facets(mm, region) -> np.ndarray:
    """Sorted facet indices of a surface (or interface) region."""
    if isinstance(region, Named):
        if region.surface not in mm.facets:
            raise KeyError(f"machine {mm.machine.name!r} has no surface {region.surface!r}")
        return mm.facets[region.surface]
    if isinstance(region, Parts):
        return exterior_facets(mm, region.names)
    if isinstance(region, Facing):
        return facing(mm, region_facets(mm, region.base), region.direction)
    if isinstance(region, (Band, InBox)):
        facets = region_facets(mm, region.base)
        return facets[_in_span(facet_centres(mm, facets), region)]
    if isinstance(region, Union):
        return np.unique(np.concatenate([region_facets(mm, r) for r in region.regions]))
    raise TypeError(f"{region!r} is not a surface region")


def _role(mm, role: str):
    try:
        return mm.machine.role(role)
    except KeyError:
        raise MissingRole(mm.machine.name, role) from None


def role_cells(mm, role: str) -> np.ndarray:
    """Cells of the machine's volume role ``role`` (:class:`MissingRole` if it has none)."""
    return region_cells(mm, _role(mm, role))


def role_facets(mm, role: str) -> np.ndarray:
    """Facets of the machine's surface or interface role ``role``."""
    return region_facets(mm, _role(mm, role))


def role_parts(mm, role: str) -> tuple[str, ...]:
    """Part names of the machine's ``parts`` role (a :class:`Parts` region)."""
    region = _role(mm, role)
    if not isinstance(region, Parts):
        raise TypeError(f"role {role!r} of machine {mm.machine.name!r} must be a Parts region")
    return tuple(region.names)
