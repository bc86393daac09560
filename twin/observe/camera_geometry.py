"""A thermal camera's geometry: the pinhole model, one ray per pixel (a few at edges), and the
pixel operator on the temperature field.

Camera frame: forward f = (target - position) / |.|, right r = f x up / |.|, down d = f x r. Pixel
(u, v) (column u = 0..W-1 left to right, row v = 0..H-1 top to bottom) covers [u, u+1) x [v, v+1)
of the image plane at unit distance, with the pixel pitch s_u = 2 tan(FOV_h / 2) / W,
s_v = 2 tan(FOV_v / 2) / H. A point X projects (pinhole) to

    u = W/2 + ((X - C) . r) / (((X - C) . f) s_u),    v = H/2 + ((X - C) . d) / (((X - C) . f) s_v),

and lands on pixel (floor u, floor v). The ray of a pixel goes from C through its centre.

A pixel integrates a square footprint of angular side IFOV (the detector's instantaneous field
of view, 1.5 mrad on the S65: larger than its 1.31 mrad pitch); at distance d the footprint is
IFOV x d across. Where the scene changes inside a pixel (an edge between parts, faces or the
room), the pixel is sampled by n x n rays at the midpoints of its footprint (offsets
IFOV ((k + 1/2)/n - 1/2) along r_c and d_c, the tangent directions at its centre ray c); else by
its centre ray.

The view (:func:`view_machine`) is built once per pose and mesh: the first hit of every ray on
the outer surface (:mod:`twin.observe.raycast`, exact occlusion), the facet, the part, the point,
the depth, the view angle and the emissivity (:class:`geometries.base.Finish`). The temperature of
a hit is the trilinear field of its facet's cell at the hit point (bilinear on the facet), so the
rows of the hitting rays on a temperature layout are a sparse matrix with 8 entries per row
(:func:`temperature_rows`), built once per layout by the prepared twin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from geometries.finishes import DEFAULT
from twin.fem.elements import shape_q1
from twin.observe.raycast import cast, outer_surface
from twin.units import clean


@dataclass(frozen=True)
class Intrinsics:
    """Resolution ``width`` x ``height`` [px], field of view ``fov_h`` x ``fov_v`` [rad] and IFOV
    [rad]. Defaults: FLIR ThermaCAM S65 (seed 001 Table 1): 320 x 240, 24 x 18 deg, 1.5 mrad."""

    width: int = 320
    height: int = 240
    fov_h: float = math.radians(24.0)
    fov_v: float = math.radians(18.0)
    ifov: float = 1.5e-3

    @property
    def pitch(self) -> tuple[float, float]:
        """(s_u, s_v): the pixel pitch on the image plane at unit distance [-]."""
        return 2 * math.tan(self.fov_h / 2) / self.width, 2 * math.tan(self.fov_v / 2) / self.height

    @property
    def shape(self) -> tuple[int, int]:
        return self.height, self.width

    def as_dict(self) -> dict:
        return {"width_px": self.width, "height_px": self.height, "fov_h_deg": clean(math.degrees(self.fov_h)),
                "fov_v_deg": clean(math.degrees(self.fov_v)), "ifov_mrad": clean(self.ifov * 1e3)}


def camera_frame(position, target, up) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(right, down, forward) unit vectors of a camera at ``position`` aimed at ``target``."""
    f = np.subtract(target, position).astype(float)
    f /= np.linalg.norm(f)
    r = np.cross(f, up)
    if np.linalg.norm(r) < 1e-9:
        raise ValueError("the camera's up vector is parallel to its line of sight")
    r /= np.linalg.norm(r)
    return r, np.cross(f, r), f


