"""Read-out at the pose of the measurement on the single reference-pose mesh: the moving body is
carried by the structure where its carriages sit *now*, not where they sat when the mesh was built.

The mesh holds every moving body at its axis's reference pose p_ref (:mod:`geometries.axes`). A
point fixed to a moving body (the workpiece on the table, the probe nest, the tool on the
carrier) is displaced, to first order, by the structure under the body's carriages plus the
body's own deformation. At pose p the carriages sit Delta = p - p_ref further along the rails, so
the support points s_i (the centres of the carriages' halves, on the rail side of the
rail/carriage interface; n of them) move by

    D_i(p) = u(s_i + Delta e) - u(s_i)                      ([m], u the structure's displacement)

more than on the mesh, e the axis direction. The body follows them as a rigid body: the
translation of their centroid s_c and the small rotation that fits them best,

    c(p) = (1/n) sum_i D_i,    theta(p) = M^-1 sum_i r_i x D_i,    M = sum_i (|r_i|^2 I - r_i r_i^T),

r_i = s_i - s_c (the least-squares theta of D_i - c = theta x r_i; the pseudo-inverse where the
points are collinear: no rotation about their line). A point x of the body then moves by
c + theta x (x - s_c): the rails' different expansion under the front and rear carriages pitches
and rolls the body, and a point high above the rails (the workpiece, the tool) feels it. A reading
q = (u_a - u_b) . d of two points a, b becomes

    q(p) = q_ref + sum_axes [m_a (c + theta x (x_a - s_c)) - m_b (c + theta x (x_b - s_c))] . d,

m_x = 1 when x moves with the axis (1 for each axis that carries it: the table rides on X and Y).
A bilinear field (u_z = k x y: the rails' rise growing along them and across them) moves the
supports rigidly, c = k Delta x_c e_z and theta = -k Delta e_y, and the body rolls with them:
exact on the mesh (tested).

c(p) and theta(p) are linear in T for a fixed p, and p changes with time, so they are interpolated
between pose nodes p_k every :data:`POSE_SPACING` over the travel (through p_ref): c(p(t)) =
sum_k phi_k(p(t)) c_k(t) with hat functions phi_k, theta alike; each c_k, theta_k is a point
operator (rows) like any other displacement read-out, and the weights phi_k(p(t)) come from the scenario's motion at the sampling instants.
Within a mesh cell the trilinear interpolation is linear along the axis, so the only
interpolation error is where a node spacing straddles a grid line.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from geometries.regions import InBox, Union, feed_drive_role
from twin.fem.points import displacement_functional, interpolation_matrix
from twin.motion import hat

POSE_SPACING = 0.02   # [m] between pose nodes
_UNIT = np.eye(3)


def carried_axes(machine) -> list:
    """The axes whose drive is in ``machine`` (its guideways and carriages declared): those a
    scenario moves (:func:`twin.motion.machine_for`). A body whose rails ride on it (a ram,
    ``screw_on_body``) is not carried: its blocks stand in the structure, so what changes with the
    pose is which stretch of the body is held, which this carry does not describe; it is read at
    the mesh's pose."""
    return [a for a in machine.axes if a.drive is not None and not a.screw_on_body
            and feed_drive_role(a.name, "carriages") in machine.roles]


def _boxes(region) -> list:
    regions = region.regions if isinstance(region, Union) else (region,)
    if not all(isinstance(r, InBox) for r in regions):
        raise ValueError("support points need rails and carriages given as boxes (InBox or a Union of them)")
    return [r.box for r in regions]


def support_points(machine, axis) -> np.ndarray:
    """(n, 3) [m] where ``axis``'s moving body rests on the structure at the mesh's pose: for each
    rail box and the carriage box beside it, the points at 1/4 and 3/4 of the carriage's length,
    its centre across, 1 mm on the rail side of their common face."""
    k = "xyz".index(axis.direction)
    rails = _boxes(machine.roles[feed_drive_role(axis.name, "guideways")])
    cars = _boxes(machine.roles[feed_drive_role(axis.name, "carriages")])
    out = []
    for c in cars:
        clo, chi = np.array(c.lo), np.array(c.hi)
        for r in rails:
            rlo, rhi = np.array(r.lo), np.array(r.hi)
            for j in (j for j in range(3) if j != k):
                other = [i for i in range(3) if i not in (j, k)][0]
                overlap = min(chi[other], rhi[other]) - max(clo[other], rlo[other])
                face, side = (rhi[j], -1.0) if abs(rhi[j] - clo[j]) < 1e-9 else (rlo[j], 1.0) if abs(rlo[j] - chi[j]) < 1e-9 else (None, 0)
                if face is None or overlap <= 0:
                    continue
                for f in (0.25, 0.75):
                    p = np.zeros(3)
                    p[k] = clo[k] + f * (chi[k] - clo[k])
                    p[other] = 0.5 * (max(clo[other], rlo[other]) + min(chi[other], rhi[other]))
                    p[j] = face + side * 1e-3
                    out.append(p)
    if not out:
        raise ValueError(f"axis {axis.name}: no carriage of {machine.name} rests on a rail (no common face)")
    return np.array(out)


def pose_nodes(axis, spacing: float = POSE_SPACING) -> np.ndarray:
    """Pose nodes [m] every ``spacing`` through ``axis.p_ref``, covering the travel."""
    lo, hi = axis.travel
    k0 = int(np.floor((lo - axis.p_ref) / spacing + 1e-9))
    k1 = int(np.ceil((hi - axis.p_ref) / spacing - 1e-9))
    return axis.p_ref + spacing * np.arange(k0, k1 + 1)


