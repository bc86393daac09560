"""Axis motion: what each linear axis does over a scenario, and the path-basis weights of the
heat that travels with it.

A scenario commands an axis with an ``[[axis]]`` table and its moves, in order::

    [[axis]]
    name = "Y"                       # an axis the machine declares (geometries.axes.LinearAxis)
    start = "0 mm"                   # optional: default, where the first move starts

    [[axis.move]]                    # trapezoidal to-and-fro between two positions
    kind = "reciprocate"
    between = ["0 mm", "280 mm"]
    feed = "20 mm/s"
    acceleration = "10 mm/s2"
    dwell = "0 s"                    # optional, at each end
    duration = "390 min"             # or count = 100 (whole strokes, one way each)

    [[axis.move]]
    kind = "hold"                    # position = "140 mm", duration = "10 min"
    # kind = "move"                  # to, feed, acceleration; optional duration (holds on arrival)
    # kind = "table"                 # times = ["0 s", ...], positions = ["0 mm", ...] (linear)

Every value carries its unit; a zero or negative feed, acceleration or duration, a move that does
not start where the axis is, a table whose times do not increase, and an axis running longer
than the scenario are :class:`twin.errors.InputError` naming the file and the key. An unknown
axis or a position outside the axis travel is refused against a machine
(:func:`check_motions`). A reciprocation given a duration runs the whole strokes that fit in it
and dwells at its last end for the rest; after its last move an axis holds where it is.

A motion is a list of pieces of constant acceleration (x = x0 + v0 tau + a tau^2 / 2), within
each of which the axis moves one way only. :func:`path_weights` turns it into the weights of a
*path basis*: heat q(t) released at the moving position x(t) is sum_i phi_i(x(t)) q(t) with
phi_i the hat functions on nodes s_i along the path (sum_i phi_i = 1 on the path), so a moving
source is a sum of fixed patterns times scalar signals and the heat equation stays linear.
"""

from __future__ import annotations

import numpy as np

from twin import limits
from twin.errors import InputError, describe
from twin.io.table_reader import TableReader
from twin.motion_checks import check_motions
from twin.units import UnitError, parse_quantity

KINDS = ("hold", "move", "reciprocate", "table")


