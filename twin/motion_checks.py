"""Checks of commanded axis motions (:class:`twin.motion.Motion`): against the scenario's length
and an affordable number of pieces (:func:`check_durations`), piece by piece as a planned motion
moves (:func:`check_pieces`, for one built in Python) and against a machine's axes and travel
(:func:`check_motions`). Each bad value is one :class:`twin.errors.InputError` naming the axis."""

from __future__ import annotations

import numpy as np

from twin import limits
from twin.errors import InputError


def check_durations(motions, duration: float, source: str) -> None:
    """No axis moves beyond the scenario's ``duration`` [s], nor in more than
    :data:`twin.limits.MAX_MOTION_PIECES` pieces; both from the motions' closed-form plan, before
    any is built."""
    for i, m in enumerate(motions):
        if m.duration > duration + 1e-6:
            raise InputError(source, f"axis[{i}].move", f"axis {m.axis} moves for {m.duration:g} s, longer than "
                                                        f"the scenario ({duration:g} s of [[spindle]] steps)")
        if m.pieces > limits.MAX_MOTION_PIECES:
            raise InputError(source, f"axis[{i}].move", f"axis {m.axis} would move in {m.pieces:.3g} pieces of "
                                                        f"constant acceleration; at most {limits.MAX_MOTION_PIECES:.0e} "
                                                        "are affordable (fewer, longer strokes)")


def check_pieces(m, source: str, field: str) -> np.ndarray:
    """A motion's pieces as a planned one has them (for one built in Python): equal lengths, finite,
    positive durations from 0 s in order without overlap, the position continuous from piece to
    piece and into ``x_end``, speeds within :data:`twin.limits.MAX_FEED` and accelerations within
    :data:`twin.limits.MAX_ACCELERATION`. Returns every extreme position [m] it reaches (piece
    ends and the turning points inside pieces)."""
    pieces = [np.asarray(c, dtype=float).ravel() for c in (m.t0, m.dur, m.x0, m.v0, m.a)]
    if len({len(c) for c in pieces}) != 1:
        raise InputError(source, field, f"axis {m.axis}: t0, dur, x0, v0 and a need one value per piece each, got "
                                        f"{', '.join(str(len(c)) for c in pieces)}")
    t0, dur, x0, v0, a = pieces
    if not all(np.all(np.isfinite(c)) for c in pieces) or not np.isfinite(m.x_end):
        raise InputError(source, field, f"axis {m.axis}: a piece's time, position, velocity or acceleration is not "
                                        "finite")
    if np.any(dur <= 0) or np.any(t0 < 0) or np.any(t0[1:] < t0[:-1] + dur[:-1] - 1e-9):
        raise InputError(source, field, f"axis {m.axis}: pieces need positive durations, from 0 s on, in order "
                                        "without overlap")
    end = x0 + v0 * dur + 0.5 * a * dur ** 2
    jumps = np.abs(np.append(x0[1:], m.x_end) - end) if len(end) else np.zeros(0)
    if np.any(jumps > 1e-9):
        k = int(np.argmax(jumps > 1e-9))
        raise InputError(source, field, f"axis {m.axis} jumps by {jumps[k] * 1e3:g} mm after piece {k}: a position "
                                        "is continuous (each piece starts where the one before ends, x_end where the "
                                        "last ends)")
    for v in np.append(np.abs(v0), np.abs(v0 + a * dur)):
        limits.check_feed(float(v), source, field, f"axis {m.axis}'s speed")
    for value in np.abs(a):
        limits.check_acceleration(float(value), source, field)
    with np.errstate(divide="ignore", invalid="ignore"):
        turn = np.where(a != 0, -v0 / a, -1.0)
    inside = (turn > 0) & (turn < dur)
    return np.concatenate([x0, [m.x_end], (x0 + v0 * turn + 0.5 * a * turn ** 2)[inside]])


def check_motions(scenario, machine) -> None:
    """Every commanded axis exists on ``machine``, is commanded once, moves as a planned motion
    does (:func:`check_pieces`) and stays within its travel, turning points inside pieces
    included."""
    source = scenario.source or scenario.name
    names = [getattr(m, "axis", None) for m in getattr(scenario, "axes", ())]
    twice = sorted({n for n in names if names.count(n) > 1}, key=str)
    if twice:
        raise InputError(source, "axis", f"axis {twice[0]} is commanded twice: give one [[axis]] per axis")
    for i, m in enumerate(getattr(scenario, "axes", ())):
        try:
            axis = machine.axis(m.axis)
        except KeyError:
            known = ", ".join(a.name for a in machine.axes) or "none"
            raise InputError(source, f"axis[{i}].name", f"machine {machine.name} has no axis {m.axis!r}; "
                                                        f"its axes: {known}") from None
        lo, hi = axis.travel
        for field, written in getattr(m, "commanded", ()):      # what the user wrote, under its own name
            if not lo - 1e-9 <= written <= hi + 1e-9:
                raise InputError(source, field, f"{written * 1e3:g} mm is outside the {axis.name} travel "
                                                f"{lo * 1e3:g} .. {hi * 1e3:g} mm of {machine.name}")
        x = check_pieces(m, source, f"axis[{i}].move")
        bad = (x < lo - 1e-9) | (x > hi + 1e-9)
        if bad.any():
            raise InputError(source, f"axis[{i}].move", f"position {x[bad][0] * 1e3:g} mm is outside the {axis.name} "
                                                        f"travel {lo * 1e3:g} .. {hi * 1e3:g} mm of {machine.name}")
