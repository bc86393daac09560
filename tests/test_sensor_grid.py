"""Dense surface-sensor grid: closed-form counts, exterior test, location in the mesh, a run."""

import math

import numpy as np
import pytest

from geometries import build_machine
from geometries.base import Box, Machine, Part, material
from twin.fem.points import locate
from twin.scenario import Ambient, Scenario
from twin.observe.sensor_grid import axis_positions, surface_sensor_grid
from twin.fem.mesh import mesh_machine


def _machine(parts):
    return Machine(name="boxes", parts=parts, surfaces=[], points=[], probes=[], tool_point="", workpiece_point="",
                   sensor_sites=[], resolutions={"coarse": 0.1})


def _n(length, spacing):
    return max(1, math.floor(length / spacing + 1e-9))


def test_axis_positions_centred_and_spaced():
    x = axis_positions(0.0, 0.33, 0.1)
    assert len(x) == 3 and np.allclose(np.diff(x), 0.1) and np.isclose(x.mean(), 0.165)
    assert np.allclose(axis_positions(0.0, 0.04, 0.05), [0.02])


@pytest.mark.parametrize("spacing", [0.05, 0.1, 0.07])
def test_one_box_counts_match_closed_form(spacing):
    a, b, c = 0.4, 0.3, 0.55
    m = _machine([Part("block", material("steel"), (Box((0, 0, 0), (a, b, c)),))])
    pts = surface_sensor_grid(m, parts=("block",), spacing=spacing)
    na, nb, nc = _n(a, spacing), _n(b, spacing), _n(c, spacing)
    assert len(pts) == 2 * (na * nb + nb * nc + na * nc)
    per_face = {f: sum(p.name.split(":")[1] == f for p in pts) for f in ("-x", "+x", "-y", "+y", "-z", "+z")}
    assert per_face == {"-x": nb * nc, "+x": nb * nc, "-y": na * nc, "+y": na * nc, "-z": na * nb, "+z": na * nb}
    assert len({p.name for p in pts}) == len(pts)
    xyz = np.array([p.xyz for p in pts])
    assert np.all(xyz > 0) and np.all(xyz < [a, b, c])
    # 1 mm inside exactly one face
    depth = np.minimum(xyz, np.array([a, b, c]) - xyz).min(axis=1)
    assert np.allclose(depth, 1e-3)


def test_covered_faces_and_overwritten_areas_carry_no_sensors():
    steel = material("steel")
    lower = Part("lower", steel, (Box((0, 0, 0), (1.0, 1.0, 0.5)),))
    upper = Part("upper", steel, (Box((0, 0, 0.5), (1.0, 1.0, 1.0)),))  # sits on all of lower's top
    insert = Part("insert", steel, (Box((0.3, 0.3, -0.1), (0.7, 0.7, 0.2)),))  # pokes through lower's floor
    m = _machine([lower, upper, insert])
    pts = surface_sensor_grid(m, parts=("lower",), spacing=0.1)
    faces = [p.name.split(":")[1] for p in pts]
    assert "+z" not in faces
    bottom = np.array([p.xyz for p in pts if p.name.split(":")[1] == "-z"])
    inside_insert = (np.abs(bottom[:, 0] - 0.5) < 0.2) & (np.abs(bottom[:, 1] - 0.5) < 0.2)
    assert len(bottom) == 100 - 16 and not inside_insert.any()


def test_cframe_grid_points_lie_in_their_parts_cells():
    m = build_machine("cframe-vmc")
    pts = surface_sensor_grid(m, spacing=0.1)
    assert {p.part for p in pts} == {"carrier", "column", "test_bar"}
    mm = mesh_machine(m, "coarse")
    cells, xi = locate(mm, np.array([p.xyz for p in pts]), [p.name for p in pts])
    assert np.all(np.abs(xi) <= 1 + 1e-9)
    assert [mm.part_names[mm.cell_part[c]] for c in cells] == [p.part for p in pts]
    again = surface_sensor_grid(m, spacing=0.1)
    assert [p.name for p in again] == [p.name for p in pts]


def test_run_with_grid_sensors_coarse():
    """Grid sensors are observers only: with the machine's own sites added under other names,
    (i) every reading at t = 0 is the uniform initial field, the 20 degC room (exact), (ii) a
    site reads the same with and without the grid beside it, and as the grid's copy of it at the
    same point (the same interpolation of one field: round-off), (iii) the heat is the spindle's:
    the warmest grid sensor is on the spindle's side (the test bar in its nose, or the carrier
    holding the bearings), and the column's warmest rises less than the carrier's."""
    from geometries.base import Point
    from twin.api import simulate

    m = build_machine("cframe-vmc")
    pts = surface_sensor_grid(m, spacing=0.15)
    sites = [p for p in m.points if p.name in m.sensor_sites]
    copies = [Point(f"copy:{p.name}", p.xyz, p.part) for p in sites]
    sc = Scenario("short", ((600.0, 9000.0), (600.0, 0.0)), Ambient("constant", mean=20.0), sample_interval=60.0)
    ds, _ = simulate("cframe-vmc", sc, resolution="coarse", sensors=pts + copies)
    assert list(ds.sensor.values) == [p.name for p in pts + copies]
    assert ds.temperature.shape == (21, len(pts) + len(copies))
    assert np.abs(ds.temperature_true.isel(time=0).values - 20.0).max() < 1e-12
    plain, _ = simulate("cframe-vmc", sc, resolution="coarse")
    own = plain.temperature_true.sel(sensor=[p.name for p in sites]).values
    assert np.allclose(ds.temperature_true.sel(sensor=[c.name for c in copies]).values, own, rtol=0, atol=1e-10)
    grid = ds.temperature_true.sel(sensor=[p.name for p in pts]).isel(time=-1)
    assert float((grid - 20.0).max()) > 0.1
    part = [p.part for p in pts]
    assert part[int(np.argmax(grid.values))] in ("test_bar", "carrier")
    rise = {name: float(grid.values[[q == name for q in part]].max()) - 20.0 for name in ("carrier", "column")}
    assert 0 < rise["column"] < rise["carrier"]