class Motion:
    """One axis's motion: pieces starting at ``t0`` [s], lasting ``dur`` [s], from ``x0`` [m] at
    velocity ``v0`` [m/s] with constant acceleration ``a`` [m/s2]; holds ``x_end`` after them.

    A motion read from a scenario (:func:`motions_from_toml`) is *planned*: its duration, end and
    number of pieces are known in closed form and its pieces are built on first use, so a motion
    longer than the scenario (or too large to afford) is refused (:func:`check_durations`)
    before anything is built."""

    def __init__(self, axis: str, t0, dur, x0, v0, a, x_end: float, source: str = ""):
        self.axis, self.x_end, self.source, self.commanded = axis, float(x_end), source, ()
        self._pieces = tuple(np.asarray(c, dtype=float) for c in (t0, dur, x0, v0, a))
        self._build, self._duration, self._count = None, None, len(self._pieces[0])

    @classmethod
    def planned(cls, axis: str, x_end: float, duration: float, pieces: int, build, source: str = "",
                commanded: tuple = ()) -> "Motion":
        """A motion of ``duration`` [s] ending at ``x_end`` [m] in at most ``pieces`` pieces, which
        ``build()`` returns as (t0, dur, x0, v0, a) when first asked for. ``commanded``: the
        positions the scenario wrote, (field, position [m]) each, checked against a machine's
        travel under their own names (:func:`twin.motion_checks.check_motions`)."""
        m = cls.__new__(cls)
        m.axis, m.x_end, m.source, m.commanded = axis, float(x_end), source, tuple(commanded)
        m._pieces, m._build, m._duration, m._count = None, build, float(duration), int(pieces)
        return m

    def _built(self) -> tuple:
        if self._pieces is None:
            self._pieces = tuple(np.asarray(c, dtype=float) for c in self._build())
            self._build = None
        return self._pieces

    t0 = property(lambda self: self._built()[0])
    dur = property(lambda self: self._built()[1])
    x0 = property(lambda self: self._built()[2])
    v0 = property(lambda self: self._built()[3])
    a = property(lambda self: self._built()[4])

    @property
    def pieces(self) -> int:
        """The number of pieces (an upper bound while the motion is not built)."""
        return self._count if self._pieces is None else len(self._pieces[0])

    def __reduce__(self):   # a planned motion pickles built (its build is a closure)
        return (Motion, (self.axis, *self._built(), self.x_end, self.source))

    def __repr__(self) -> str:
        return f"Motion(axis={self.axis!r}, duration={self.duration:g} s, x_end={self.x_end:g} m)"

    @property
    def duration(self) -> float:
        """End of the last piece [s]."""
        if self._pieces is None:
            return self._duration
        t0, dur = self._pieces[:2]
        return float(t0[-1] + dur[-1]) if len(t0) else 0.0

    @property
    def positions(self) -> np.ndarray:
        """Every position [m] the axis passes through at a piece boundary (its extremes)."""
        return np.append(self.x0, self.x_end)

    def _at(self, t: np.ndarray):
        t = np.asarray(t, dtype=float)
        if not len(self.t0):
            return None, None, t
        i = np.clip(np.searchsorted(self.t0, t, side="right") - 1, 0, len(self.t0) - 1)
        tau = np.clip(t - self.t0[i], 0.0, self.dur[i])
        return i, tau, t

    def _inside(self, i: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Whether each time t lies within its piece i (not before the first, after the last, or
        in a gap)."""
        return (t >= self.t0[i]) & (t < self.t0[i] + self.dur[i])

    def position(self, t) -> np.ndarray:
        """Position [m] at times t [s] (the start position before 0, the end after the last piece)."""
        i, tau, t = self._at(t)
        if i is None:
            return np.full(t.shape, self.x_end)
        return self.x0[i] + self.v0[i] * tau + 0.5 * self.a[i] * tau ** 2

    def velocity(self, t) -> np.ndarray:
        """Velocity [m/s] at times t [s] (0 outside the pieces)."""
        i, tau, t = self._at(t)
        if i is None:
            return np.zeros(t.shape)
        return np.where(self._inside(i, t), self.v0[i] + self.a[i] * tau, 0.0)

    def acceleration(self, t) -> np.ndarray:
        """Acceleration [m/s2] at times t [s] (0 outside the pieces)."""
        i, tau, t = self._at(t)
        if i is None:
            return np.zeros(t.shape)
        return np.where(self._inside(i, t), self.a[i], 0.0)

    def squared_acceleration_integral(self, t) -> np.ndarray:
        """int_0^t a(s)^2 ds [m2/s3] at times t [s], exact: a is constant on each piece, so the
        integral is the full pieces before t plus a_i^2 times the part of piece i up to t."""
        i, tau, t = self._at(t)
        if i is None:
            return np.zeros(t.shape)
        a2 = self.a ** 2
        before = np.concatenate([[0.0], np.cumsum(a2 * self.dur)[:-1]])
        return before[i] + a2[i] * tau


class _Builder:
    """Appends pieces while tracking time and position."""

    def __init__(self, axis: str, x: float, source: str):
        self.axis, self.x, self.t, self.source = axis, x, 0.0, source
        self.rows: list[tuple[float, float, float, float, float]] = []

    def piece(self, dur: float, v0: float, a: float) -> None:
        if dur > 0:
            self.rows.append((self.t, dur, self.x, v0, a))
            self.t += dur
            self.x += v0 * dur + 0.5 * a * dur ** 2

    def polyline(self, times: np.ndarray, xs: np.ndarray) -> None:
        """Through positions ``xs`` [m] at ``times`` [s] after now, linearly (constant velocity)."""
        for dt, x0, x1 in zip(np.diff(times), xs[:-1], xs[1:]):
            self.piece(dt, (x1 - x0) / dt, 0.0)
            self.x = x1

    def hold(self, dur: float) -> None:
        self.piece(dur, 0.0, 0.0)

    def trapezoid(self, target: float, feed: float, accel: float) -> None:
        """A point-to-point move to ``target`` [m]: accelerate at ``accel``, cruise at ``feed``,
        decelerate (triangular when the distance is shorter than feed^2 / accel)."""
        d = target - self.x
        s, d = np.sign(d), abs(d)
        if d == 0:
            return
        if d >= feed ** 2 / accel:
            ta, tc = feed / accel, (d - feed ** 2 / accel) / feed
            self.piece(ta, 0.0, s * accel)
            self.piece(tc, s * feed, 0.0)
            self.piece(ta, s * feed, -s * accel)
        else:
            tp = np.sqrt(d / accel)
            self.piece(tp, 0.0, s * accel)
            self.piece(tp, s * accel * tp, -s * accel)
        self.x = target   # no round-off drift over thousands of strokes

    def pieces(self) -> tuple:
        """The pieces so far as (t0, dur, x0, v0, a)."""
        return tuple(np.array(self.rows, dtype=float).reshape(-1, 5).T)

    def motion(self) -> Motion:
        return Motion(self.axis, *self.pieces(), x_end=self.x, source=self.source)


def logged_motion(axis: str, times, positions, source: str = "") -> Motion:
    """The motion through logged ``positions`` [m] at ``times`` [s] (from 0, increasing),
    linear between samples: what a measurement's ``axis_position`` column drives."""
    times, positions = np.asarray(times, float), np.asarray(positions, float)
    b = _Builder(axis, float(positions[0]), source)
    b.polyline(times - times[0], positions)
    return b.motion()


def stroke_time(distance: float, feed: float, accel: float) -> float:
    """Duration [s] of a trapezoidal move over ``distance`` [m]: d / v + v / a when the feed is
    reached (d >= v^2 / a), else 2 sqrt(d / a)."""
    d = abs(distance)
    return d / feed + feed / accel if d >= feed ** 2 / accel else 2.0 * np.sqrt(d / accel)


def motions_from_toml(raw, source: str) -> tuple[Motion, ...]:
    """The ``[[axis]]`` tables of a scenario (``raw``: None or a list of tables) as motions."""
    if raw is None:
        return ()
    if not isinstance(raw, list) or not raw:
        raise InputError(source, "axis", "expected one or more [[axis]] tables")
    out, names = [], set()
    for i, table in enumerate(raw):
        r = TableReader(table, source, f"axis[{i}].", known=("name", "start", "move"))
        name = r.get("name", required=True)
        if not isinstance(name, str) or not name:
            raise InputError(source, f"axis[{i}].name", "expected an axis name such as \"Y\"")
        if name in names:
            raise InputError(source, f"axis[{i}].name", f"axis {name} is commanded twice; give it one [[axis]] table")
        names.add(name)
        start = r.get("start", "length")
        moves = r.get("move", required=True)
        r.finish()
        if not isinstance(moves, list) or not moves:
            raise InputError(source, f"axis[{i}].move", "expected one or more [[axis.move]] tables")
        out.append(_motion(name, start, moves, source, f"axis[{i}].move"))
    return tuple(out)


def _motion(name: str, start, moves: list, source: str, prefix: str) -> Motion:
    """One axis's moves, checked and planned in closed form (duration, end, pieces: no time or
    memory in proportion to a count of strokes); the pieces are built on first use."""
    x = t = None
    runs, pieces = [], 0
    commanded = [] if start is None else [(prefix.rsplit(".", 1)[0] + ".start", start)]
    for j, raw in enumerate(moves):
        r = TableReader(raw, source, f"{prefix}[{j}].", known=("kind",) + tuple(k for ks in MOVE_KEYS.values() for k in ks))
        kind = r.get("kind", required=True)
        if not isinstance(kind, str) or kind not in KINDS:
            raise InputError(source, f"{prefix}[{j}].kind", f"unknown kind {describe(kind)}; known: {', '.join(KINDS)}")
        r.expect("kind", *MOVE_KEYS[kind])
        begin, run, plan, written = _MOVES[kind](r, source)
        commanded += [(f"{prefix}[{j}].{key}", float(v)) for key, v in written]
        r.finish()
        if x is None:
            if begin is None and start is None:
                raise InputError(source, f"{prefix}[{j}]", "a first move of kind 'move' needs the axis's start")
            x0 = x = start if start is not None else begin
            t = 0.0
        if begin is not None and abs(begin - x) > 1e-9:
            raise InputError(source, f"{prefix}[{j}]", f"starts at {begin * 1e3:g} mm but axis {name} is at "
                                                       f"{x * 1e3:g} mm there; add a move")
        dur, x, n = plan(x)
        t += dur
        pieces += n
        runs.append(run)

    def build():
        b = _Builder(name, x0, source)
        for run in runs:
            run(b)
        return b.pieces()
    return Motion.planned(name, x, t, pieces, build, source, tuple(commanded))


def _positive(r, key: str, dimension: str) -> float:
    return r.positive(key, dimension, required=True)


def _feed_accel(r) -> tuple[float, float]:
    """A move's ``feed`` [m/s] and ``acceleration`` [m/s2]: positive and within
    :data:`twin.limits.MAX_FEED` and :data:`twin.limits.MAX_ACCELERATION`."""
    feed = limits.check_feed(_positive(r, "feed", "velocity"), r.source, r.prefix + "feed")
    accel = limits.check_acceleration(_positive(r, "acceleration", "acceleration"), r.source, r.prefix + "acceleration")
    return feed, accel


def _hold(r, source):
    x = r.get("position", "length", required=True)
    dur = _positive(r, "duration", "time")
    return x, lambda b: b.hold(dur), lambda x0: (dur, x0, 1), [("position", x)]


def _move(r, source):
    to = r.get("to", "length", required=True)
    feed, accel = _feed_accel(r)
    dur = r.positive("duration", "time")

    def plan(x):
        need = stroke_time(to - x, feed, accel)
        if dur is not None and dur < need - 1e-9:
            raise InputError(source, r.prefix + "duration", f"the move takes {need:g} s, longer than the duration")
        return (need if dur is None else dur), to, 4

    def run(b):
        need = stroke_time(to - b.x, feed, accel)
        b.trapezoid(to, feed, accel)
        if dur is not None:
            b.hold(dur - need)
    return None, run, plan, [("to", to)]


def _reciprocate(r, source):
    ends = r.get("between", required=True)
    if not isinstance(ends, list) or len(ends) != 2:
        raise InputError(source, r.prefix + "between", "expected two positions, e.g. [\"0 mm\", \"280 mm\"]")
    try:
        a, c = (parse_quantity(e, "length") for e in ends)
    except UnitError as err:
        raise InputError(source, r.prefix + "between", str(err)) from None
    if a == c:
        raise InputError(source, r.prefix + "between", "the two ends must differ")
    feed, accel = _feed_accel(r)
    dwell = r.get("dwell", "time", default=0.0)
    if dwell < 0:
        raise InputError(source, r.prefix + "dwell", "must not be negative")
    dur, count = r.positive("duration", "time"), r.get("count")
    if (dur is None) == (count is None):
        r.missing("duration", "give exactly one of duration and count")
    period = stroke_time(c - a, feed, accel) + dwell
    if count is not None:
        if isinstance(count, bool) or not isinstance(count, int) or count <= 0:
            raise InputError(source, r.prefix + "count", f"expected a positive whole number of strokes, got "
                                                         f"{describe(count)}")
        n, rest = count, 0.0
    else:
        n = int(np.floor(dur / period + 1e-9))
        rest = dur - n * period
        if n == 0:
            raise InputError(source, r.prefix + "duration", f"shorter than one stroke ({period:g} s)")

    def run(b):
        for k in range(n):
            b.trapezoid(c if k % 2 == 0 else a, feed, accel)
            b.hold(dwell)
        b.hold(rest)
    # closed form: n strokes of one period each, ending at the far end after an odd count
    return (a, run, lambda x0: (n * period + rest, c if n % 2 else a, n * (3 + (dwell > 0)) + 1),
            [("between", a), ("between", c)])


def _table(r, source):
    times = _quantities(r, "times", "time", source)
    xs = _quantities(r, "positions", "length", source)
    if len(times) != len(xs) or len(times) < 2:
        raise InputError(source, r.prefix + "positions", "needs as many entries as times, at least two")
    if times[0] != 0 or np.any(np.diff(times) <= 0):
        raise InputError(source, r.prefix + "times", "must start at 0 s and increase strictly")
    speed = np.abs(np.diff(xs) / np.diff(times))
    k = int(np.argmax(speed))
    if not speed[k] <= limits.MAX_FEED:
        limits.check_feed(speed[k], source, r.prefix + "positions",
                          f"from {xs[k] * 1e3:g} mm at {times[k]:g} s to {xs[k + 1] * 1e3:g} mm at "
                          f"{times[k + 1]:g} s the speed")
    return (xs[0], lambda b: b.polyline(times, xs), lambda x0: (float(times[-1]), float(xs[-1]), len(times) - 1),
            [("positions", x) for x in xs])


def _quantities(r, key: str, dimension: str, source: str) -> np.ndarray:
    values = r.get(key, required=True)
    if not isinstance(values, list):
        raise InputError(source, r.prefix + key, "expected a list of quantities")
    try:
        return np.array([parse_quantity(v, dimension) for v in values])
    except UnitError as err:
        raise InputError(source, r.prefix + key, str(err)) from None


# each kind's reader returns (its start or None, run(builder), plan(x0) -> (duration, end, pieces),
# the positions it was given as [(key, position [m])], checked against a machine's travel by name)
_MOVES = {"hold": _hold, "move": _move, "reciprocate": _reciprocate, "table": _table}
MOVE_KEYS = {"hold": ("position", "duration"), "move": ("to", "feed", "acceleration", "duration"),
             "reciprocate": ("between", "feed", "acceleration", "dwell", "duration", "count"),
             "table": ("times", "positions")}    # the keys of each kind of [[axis.move]] (besides kind)


def machine_for(machine, scenario):
    """The machine a scenario runs on: ``machine`` with the feed drives' parts of the axes the
    scenario commands (:func:`geometries.axes.with_feed_drives`), after checking
    the motions against it (:func:`check_motions`); ``machine`` itself otherwise."""
    if not getattr(scenario, "axes", ()):
        return machine
    check_motions(scenario, machine)
    from geometries.axes import with_feed_drives
    return with_feed_drives(machine, {m.axis for m in scenario.axes})


# --- path basis -------------------------------------------------------------------------------

def path_nodes(lo: float, hi: float, spacing: float) -> np.ndarray:
    """Uniform nodes [m] from ``lo`` to ``hi``, no further apart than ``spacing``."""
    n = max(1, int(np.ceil((hi - lo) / spacing - 1e-9)))
    return np.linspace(lo, hi, n + 1)


def hat(nodes: np.ndarray, x) -> np.ndarray:
    """(len(x), N) hat functions phi_i(x) on uniform ``nodes`` (sum 1 for x on the path)."""
    h = nodes[1] - nodes[0] if len(nodes) > 1 else 1.0
    u = (np.asarray(x, float)[:, None] - nodes[None, :]) / h
    return np.clip(1.0 - np.abs(u), 0.0, None)


def hat_integral(nodes: np.ndarray, x: np.ndarray) -> np.ndarray:
    """(len(x), N) Phi_i(x) = integral of phi_i from -inf to x [m] (piecewise quadratic)."""
    h = nodes[1] - nodes[0] if len(nodes) > 1 else 1.0
    u = np.clip((np.asarray(x, float)[:, None] - nodes[None, :]) / h, -1.0, 1.0)
    return h * np.where(u < 0, 0.5 * (u + 1) ** 2, 1.0 - 0.5 * (1 - u) ** 2)


_GAUSS = np.polynomial.legendre.leggauss(24)


def path_weights(motion: Motion, nodes: np.ndarray, edges: np.ndarray, per: str) -> np.ndarray:
    """(len(edges) - 1, N) averages over each interval [edges[n], edges[n+1]] [s] of

    * ``per="distance"``: phi_i(x(t)) |v(t)| [m/s], exactly (x is monotone in each piece, so the
      integral is |Phi_i(x_b) - Phi_i(x_a)|); summed over i it is the distance travelled / dt;
    * ``per="time"``: phi_i(x(t)) [1], exactly where the axis stands or moves at constant
      velocity, by 24-point Gauss quadrature while it accelerates; summed over i it is 1.

    Before the first piece and after the last the axis stands at its start and end."""
    edges = np.asarray(edges, float)
    breaks = np.unique(np.concatenate([edges, motion.t0, [motion.duration]]))
    breaks = breaks[(breaks >= edges[0]) & (breaks <= edges[-1])]
    ta, tb = breaks[:-1], breaks[1:]
    bin_ = np.clip(np.searchsorted(edges, ta, side="right") - 1, 0, len(edges) - 2)
    out = np.zeros((len(edges) - 1, len(nodes)))
    xa, xb = motion.position(ta), motion.position(tb)
    if per == "distance":
        contrib = np.abs(hat_integral(nodes, xb) - hat_integral(nodes, xa))
    elif per == "time":
        dt = tb - ta
        mid = 0.5 * (ta + tb)
        i = np.clip(np.searchsorted(motion.t0, mid, side="right") - 1, 0, max(len(motion.t0) - 1, 0))
        accel = (np.abs(motion.a[i]) > 0) & (mid < motion.duration) if len(motion.t0) else np.zeros(len(mid), bool)
        moving = np.abs(xb - xa) > 1e-15
        contrib = np.zeros((len(ta), len(nodes)))
        lin = moving & ~accel
        contrib[lin] = (hat_integral(nodes, xb[lin]) - hat_integral(nodes, xa[lin])) / ((xb - xa)[lin] / dt[lin])[:, None]
        still = ~moving
        contrib[still] = hat(nodes, xa[still]) * dt[still, None]
        acc = moving & accel
        if acc.any():
            g, w = _GAUSS
            tq = 0.5 * (ta[acc, None] + tb[acc, None]) + 0.5 * dt[acc, None] * g[None, :]
            phi = hat(nodes, motion.position(tq.ravel())).reshape(tq.shape + (len(nodes),))
            contrib[acc] = np.einsum("q,kqn->kn", w, phi) * 0.5 * dt[acc, None]
    else:
        raise ValueError(f"per must be 'distance' or 'time', got {per!r}")
    np.add.at(out, bin_, contrib)
    return out / np.diff(edges)[:, None]


def step_signal(values: np.ndarray, dt: float):
    """A signal holding ``values[n]`` on the time step (n dt, (n+1) dt] [s]: what the theta scheme
    sees at t_n + theta dt for any theta in (0, 1], so the energy of a step is dt values[n]."""
    values = np.asarray(values, float)

    def signal(t):
        n = np.clip(np.ceil(np.asarray(t, float) / dt - 1e-9).astype(int) - 1, 0, len(values) - 1)
        return values[n]
    return signal