def rotation_weights(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(centroid s_c (3,), W (3, 3, n)) of support points (n, 3) [m]: the least-squares small
    rotation of displacements D (n, 3) about s_c is theta_a = sum_{b,i} W[a, b, i] D[i, b]
    (module docstring: theta = M^-1 sum_i r_i x D_i, pseudo-inverse)."""
    centre = points.mean(axis=0)
    r = points - centre
    M = sum(np.dot(v, v) * np.eye(3) - np.outer(v, v) for v in r)
    Minv = np.linalg.pinv(M, rcond=1e-9)
    cross = np.array([[[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]] for v in r])   # r x . (n, 3, 3)
    return centre, np.einsum("ac,icb->abi", Minv, cross)


class PoseCarry:
    """The carry c_k and rotation theta_k of every carried axis at its pose nodes, as displacement
    functionals, and their combination at the sampling instants (module docstring). ``points``:
    the observer's point names, to know which of them move with which axis and where they are."""

    def __init__(self, machine, points):
        self.axes = carried_axes(machine)
        parts = {p.name: p.part for p in machine.points}
        self.moves = np.array([[1.0 if parts[n] in a.moving else 0.0 for n in points] for a in self.axes]).reshape(
            len(self.axes), len(points))
        self.xyz = np.array([machine.point(n).xyz for n in points], float).reshape(len(points), 3)
        self.nodes = [pose_nodes(a) for a in self.axes]
        self.rotations = [rotation_weights(support_points(machine, a)) for a in self.axes]

    @property
    def nrows(self) -> int:
        return 6 * sum(len(n) for n in self.nodes)

    def functionals(self, mm) -> sp.csr_matrix:
        """Rows (axis, node, [c . e_x, c . e_y, c . e_z, theta_x, theta_y, theta_z]): the mean over
        the support points of the displacement at s_i + Delta_k minus that at s_i [m], and the
        least-squares rotation of those differences [rad]."""
        blocks = []
        for a, nodes, (_, W) in zip(self.axes, self.nodes, self.rotations):
            s = support_points(mm.machine, a)
            e = _UNIT["xyz".index(a.direction)]
            at_ref = interpolation_matrix(mm, s, field="mesh")
            for p in nodes:
                P = interpolation_matrix(mm, s + (p - a.p_ref) * e, field="mesh") - at_ref
                D = [displacement_functional(P, d) for d in _UNIT]          # (n, 3 n_nodes) per direction
                mean = sp.csr_matrix(np.full((1, len(s)), 1.0 / len(s)))
                blocks += [mean @ Db for Db in D]
                blocks += [sum(sp.csr_matrix(W[k, b][None, :]) @ D[b] for b in range(3)) for k in range(3)]
        return sp.vstack(blocks).tocsr() if blocks else sp.csr_matrix((0, 3 * mm.nnodes))

    def positions(self, times, scenario) -> np.ndarray:
        """(n_t, n_axes) each carried axis's commanded position [m] at ``times`` [s]."""
        from twin.effects.moving import motion_of
        t = np.asarray(times, float)
        return np.column_stack([motion_of(scenario, a).position(t) for a in self.axes]).reshape(len(t), len(self.axes))

    def motion(self, raw: np.ndarray, positions: np.ndarray) -> np.ndarray:
        """(n_t, n_axes, 6) the carry c(p) [m] and rotation theta(p) [rad] of each axis at
        ``positions`` (n_t, n_axes) [m] (:meth:`positions`: where the axes are at each instant),
        from the raw readings (n_t, nrows) of :meth:`functionals`: each node's change since the
        first instant (the uniform start field, which displaces nothing), weighted by the hats
        phi_k(p)."""
        out = np.zeros((len(raw), len(self.axes), 6))
        i = 0
        for j, nodes in enumerate(self.nodes):
            block = raw[:, i:i + 6 * len(nodes)].reshape(len(raw), len(nodes), 6)
            block = block - block[:1]
            p = np.clip(positions[:, j], nodes[0], nodes[-1])
            out[:, j] = np.einsum("tk,tkd->td", hat(nodes, p), block)
            i += 6 * len(nodes)
        return out

    def carry(self, raw: np.ndarray, positions: np.ndarray) -> np.ndarray:
        """(n_t, n_axes, 3) the translation c(p) [m] of :meth:`motion`."""
        return self.motion(raw, positions)[..., :3]

    def correction(self, raw: np.ndarray, positions: np.ndarray, pairs) -> np.ndarray:
        """(n_t, len(pairs)) [m]: for each reading (a, b, direction) of ``pairs`` (indices into the
        observer's points, a unit direction), sum over axes of
        [m_a (c + theta x (x_a - s_c)) - m_b (c + theta x (x_b - s_c))] . direction, the axes at
        ``positions`` (n_t, n_axes) [m]."""
        mo = self.motion(raw, positions)
        c, theta = mo[..., :3], mo[..., 3:]
        out = np.zeros((len(raw), len(pairs)))
        for n, (a, b, d) in enumerate(pairs):
            d = np.asarray(d, float)
            w = self.moves[:, a] - self.moves[:, b]          # (n_axes,)
            # (theta x r) . d = theta . (r x d), r the point's arm from the axis's support centroid
            arm = np.array([self.moves[j, a] * np.cross(self.xyz[a] - centre, d)
                            - self.moves[j, b] * np.cross(self.xyz[b] - centre, d)
                            for j, (centre, _) in enumerate(self.rotations)]).reshape(len(self.axes), 3)
            out[:, n] = np.einsum("j,tjd,d->t", w, c, d) + np.einsum("tjd,jd->t", theta, arm)
        return out
