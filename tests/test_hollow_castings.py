"""Hollow castings (``Part.voids``): a box column with closed cores instead of a solid block, the
option with which README "The workshop" measured the door event's trade-off. Geometry checked
against closed forms on the coarse mesh (about 1 s)."""

from __future__ import annotations

import numpy as np
import pytest

from geometries.base import Box
from geometries.cframe_vmc import build, carrier_cores, column_cores
from twin.fem.mesh import mesh_machine
from twin.fem.regions import role_facets


@pytest.fixture(scope="module")
def solid_and_hollow():
    return mesh_machine(build(), "coarse"), mesh_machine(build(column_wall=0.03), "coarse")


def test_column_volume_is_the_block_less_its_core(solid_and_hollow):
    """V_hollow = V_block - (x1 - x0)(y1 - y0)(z1 - z0) of the core, to round-off."""
    solid, hollow = solid_and_hollow
    core = column_cores(0.45, 0.90, 1.90, 0.03, ribs=False)
    assert len(core) == 1
    v_solid, v_hollow = (m.volume_of(m.cells_of("column")) for m in solid_and_hollow)
    assert v_hollow == pytest.approx(v_solid - core[0].volume, abs=1e-12)


def test_core_walls_are_no_skin(solid_and_hollow):
    """The cavity's walls (area 2 (ab + bc + ca) of the core) are boundary faces of the mesh but
    not skin: the skin keeps exactly the solid machine's area."""
    solid, hollow = solid_and_hollow
    skin = [m.facet_area(role_facets(m, "structure.skin")) for m in (solid, hollow)]
    assert skin[1] == pytest.approx(skin[0], abs=1e-12)
    a, b, c = np.subtract(column_cores(0.45, 0.90, 1.90, 0.03, ribs=False)[0].hi,
                          column_cores(0.45, 0.90, 1.90, 0.03, ribs=False)[0].lo)
    boundary = [m.facet_area(m.mesh.boundary_facets()) for m in (solid, hollow)]
    assert boundary[1] - boundary[0] == pytest.approx(2 * (a * b + b * c + c * a), abs=1e-12)


def test_ribs_and_carrier_cores_stay_inside_their_castings():
    """Six column cores (a web and two diaphragms, walls 30 mm apart) and three carrier cores
    round the spindle boss, each inside its casting's box and disjoint from the others."""
    cores = column_cores(0.45, 0.90, 1.90, 0.03, ribs=True)
    carrier = carrier_cores(0.45, 0.03)
    assert len(cores) == 6 and len(carrier) == 3
    for group, outer in ((cores, Box((-0.25, 0.45, 0.35), (0.25, 0.90, 1.90))),
                         (carrier, Box((-0.18, -0.12, 1.10), (0.18, 0.45, 1.55)))):
        assert all(outer.contains(np.array([b.lo, b.hi])).all() for b in group)
        total = sum(b.volume for b in group)
        lo = np.min([b.lo for b in group], axis=0)
        hi = np.max([b.hi for b in group], axis=0)
        grid = np.stack(np.meshgrid(*[np.linspace(l, h, 41) for l, h in zip(lo, hi)], indexing="ij"), -1).reshape(-1, 3)
        inside = sum(b.contains(grid, tol=-1e-9) for b in group)
        assert inside.max() <= 1 and total < Box(tuple(lo), tuple(hi)).volume
    assert column_cores(0.45, 0.90, 1.90, None, ribs=True) == () and carrier_cores(0.45, None) == ()
