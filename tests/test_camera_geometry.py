"""The thermal camera's geometry against closed forms: the pinhole projection, a pixel's footprint,
occlusion, the grid caster against trimesh's intersector, the overview pose's framing and the
outer surface's normals. The radiometry, noise, frames and files are in ``tests/test_camera.py``,
whose small scenes these share."""

import math

import numpy as np
import pytest

from geometries.base import Box, Part, material
from tests.test_camera import POSE, SMALL, _machine, _plate
from twin.fem.mesh import build_mesh
from twin.observe.camera import CameraConfig
from twin.observe.camera_geometry import (Intrinsics, camera_frame, footprint_directions, pixel_directions, project,
                                          temperature_rows, view_machine)


def test_point_lands_on_its_pinhole_pixel_and_depth_is_the_ray_length():
    """A 2 cm cube at a known point is seen by pixel (floor u, floor v) of u = W/2 + (X-C).r /
    ((X-C).f s_u), v = H/2 + (X-C).d / ((X-C).f s_v); its depth is the ray's length to the face."""
    centre = np.array([0.17, -0.4, 0.62])
    cube = Part("cube", material("steel"), (Box(tuple(centre - 0.01), tuple(centre + 0.01)),))
    plate = _plate().parts[0]
    m = _machine([plate, cube], [], spacing=0.01)
    r, d, f = camera_frame(POSE.position, POSE.target, POSE.up)
    su, sv = SMALL.pitch
    c = centre - np.array(POSE.position)
    u_closed = SMALL.width / 2 + (c @ r) / ((c @ f) * su)
    v_closed = SMALL.height / 2 + (c @ d) / ((c @ f) * sv)
    u, v = project(POSE, SMALL, centre[None, :])
    assert u[0] == pytest.approx(u_closed, rel=1e-12) and v[0] == pytest.approx(v_closed, rel=1e-12)
    view = view_machine(build_mesh(m, 0.25), m, POSE, SMALL, edge_rays=1)
    iu, iv = int(math.floor(u[0])), int(math.floor(v[0]))
    assert view.part[iv, iu] == 1
    assert (view.part == 1).sum() == 1  # 2 cm at 1.1 m is smaller than a pixel (2.4 cm)
    ray = pixel_directions(POSE, SMALL, np.array([iu]), np.array([iv]))[0]
    front = centre[1] - 0.01
    assert view.depth[iv, iu] == pytest.approx((front - POSE.position[1]) / ray[1], rel=1e-12)


def test_pixel_footprint_is_ifov_times_distance():
    """n x n footprint rays of the on-axis direction hit a plate at distance d on a square grid
    of side IFOV d (midpoints: spacing IFOV d / n)."""
    d, n, ifov = 1.5, 5, 1.5e-3
    m = _plate()
    from twin.observe.raycast import cast, outer_surface

    r, _, f = camera_frame(POSE.position, POSE.target, POSE.up)
    dirs = footprint_directions(f[None, :], r, ifov, n)
    hits = cast(outer_surface(build_mesh(m, 0.25)), np.array(POSE.position), dirs, "grid")
    assert (hits.index >= 0).all()
    x = np.unique(np.round(hits.point[:, 0], 12))
    z = np.unique(np.round(hits.point[:, 2], 12))
    assert len(x) == len(z) == n
    assert n * np.diff(x).mean() == pytest.approx(ifov * d, rel=1e-9)
    assert n * np.diff(z).mean() == pytest.approx(ifov * d, rel=1e-9)


def test_a_part_behind_another_is_hidden():
    """A block in front of the plate: its pixels see the block, and their rows touch no
    temperature dof of the plate (there is a gap, so no shared nodes)."""
    block = Part("block", material("steel"), (Box((-0.1, -0.3, 0.4), (0.1, -0.1, 0.6)),))
    m = _machine([_plate().parts[0], block], [], spacing=0.1)
    mm = build_mesh(m, 0.1)
    view = view_machine(mm, m, POSE, SMALL, edge_rays=1)
    on_block = view.part.ravel() == 1
    assert on_block.sum() > 4 and (view.part == 0).sum() > 100
    rows = temperature_rows(view, mm)
    plate_dofs = np.unique(mm.heat_t[:, mm.cells_of("plate")])
    block_rays = np.flatnonzero(on_block[view.ray_pixel[view.hit]])
    assert rows[block_rays][:, plate_dofs].nnz == 0
    assert np.all(view.depth.ravel()[on_block] < 1.5 - 0.1 + 1e-9)


