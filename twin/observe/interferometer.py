"""Laser interferometer (ISO 230-2 style): the thermal positioning error along an axis.

A scenario asks for it with::

    [interferometer]
    axis = "Y"
    runs = ["0 min", "20 min", "60 min"]     # instants of the bidirectional runs (on the time grid)
    targets = ["0 mm", "280 mm"]              # first and last target (default: the axis travel)
    spacing = "10 mm"                         # optional, default 10 mm

At each run the optics read every target in both directions with the structure's temperature
frozen at that instant (the seconds a run takes are neglected, so both directions read alike:
the model has no reversal error). The laser is on the tool side and the retroreflector on the
workpiece; the error is the actual minus the commanded position of the axis (ISO 230-2), the
moving side relative to the other: of the workpiece relative to the tool when the axis carries the
workpiece (s = +1: the C-frame's X and Y), of the tool relative to the workpiece when it carries
the tool (s = -1: Z). So at a free uniform expansion alpha dT of a machine of one material,
e(p) = alpha dT (s (x_w - x_t) . d + p - p_ref) with x_w, x_t the workpiece and tool points at
the mesh's pose p_ref, whichever side moves:

* **semi-closed loop** (rotary encoder): the nut sits where the screw's length from its fixed
  bearing puts it, so

      e(p) = alpha_s integral_{y_f}^{y_n(p)} (T_screw(s) - T_0) ds + c,

  with y_f the fixed bearing, y_n(p) the nut at commanded position p and c the structure's share
  (s (u_w - u_t) along the axis, plus the fixed bearing's displacement, minus the nut's as the
  bonded mesh gives it), one adjoint functional (:mod:`twin.observe.displacement`);
  c does not depend on p, so it moves the curve and leaves its slope;
* **closed loop** (linear scale): the read head stops where the graduation p is, and the
  graduations follow the scale's carrier, so

      e(p) = u_c(y_s(p)) + c',

  u_c the carrier's displacement along the axis at the scale's graduation for p and c' the
  structure's share (s (u_w - u_t) minus the read head's displacement at the mesh's pose); the
  screw's expansion does not enter. Both from adjoint functionals (one per target).

Output: ``positioning_error(run_time, target, direction)`` [um] as the change from the cold state
at t = 0 (the reference run: the thermal error), the targets' positions [mm], and
``positioning_slope(run_time)`` [um/mm], the slope of the least-squares line through each run
(seed 003's k - k0). Exact for a screw at a uniform rise dT fixed at y_f: e = alpha dT (y_n - y_f);
a closed loop on a carrier at a uniform rise reads its free expansion, slope alpha_c dT.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from geometries.axes import carried_sign
from geometries.regions import feed_drive_role
from twin.errors import InputError
from twin.fem.points import displacement_functional, interpolation_matrix
from twin.io.table_reader import TableReader
from twin.limits import is_finite_number
from twin.observe.base import variable
from twin.observe.displacement import DisplacementObserver
from twin.observe.instants import baseline_instants, check_on_grid
from twin.units import UnitError, parse_quantity

LINE_STEP = 0.002   # [m] quadrature step along the screw (trapezoidal rule on the trilinear field)


@dataclass(frozen=True)
class InterferometerConfig:
    """Axis name, run instants [s], first and last target [m] (None: the travel), spacing [m]."""

    axis: str
    runs: tuple[float, ...]
    first: float | None = None
    last: float | None = None
    spacing: float = 0.010
    source: str = ""

    def targets(self, axis) -> np.ndarray:
        """Commanded target positions [m] from first to last every ``spacing``, the last target
        itself included unless it lies within 1 nm of a multiple of the spacing (an absolute
        tolerance: a relative one would grow with the distance from the machine's origin)."""
        lo = axis.travel[0] if self.first is None else self.first
        hi = axis.travel[1] if self.last is None else self.last
        n = int(np.floor((hi - lo) / self.spacing + 1e-9))
        t = lo + self.spacing * np.arange(n + 1)
        return t if abs(t[-1] - hi) <= 1e-9 else np.append(t, hi)


MIN_SPACING = 1e-3      # [m] the closest targets a run may have


def interferometer_from_toml(raw, source: str) -> InterferometerConfig | None:
    """The scenario's ``[interferometer]`` table (None when absent)."""
    if raw is None:
        return None
    r = TableReader(raw, source, "interferometer.", known=("axis", "runs", "targets", "spacing"))
    axis = r.get("axis", required=True)
    runs = r.get("runs", required=True)
    targets = r.get("targets")
    spacing = r.positive("spacing", "length", default=0.010)
    r.finish()
    if spacing < MIN_SPACING:
        raise InputError(source, "interferometer.spacing", f"{spacing * 1e3:g} mm is below {MIN_SPACING * 1e3:g} mm: "
                                                           "the targets of a positioning test (ISO 230-2) lie millimetres "
                                                           "apart or more, and the mesh resolves centimetres")
    if not isinstance(axis, str):
        raise InputError(source, "interferometer.axis", "expected an axis name such as \"Y\"")
    times = baseline_instants(runs, source, "interferometer.runs", "the cold reference run")
    try:
        ends = [parse_quantity(v, "length") for v in targets] if isinstance(targets, list) else None
    except UnitError as err:
        raise InputError(source, "interferometer.targets", str(err)) from None
    if targets is not None and (ends is None or len(ends) != 2 or ends[1] <= ends[0]):
        raise InputError(source, "interferometer.targets", "expected [first, last] with last > first")
    first, last = (None, None) if ends is None else ends
    return InterferometerConfig(axis, times, first, last, spacing, source)


def check_interferometer(config: InterferometerConfig, scenario, machine) -> None:
    """The axis exists, its feedback is modelled (a semi-closed loop's screw is on ``machine``: the
    scenario moves the axis, :func:`twin.motion.machine_for`), the targets lie in its travel and
    the runs on the scenario's time grid within its duration."""
    if not isinstance(config, InterferometerConfig):
        raise InputError(scenario.name, "interferometer", f"expected a twin.observe.interferometer.InterferometerConfig, "
                                                          f"got {config!r}")
    src = config.source or scenario.name
    if not is_finite_number(config.spacing) or config.spacing < MIN_SPACING:
        raise InputError(src, "interferometer.spacing", f"expected a finite spacing of {MIN_SPACING * 1e3:g} mm or more "
                                                        f"[m], got {config.spacing!r}")
    ends = [v for v in (config.first, config.last) if v is not None]
    if any(not is_finite_number(v) for v in ends) or (len(ends) == 2 and ends[1] <= ends[0]):
        raise InputError(src, "interferometer.targets", f"expected finite first < last [m], got {config.first!r}, "
                                                        f"{config.last!r}")
    try:
        axis = machine.axis(config.axis)
    except KeyError:
        raise InputError(src, "interferometer.axis", f"machine {machine.name} has no axis {config.axis!r}") from None
    if carried_sign(machine, axis) == 0.0:
        raise InputError(src, "interferometer.axis", f"axis {axis.name} of {machine.name} carries neither the tool nor "
                                                     "the workpiece alone: its positioning error has no side")
    if (axis.drive if axis.feedback == "semi-closed" else axis.scale) is None:
        what = "screw (feed drive)" if axis.feedback == "semi-closed" else "linear scale"
        raise InputError(src, "interferometer.axis", f"axis {axis.name} of {machine.name} is {axis.feedback} loop and "
                                                     f"its {what} is not modelled")
    if axis.feedback == "semi-closed" and feed_drive_role(axis.name, "screw") not in machine.roles:
        moved = {m.axis for m in getattr(scenario, "axes", ())}
        why = ("" if axis.name in moved else
               f"; the scenario has no [[axis]] for {axis.name}: add one (a kind = \"hold\" move if it stands still)")
        raise InputError(src, "interferometer.axis", f"axis {axis.name} of {machine.name} is semi-closed loop: its "
                                                     "positioning error integrates the screw's temperature, and the "
                                                     "screw (its feed drive) is built only for an axis the scenario "
                                                     f"moves{why}")
    t = config.targets(axis)
    if t[0] < axis.travel[0] - 1e-9 or t[-1] > axis.travel[1] + 1e-9:
        raise InputError(src, "interferometer.targets", f"outside the {axis.name} travel "
                                                        f"{axis.travel[0] * 1e3:g} .. {axis.travel[1] * 1e3:g} mm")
    gap = float(np.min(np.diff(t))) if len(t) > 1 else np.inf
    if gap < MIN_SPACING - 1e-12:     # the last target, appended after first + k spacing, too close to it
        raise InputError(src, "interferometer.targets", f"the last target, {t[-1] * 1e3:g} mm, lies {gap * 1e3:g} mm "
                                                        f"after the one before it (first + a multiple of the "
                                                        f"{config.spacing * 1e3:g} mm spacing): targets closer than "
                                                        f"{MIN_SPACING * 1e3:g} mm are refused; make last - first a "
                                                        "multiple of the spacing, or move the last target")
    check_on_grid(config.runs, scenario, src, "interferometer.runs", "the cold reference run")


def screw_line_rows(layout, axis, targets: np.ndarray, expansion: float) -> sp.csr_matrix:
    """(n_targets, n_heat) rows: alpha_s times the integral of T along the screw's centre line from
    the fixed bearing to the nut at each target (trapezoidal rule on one set of points, at most
    :data:`LINE_STEP` apart, that holds every nut position)."""
    drive = axis.drive
    d = "xyz".index(axis.direction)
    ends = axis.nut_coordinate(np.asarray(targets, float))
    lo, hi = min(drive.fixed_end, ends.min()), max(drive.fixed_end, ends.max())
    n = max(1, int(np.ceil((hi - lo) / LINE_STEP)))
    s = np.unique(np.concatenate([np.linspace(lo, hi, n + 1), ends, [drive.fixed_end]]))
    xyz = np.empty((len(s), 3))
    xyz[:, d] = s
    xyz[:, [k for k in range(3) if k != d]] = drive.screw_axis
    P = interpolation_matrix(layout, xyz, field="temperature")
    # trapezoidal weights of integral_{fixed}^{end}: half the neighbouring intervals inside the span
    W = np.zeros((len(ends), len(s)))
    for i, y in enumerate(ends):
        a, b = sorted((drive.fixed_end, y))
        inside = (s >= a - 1e-12) & (s <= b + 1e-12)
        idx = np.flatnonzero(inside)
        if len(idx) > 1:
            h = np.diff(s[idx])
            W[i, idx[:-1]] += 0.5 * h
            W[i, idx[1:]] += 0.5 * h
        W[i] *= np.sign(y - drive.fixed_end)
    return expansion * sp.csr_matrix(W @ P)


class LaserInterferometer(DisplacementObserver):
    """Bidirectional positioning-error runs along ``config.axis`` at ``config.runs`` (see module)."""

    key = "interferometer"
    layout_cached = True

    def __init__(self, config: InterferometerConfig, machine):
        if not isinstance(config, InterferometerConfig):
            raise InputError("command line", "interferometer", f"expected an InterferometerConfig, got {config!r}")
        self.config = config
        try:
            self.axis = machine.axis(config.axis)
        except KeyError:
            raise InputError(config.source or "command line", "interferometer.axis",
                             f"machine {machine.name} has no axis {config.axis!r}") from None
        self.targets = config.targets(self.axis)

    def cache_key(self) -> tuple:
        return (type(self).__name__, self.config)

    def check(self, scenario, machine) -> None:
        """Its runs on the scenario's grid, from 0 s, increasing; its axis and targets on the machine."""
        check_interferometer(self.config, scenario, machine)

    def _point(self, along: float, across) -> np.ndarray:
        k = "xyz".index(self.axis.direction)
        p = np.zeros(3)
        p[k], p[[i for i in range(3) if i != k]] = along, across
        return p

    def functionals(self, mm):
        """Semi-closed, one row: s (workpiece - tool) + fixed bearing - nut housing along the axis
        (the structure's share c: on the bonded mesh the moving body follows the structure under
        the nut; on the machine it follows the fixed bearing plus the screw). Closed, 1 + n_targets
        rows: s (workpiece - tool) - read head at the mesh's pose, then the scale's carrier at each
        target's graduation. s = +1 when the axis carries the workpiece, -1 when it carries the
        tool (module docstring)."""
        m, a = mm.machine, self.axis
        d = np.eye(3)["xyz".index(a.direction)]
        ends = [m.point(m.workpiece_point).xyz, m.point(m.tool_point).xyz]
        s = -carried_sign(m, a)
        if a.feedback == "semi-closed":
            pts = ends + [self._point(a.drive.fixed_end, a.drive.screw_axis),
                          self._point(a.nut_coordinate(a.p_ref), np.add(a.drive.screw_axis, a.drive.nut_offset))]
            weights = np.array([[s, -s, 1.0, -1.0]])
        else:
            marks = [self._point(y, a.scale.line) for y in a.nut_coordinate(self.targets)]
            pts = ends + [self._point(a.nut_coordinate(a.p_ref), a.scale.head)] + marks
            weights = np.zeros((1 + len(marks), len(pts)))
            weights[0, :3] = (s, -s, -1.0)
            weights[np.arange(1, len(marks) + 1), np.arange(3, len(pts))] = 1.0
        P = interpolation_matrix(mm, np.array(pts), [f"interferometer point {i}" for i in range(len(pts))], field="mesh")
        return sp.csr_matrix(weights @ displacement_functional(P, d))

    def rows(self, twin, loads):
        return self.material_rows(twin, loads, None)

    def material_rows(self, twin, loads, material: str | None):
        """The rows (n_targets, n_heat); with ``material``, those of that material's expansion alone
        (d e / d s for alpha_m (1 + s): the structure's share through that material's cells, plus
        the screw's line integral when the screw is of it), as
        :class:`twin.observe.ExpansionSensitivity` needs."""
        layout = loads.mm
        R = twin.displacement_rows(self, layout, material=material)   # (1 or 1 + n_targets, n_heat)
        offset = np.repeat(R[:1], len(self.targets), axis=0)
        if self.axis.feedback == "closed":
            return sp.csr_matrix(R[1:] + offset)
        screw = twin.machine.part(twin.machine.roles[feed_drive_role(self.axis.name, "screw")].names[0])
        steel = twin.materials.get(screw.name, screw.material)
        if material is not None and steel.name != material:
            return sp.csr_matrix(offset)
        return sp.csr_matrix(screw_line_rows(layout, self.axis, self.targets, steel.expansion) + offset)

    def sample_steps(self, times):
        dt = times[1] - times[0] if len(times) > 1 else 1.0
        return np.array([int(round(t / dt)) for t in self.config.runs])

    def data(self, raw, ctx):
        err = (raw - raw[0]) * 1e6                            # (runs, targets) [um]; run 0 is the cold one
        tgt = self.targets * 1e3
        slope = np.polyfit(tgt, err.T, 1)[0]
        both = np.stack([err, err], axis=-1)
        return ({"positioning_error": variable(("run_time", "target", "direction"), both, "um",
                                               f"thermal positioning error of axis {self.axis.name} (run minus cold)"),
                 "positioning_slope": variable(("run_time",), slope, "um/mm",
                                               "slope of the least-squares line through each run (k - k0)")},
                {"run_time": ("run_time", np.asarray(self.config.runs, float), {"units": "s", "long_name": "run instant"}),
                 "target": ("target", tgt, {"units": "mm", "long_name": f"commanded {self.axis.name} position"}),
                 "direction": ("direction", ["forward", "backward"], {"long_name": "approach direction"})})


class PositioningTrace(LaserInterferometer):
    """The interferometer's positioning error at every output instant of the run (not only at
    its runs): raw (n_t, n_targets) [m], the same rows as :class:`LaserInterferometer`. The
    diagnosis reads it at the runs of a measurement (:mod:`validate.evidence`); no Dataset
    variables of its own."""

    key = "positioning_trace"

    def sample_steps(self, times):
        return None

    def data(self, raw, ctx):
        return {}, {}