def project(pose, intr: Intrinsics, xyz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Continuous image coordinates (u, v) of points (n, 3) [m] (pinhole; module docstring)."""
    r, d, f = camera_frame(pose.position, pose.target, pose.up)
    c = np.atleast_2d(xyz) - np.asarray(pose.position, dtype=float)
    su, sv = intr.pitch
    z = c @ f
    return intr.width / 2 + (c @ r) / (z * su), intr.height / 2 + (c @ d) / (z * sv)


def pixel_directions(pose, intr: Intrinsics, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Unit directions (n, 3) of the rays through the centres of pixels (u, v) (integer arrays)."""
    r, d, f = camera_frame(pose.position, pose.target, pose.up)
    su, sv = intr.pitch
    a = (np.asarray(u) + 0.5 - intr.width / 2) * su
    b = (np.asarray(v) + 0.5 - intr.height / 2) * sv
    dirs = f[None, :] + a[:, None] * r[None, :] + b[:, None] * d[None, :]
    return dirs / np.linalg.norm(dirs, axis=1, keepdims=True)


def footprint_directions(centre: np.ndarray, right: np.ndarray, ifov: float, n: int) -> np.ndarray:
    """(len(centre) * n * n, 3) unit directions at the midpoints of an n x n split of each pixel's
    IFOV x IFOV footprint around its centre ray (rows of ``centre``); pixel-major order."""
    rc = right[None, :] - (centre @ right)[:, None] * centre
    rc /= np.linalg.norm(rc, axis=1, keepdims=True)
    dc = np.cross(centre, rc)
    k = ifov * ((np.arange(n) + 0.5) / n - 0.5)
    a, b = np.meshgrid(k, k, indexing="xy")
    dirs = (centre[:, None, :] + a.ravel()[None, :, None] * rc[:, None, :] + b.ravel()[None, :, None] * dc[:, None, :])
    dirs = dirs.reshape(-1, 3)
    return dirs / np.linalg.norm(dirs, axis=1, keepdims=True)


@dataclass
class View:
    """What one camera pose sees of one mesh, per ray and per pixel (layout independent).

    Rays: ``ray_pixel`` (flat pixel index v * W + u), ``ray_weight`` (1 / rays of its pixel),
    ``ray_facet`` (index into ``surface``'s facets, -1: the room), ``ray_point`` [m],
    ``ray_depth`` [m], ``ray_emissivity``. Pixel layers (H, W), of the centre ray: ``part`` (index
    into ``part_names``, -1: the room), ``facet`` (mesh facet id, -1), ``depth`` [m] (nan),
    ``view_angle`` [deg] between the ray and the surface normal (nan); ``coverage``: the share of
    the pixel's rays that hit the machine; ``emissivity``: the mean over those rays (nan: none).
    """

    intrinsics: Intrinsics
    surface: object
    part_names: list
    ray_pixel: np.ndarray
    ray_weight: np.ndarray
    ray_facet: np.ndarray
    ray_point: np.ndarray
    ray_depth: np.ndarray
    ray_emissivity: np.ndarray
    part: np.ndarray
    facet: np.ndarray
    depth: np.ndarray
    view_angle: np.ndarray
    coverage: np.ndarray
    emissivity: np.ndarray

    @property
    def hit(self) -> np.ndarray:
        """Indices of the rays that hit the machine (the rows of :func:`temperature_rows`)."""
        return np.flatnonzero(self.ray_facet >= 0)

    def pixel_sum(self, rays: np.ndarray) -> sp.csr_matrix:
        """(n_pixels, len(rays)) weights summing the given rays into their pixels."""
        n_pix = self.intrinsics.width * self.intrinsics.height
        return sp.csr_matrix((self.ray_weight[rays], (self.ray_pixel[rays], np.arange(len(rays)))),
                             shape=(n_pix, len(rays)))

    @property
    def room_weight(self) -> np.ndarray:
        """(n_pixels,) the share of each pixel's rays that see the room."""
        return 1.0 - self.coverage.ravel()


def view_machine(mm, machine, pose, intr: Intrinsics, edge_rays: int = 3, backend: str = "auto") -> View:
    """Cast the camera's rays at the outer surface of ``mm`` and build the :class:`View`;
    ``edge_rays`` n > 1 resamples pixels at edges with n x n footprint rays."""
    position = np.asarray(pose.position, dtype=float)
    _check_outside(machine, position)
    surface = outer_surface(mm)
    H, W = intr.shape
    vv, uu = np.meshgrid(np.arange(H), np.arange(W), indexing="ij")
    centre = pixel_directions(pose, intr, uu.ravel(), vv.ravel())
    hits = cast(surface, position, centre, backend)
    part = np.where(hits.index >= 0, mm.cell_part[surface.owner[np.maximum(hits.index, 0)]], -1)
    normal_id = np.where(hits.index >= 0, surface.axis[np.maximum(hits.index, 0)] * 2
                         + (surface.normal[np.maximum(hits.index, 0)].sum(axis=1) > 0), -1)
    edge = _edges(part.reshape(H, W), normal_id.reshape(H, W), hits.distance.reshape(H, W)).ravel()
    n = max(1, int(edge_rays))
    fine = np.flatnonzero(edge) if n > 1 else np.zeros(0, dtype=int)
    coarse = np.setdiff1d(np.arange(H * W), fine)
    if len(fine):
        right = camera_frame(pose.position, pose.target, pose.up)[0]
        sub = footprint_directions(centre[fine], right, intr.ifov, n)
        sub_hits = cast(surface, position, sub, backend)
    else:
        sub_hits = cast(surface, position, np.zeros((0, 3)) + [0.0, 0.0, 1.0], "grid")
    ray_pixel = np.concatenate([coarse, np.repeat(fine, n * n)])
    ray_weight = np.concatenate([np.ones(len(coarse)), np.full(len(fine) * n * n, 1.0 / (n * n))])
    ray_facet = np.concatenate([hits.index[coarse], sub_hits.index])
    ray_point = np.concatenate([hits.point[coarse], sub_hits.point])
    ray_depth = np.concatenate([hits.distance[coarse], sub_hits.distance])
    ray_part = np.where(ray_facet >= 0, mm.cell_part[surface.owner[np.maximum(ray_facet, 0)]], -1)
    ray_eps = surface_emissivity(machine, mm.part_names, ray_part, ray_point)
    hit = ray_facet >= 0
    coverage = np.bincount(ray_pixel, weights=ray_weight * hit, minlength=H * W)
    eps_sum = np.bincount(ray_pixel, weights=ray_weight * np.where(hit, ray_eps, 0.0), minlength=H * W)
    with np.errstate(invalid="ignore", divide="ignore"):
        emissivity = np.where(coverage > 0, eps_sum / coverage, np.nan)
        normal = surface.normal[np.maximum(hits.index, 0)]
        cosine = np.abs(np.einsum("ij,ij->i", normal, centre))
    angle = np.where(hits.index >= 0, np.degrees(np.arccos(np.clip(cosine, 0.0, 1.0))), np.nan)
    return View(intr, surface, list(mm.part_names), ray_pixel, ray_weight, ray_facet, ray_point,
                np.where(hit, ray_depth, np.nan), ray_eps, part.reshape(H, W).astype(np.int16),
                np.where(hits.index >= 0, surface.facets[np.maximum(hits.index, 0)], -1).reshape(H, W),
                np.where(hits.index >= 0, hits.distance, np.nan).reshape(H, W), angle.reshape(H, W),
                coverage.reshape(H, W), emissivity.reshape(H, W))


def _check_outside(machine, position: np.ndarray) -> None:
    for part in machine.parts:
        for box in part.boxes:
            if box.contains(position[None, :])[0]:
                raise ValueError(f"the camera at {tuple(np.round(position, 3))} m is inside part {part.name!r}")


def _edges(part: np.ndarray, normal_id: np.ndarray, depth: np.ndarray, jump: float = 0.02) -> np.ndarray:
    """Pixels whose 4-neighbours see another part, another face orientation, the room, or a
    surface more than ``jump`` (relative) nearer or farther."""
    edge = np.zeros(part.shape, bool)
    d = np.where(np.isfinite(depth), depth, 1e30)
    for axis in (0, 1):
        a = [slice(None)] * 2
        b = [slice(None)] * 2
        a[axis], b[axis] = slice(1, None), slice(None, -1)
        a, b = tuple(a), tuple(b)
        diff = ((part[a] != part[b]) | (normal_id[a] != normal_id[b])
                | (np.abs(d[a] - d[b]) > jump * np.minimum(d[a], d[b])))
        edge[a] |= diff
        edge[b] |= diff
    return edge


def surface_emissivity(machine, part_names: list, part: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Emissivity of hits on parts ``part`` (indices into ``part_names``, -1: none) at ``point``
    [m]: the last of the machine's finishes covering the part (and the point, for a patch), else
    :data:`geometries.finishes.DEFAULT`."""
    eps = np.full(len(part), DEFAULT.value)
    for finish in machine.finishes:
        ids = [part_names.index(p) for p in finish.parts if p in part_names]
        on = np.isin(part, ids)
        if finish.within is not None:
            on &= finish.within.contains(point, tol=1e-6)
        eps[on] = finish.emissivity.value
    return eps


def temperature_rows(view: View, layout) -> sp.csr_matrix:
    """(n_hit_rays, layout.nheat): the temperature at each hitting ray's point, trilinear in the
    cell that owns its facet (temperature dofs of ``layout``, split or not)."""
    rays = view.hit
    cells = view.surface.owner[view.ray_facet[rays]]
    mesh = layout.mesh
    lo = mesh.p[:, mesh.t[0, cells]].T
    hi = mesh.p[:, mesh.t[7, cells]].T
    xi = np.clip(2.0 * (view.ray_point[rays] - lo) / (hi - lo) - 1.0, -1.0, 1.0)
    n, _ = shape_q1(xi)
    rows = np.repeat(np.arange(len(rays)), 8)
    return sp.csr_matrix((n.ravel(), (rows, layout.heat_t[:, cells].T.ravel())), shape=(len(rays), layout.nheat))