def test_grid_caster_matches_trimesh_ray_triangle():
    """The grid caster and trimesh's Moller-Trumbore intersector (fed every triangle) agree on
    the first hit of random rays at a coarse C-frame machine; Embree too when installed."""
    import trimesh
    from trimesh.ray.ray_triangle import ray_triangle_id

    from geometries import build_machine
    from twin.fem.mesh import mesh_machine
    from twin.observe.raycast import cast, embree_available, outer_surface

    m = build_machine("cframe-vmc")
    surface = outer_surface(mesh_machine(m, "coarse"))
    rng = np.random.default_rng(1)
    origin = np.array([0.3, -2.0, 1.4])
    dirs = np.column_stack([rng.uniform(-0.3, 0.2, 60), np.ones(60), rng.uniform(-0.6, 0.2, 60)])
    grid = cast(surface, origin, dirs, "grid")
    verts, faces = surface.triangles()
    tris = verts[faces]

    class Everything:  # an r-tree stand-in that offers every triangle to every ray
        bounds = np.concatenate([verts.min(axis=0), verts.max(axis=0)])

        def intersection(self, bounds):
            return range(len(tris))

    o = np.repeat(origin[None, :], len(dirs), axis=0)
    unit = dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
    tri, ray, loc = ray_triangle_id(tris, o, unit, tree=Everything(), multiple_hits=True)
    first = np.full(len(dirs), np.inf)
    for t_, r_, p_ in zip(tri, ray, loc):
        first[r_] = min(first[r_], np.linalg.norm(p_ - origin))
    assert np.array_equal(np.isfinite(first), grid.index >= 0) and (grid.index >= 0).sum() > 20
    hit = grid.index >= 0
    assert np.allclose(grid.distance[hit], first[hit], rtol=0, atol=1e-9)
    if embree_available():  # (facet indices may differ on a ray through an edge; the distance may not)
        emb = cast(surface, origin, dirs, "embree")
        assert np.array_equal(emb.index >= 0, hit) and np.allclose(emb.distance[hit], grid.distance[hit], atol=1e-9)
    assert isinstance(trimesh.__version__, str)


def test_overview_front_frames_the_bounding_box_with_a_ten_percent_margin():
    """overview-front stands on the box's centre line at -y, aimed at its centre (x_c, y_c, z_c), at
    d = 1.1 max(L_x / (2 tan(fov_h/2)), L_z / (2 tan(fov_v/2))) + L_y / 2, so the front face
    y = y_lo lies D = y_lo - y_cam = 1.1 max(...) ahead. The pinhole (right = +x, down = -z) maps
    a front-face point to u = W/2 + (x - x_c) W / (2 D tan(fov_h/2)), v = H/2 - (z - z_c) H /
    (2 D tan(fov_v/2)); the corners of a 2 x 1 x 0.5 m box then span max(du/W, dv/H) = 1/1.1, the
    width binding (the height spans less). Default intrinsics; rounding only: rel 1e-14."""
    from twin.observe.camera import OVERVIEW

    lo, hi = np.array([0.3, 0.2, 0.1]), np.array([2.3, 1.2, 0.6])          # 2 x 1 x 0.5 m
    m = _machine([Part("box", material("steel"), (Box(tuple(lo), tuple(hi)),))], [])
    intr = Intrinsics()
    pose = CameraConfig(pose=OVERVIEW).resolve_pose(m)
    centre = 0.5 * (lo + hi)
    assert np.array_equal(pose.target, centre)
    assert (pose.position[0], pose.position[2]) == (centre[0], centre[2]) and pose.position[1] < lo[1]
    D = lo[1] - pose.position[1]
    tx, tz = math.tan(intr.fov_h / 2), math.tan(intr.fov_v / 2)
    corners = np.array([[x, lo[1], z] for x in (lo[0], hi[0]) for z in (lo[2], hi[2])])
    u = intr.width / 2 + (corners[:, 0] - centre[0]) * intr.width / (2 * D * tx)
    v = intr.height / 2 - (corners[:, 2] - centre[2]) * intr.height / (2 * D * tz)
    du, dv = np.ptp(u) / intr.width, np.ptp(v) / intr.height
    assert max(du, dv) == pytest.approx(1 / 1.1, rel=1e-14)
    assert du > dv
    # the library's pinhole agrees with the one written out above
    pu, pv = project(pose, intr, corners)
    np.testing.assert_allclose(np.c_[pu, pv], np.c_[u, v], rtol=1e-14)


def test_the_outer_surface_normals_point_out_of_the_body():
    """Each boundary rectangle's normal is the unit axis vector pointing away from its owner cell
    (n . (facet centre - owner cell centre) > 0), so on an L-shaped body of two boxes every face
    at the body's largest x has n = +x, every one at its smallest -x, and an inner corner's faces
    point into the notch."""
    from twin.observe.raycast import outer_surface
    parts = [Part("a", material("steel"), (Box((0.0, 0.0, 0.0), (1.0, 0.5, 0.5)),)),
             Part("b", material("steel"), (Box((0.0, 0.0, 0.5), (0.5, 0.5, 1.0)),))]
    mm = build_mesh(_machine(parts, []), 0.25)
    s = outer_surface(mm)
    facet_centre = 0.5 * (s.lo + s.hi)
    owner_centre = mm.mesh.p[:, mm.mesh.t[:, s.owner]].mean(axis=1).T
    assert np.all(np.abs(s.normal).sum(axis=1) == 1.0)
    assert np.all(np.einsum("ij,ij->i", s.normal, facet_centre - owner_centre) > 0)
    x = facet_centre[:, 0]
    assert np.all(s.normal[np.isclose(x, 1.0) & (s.axis == 0), 0] == 1.0)
    assert np.all(s.normal[np.isclose(x, 0.0) & (s.axis == 0), 0] == -1.0)
    notch = (s.axis == 0) & np.isclose(x, 0.5)             # the step face of b, above a's top
    assert notch.any() and np.all(s.normal[notch, 0] == 1.0)
    top_of_a = (s.axis == 2) & np.isclose(facet_centre[:, 2], 0.5)
    assert top_of_a.any() and np.all(s.normal[top_of_a, 2] == 1.0)
