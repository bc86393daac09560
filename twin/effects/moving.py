"""Heat that moves with an axis, as fixed patterns times schedule weights (a path basis).

A source releasing q(t) [W] at the moving coordinate y(t) (a ball nut on its screw, a carriage on
its rail) is written sum_i phi_i(y(t)) q(t) with hat functions phi_i on nodes s_i along the path
(:func:`twin.motion.path_weights`); node i's heat goes into the cells of the mesh slab (across the
axis) that holds s_i, so each node is a fixed :class:`HeatSource` and its weight a scalar signal.
The loads stay linear, the patterns are assembled once, one factorisation serves every step,
and the diagnosis's signatures stay exact. Weights are step averages, held on each time step
(:func:`twin.motion.step_signal`): the heat a step receives is exactly the integral of q over it.

Heat that arises in a moving *body* at a place fixed to it (the nut housing, the carriages) is a
stationary pattern on the mesh, whose pose is the body's reference pose (:mod:`geometries.axes`).
"""

from __future__ import annotations

import numpy as np

from twin.effects.base import HeatSource
from twin.fem.regions import cell_centres, role_cells
from twin.motion import Motion, hat_integral, path_nodes, path_weights, step_signal

PATH_SPACING = 0.01   # [m] between path-basis nodes (finer than any mesh's cells along the axis)
REFERENCE_FEED = 0.02   # [m/s] the feed at which the speed-proportional powers are given (seed 003)
REFERENCE_ACCELERATION = 1.0   # [m/s2] the acceleration at which inertia losses are given


def motion_of(scenario, axis) -> Motion:
    """The scenario's motion of ``axis``; an axis the scenario does not command stands at the
    mesh's pose (``axis.p_ref``)."""
    for m in getattr(scenario, "axes", ()):
        if m.axis == axis.name:
            return m
    empty = np.zeros(0)
    return Motion(axis.name, empty, empty, empty, empty, empty, x_end=axis.p_ref)


def step_edges(scenario) -> np.ndarray:
    """The scenario's time steps' edges [s]."""
    return scenario.times()


def speed_signal(scenario, motion: Motion, scale: float):
    """Signal scale * (mean |v| over each time step) [W when scale is W s/m]: the travelled
    distance per step, exact."""
    edges = step_edges(scenario)
    nodes = np.array([motion.positions.min() - 1.0, motion.positions.max() + 1.0])  # one wide hat pair: sum 1
    w = path_weights(motion, nodes, edges, "distance").sum(axis=1)
    return step_signal(scale * w, scenario.sample_interval)


def acceleration_signal(scenario, motion: Motion, scale: float):
    """Signal scale * (mean a(t)^2 over each time step) [W when scale is W s^4/m^2], exact
    (:meth:`twin.motion.Motion.squared_acceleration_integral`)."""
    edges = step_edges(scenario)
    mean = np.diff(motion.squared_acceleration_integral(edges)) / np.diff(edges)
    return step_signal(scale * mean, scenario.sample_interval)


def travelling_sources(label: str, mm, role: str, axis, motion: Motion, scenario, scale: float, per: str,
                       offsets=(0.0,), spacing: float = PATH_SPACING) -> list[HeatSource]:
    """Path-basis sources of a heat q = scale * (|v| when ``per="distance"``, 1 when ``"time"``)
    [W] released in the cells of ``role`` at the machine coordinate of the nut plus each of
    ``offsets`` [m] (q split equally among them, e.g. two carriages).

    Nodes s_i every ``spacing`` over the axis travel; node i's heat is spread along the axis as its
    hat phi_i (restricted to the travel, normalised) and each mesh slab of the role's cells takes
    the share of the hat that lies over it: slab j receives sum_i w_i(t) O_ij with
    O_ij = int_slab_j phi_i / int phi_i, so a nut passing at constant speed heats every slab in
    proportion to its length, exactly, and the total is q exactly."""
    cells = role_cells(mm, role)
    d = "xyz".index(axis.direction)
    centre = cell_centres(mm, cells)[:, d]
    lines = np.unique(np.round(mm.mesh.p[d, mm.mesh.t[:, cells]].ravel(), 12))
    lo, hi = axis.travel
    nodes = path_nodes(lo, hi, spacing)
    w = path_weights(motion, nodes, step_edges(scenario), per) * (scale / len(offsets))
    total = np.zeros((w.shape[0], len(lines) - 1))
    ends = np.sort(axis.nut_coordinate(np.array([lo, hi])))      # a screw on the body runs the other way
    flip = slice(None, None, -1) if axis.nut_coordinate(hi) < axis.nut_coordinate(lo) else slice(None)
    for off in offsets:
        s = axis.nut_coordinate(nodes)[flip] + off                       # increasing
        a = np.maximum(lines[:-1], ends[0] + off)
        b = np.maximum(np.minimum(lines[1:], ends[1] + off), a)
        overlap = (hat_integral(s, b) - hat_integral(s, a)).T[flip]    # (nodes, slabs), nodes in path order
        s = s[flip]
        inside = overlap.sum(axis=1)
        for i in np.flatnonzero(inside <= 0):    # a node beyond the role's cells: the nearest slab
            overlap[i, np.clip(np.searchsorted(lines, s[i]) - 1, 0, len(lines) - 2)] = 1.0
        total += w @ (overlap / overlap.sum(axis=1, keepdims=True))
    out = []
    for j in np.flatnonzero(np.abs(total).sum(axis=0) > 0):
        mine = cells[(centre > lines[j]) & (centre < lines[j + 1])]
        if len(mine) == 0:
            raise ValueError(f"{label}: role {role!r} has no cells between {lines[j]:g} and {lines[j + 1]:g} m")
        out.append(HeatSource(f"{label}@{0.5 * (lines[j] + lines[j + 1]) * 1e3:.0f}mm", mine,
                              step_signal(total[:, j], scenario.sample_interval)))
    return out
