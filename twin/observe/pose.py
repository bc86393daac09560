"""Read-out at the pose of the measurement on the single reference-pose mesh: the moving body is
carried by the structure where its carriages sit *now*, not where they sat when the mesh was built.

The mesh holds every moving body at its axis's reference pose p_ref (:mod:`geometries.axes`). A
point fixed to a moving body (the workpiece on the table, the probe nest, the tool on the
carrier) is displaced, to first order, by the structure under the body's carriages plus the
body's own deformation. At pose p the carriages sit Delta = p - p_ref further along the rails, so
the body is carried by

    c(p) = (1/n) sum_i [u(s_i + Delta e) - u(s_i)]          (a rigid translation, [m])

more than on the mesh, s_i the n support points (the centres of the carriages' halves, on the
rail side of the rail/carriage interface), e the axis direction and u the structure's thermal
displacement. A reading q = (u_a - u_b) . d of two points a, b becomes
q(p) = q_ref + (m_a - m_b) c(p) . d, m_x = 1 when x moves with the axis (1 for each axis that
carries it: the table rides on X and Y). Tilts of the body (the rails' different expansion under
front and rear carriages) are not carried.

c(p) is linear in T for a fixed p, and p changes with time, so it is interpolated between pose
nodes p_k every :data:`POSE_SPACING` over the travel (through p_ref): c(p(t)) = sum_k phi_k(p(t))
c_k(t) with hat functions phi_k; each c_k is a point operator (rows) like any other displacement
read-out, and the weights phi_k(p(t)) come from the scenario's motion at the sampling instants.
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


class PoseCarry:
    """The carry c_k of every carried axis at its pose nodes, as displacement functionals, and
    their combination at the sampling instants (module docstring). ``points``: the observer's
    point names, to know which of them move with which axis."""

    def __init__(self, machine, points):
        self.axes = carried_axes(machine)
        parts = {p.name: p.part for p in machine.points}
        self.moves = np.array([[1.0 if parts[n] in a.moving else 0.0 for n in points] for a in self.axes]).reshape(
            len(self.axes), len(points))
        self.nodes = [pose_nodes(a) for a in self.axes]

    @property
    def nrows(self) -> int:
        return 3 * sum(len(n) for n in self.nodes)

    def functionals(self, mm) -> sp.csr_matrix:
        """Rows (axis, node, direction) of c_k . e_direction: the mean over the support points of
        the displacement at s_i + Delta_k minus that at s_i [m]."""
        blocks = []
        for a, nodes in zip(self.axes, self.nodes):
            s = support_points(mm.machine, a)
            e = _UNIT["xyz".index(a.direction)]
            at_ref = interpolation_matrix(mm, s, field="mesh")
            for p in nodes:
                P = interpolation_matrix(mm, s + (p - a.p_ref) * e, field="mesh") - at_ref
                mean = sp.csr_matrix(np.full((1, len(s)), 1.0 / len(s))) @ P
                blocks += [displacement_functional(mean, d) for d in _UNIT]
        return sp.vstack(blocks).tocsr() if blocks else sp.csr_matrix((0, 3 * mm.nnodes))

    def positions(self, times, scenario) -> np.ndarray:
        """(n_t, n_axes) each carried axis's commanded position [m] at ``times`` [s]."""
        from twin.effects.moving import motion_of
        t = np.asarray(times, float)
        return np.column_stack([motion_of(scenario, a).position(t) for a in self.axes]).reshape(len(t), len(self.axes))

    def carry(self, raw: np.ndarray, positions: np.ndarray) -> np.ndarray:
        """(n_t, n_axes, 3) the carry c(p) [m] of each axis at ``positions`` (n_t, n_axes) [m]
        (:meth:`positions`: where the axes are at each instant), from the raw readings (n_t,
        nrows) of :meth:`functionals`: each node's change since the first instant (the uniform
        start field, which displaces nothing), weighted by the hats phi_k(p)."""
        out = np.zeros((len(raw), len(self.axes), 3))
        i = 0
        for j, nodes in enumerate(self.nodes):
            block = raw[:, i:i + 3 * len(nodes)].reshape(len(raw), len(nodes), 3)
            block = block - block[:1]
            p = np.clip(positions[:, j], nodes[0], nodes[-1])
            out[:, j] = np.einsum("tk,tkd->td", hat(nodes, p), block)
            i += 3 * len(nodes)
        return out

    def correction(self, raw: np.ndarray, positions: np.ndarray, pairs) -> np.ndarray:
        """(n_t, len(pairs)) [m]: for each reading (a, b, direction) of ``pairs`` (indices into the
        observer's points, a unit direction), sum over axes (m_a - m_b) c(p) . direction, the axes
        at ``positions`` (n_t, n_axes) [m]."""
        c = self.carry(raw, positions)
        out = np.zeros((len(raw), len(pairs)))
        for n, (a, b, d) in enumerate(pairs):
            w = self.moves[:, a] - self.moves[:, b]          # (n_axes,)
            out[:, n] = np.einsum("j,tjd,d->t", w, c, np.asarray(d, float))
        return out
