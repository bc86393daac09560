"""Physical limits of what a user may ask for, in one place.

Every number that crosses a boundary (a scenario, a measurement, a command-line option) is
finite (:mod:`twin.units` refuses NaN and inf) and, through this module, physically possible and
affordable. Each check raises :class:`twin.errors.InputError` ``(source, field, message)``.

* Temperatures [degC] above absolute zero (-273.15 degC) and within a plausible range: room air
  :data:`AIR_RANGE` (-40 to 60 degC), a machine's structure :data:`STRUCTURE_RANGE` (-40 to
  200 degC; a log in kelvin under a degC mapping reads 290-300 "degC" and is refused with a hint).
* Spindle speeds [rpm] from 0 to the machine's maximum (``Machine.max_speed``; machines that do
  not declare one: :data:`UNDECLARED_MAX_SPEED`); a measured log may exceed it by
  :data:`LOGGED_SPEED_MARGIN` (controller overshoot, encoder noise).
* Run sizes: at most :data:`MAX_STEPS` time steps (duration / sample interval) and at most
  :data:`MAX_NODE_STEPS` node-steps (steps x temperature nodes): a run beyond them would take
  days or terabytes, so it is refused with the size it implies.
* Probe readings [m] within :data:`PROBE_RANGE` (10 mm) of their zero: thermal drift is tens of
  micrometres, a reading of metres is a unit mistake. Laser triangulation readings likewise.
* Strain readings [m/m] within :data:`STRAIN_RANGE` (5000 um/m) of their zero: thermal strains of
  a machine structure are tens to hundreds of um/m (steel yields near 2000 um/m).
* C-axis speeds [rpm] from 0 to the machine's C-axis maximum (``parameters["c_axis_max_speed"]``),
  with :data:`LOGGED_SPEED_MARGIN` for a log; a machine without a C axis has none.
* Positions [m]: a sensor glued to the machine lies inside one of its parts (inside the named
  part when one is given); a sensor in the air (part ``"air"``) within :data:`AIR_REACH` of it.
* Axis motion ([[axis]], :mod:`twin.motion`): a feed [m/s] at most :data:`MAX_FEED` (2 m/s =
  120 m/min, the rapid traverse of the fastest linear-motor machine tools), an acceleration
  [m/s2] at most :data:`MAX_ACCELERATION` (50 m/s2, about 5 g: linear motors reach 2-5 g, ball
  screws about 1 g), a table move's implied speed (its largest |dposition/dt|) within
  :data:`MAX_FEED`, and at most :data:`MAX_MOTION_PIECES` pieces of constant acceleration per axis.
* Meshes: at most :data:`MAX_NODES` nodes, estimated from the grid lines before any array of the
  mesh is allocated (:func:`twin.fem.mesh.build_mesh`).
* Seeds: integers from 0 to 2**32 - 1 (stored in the result's attributes, reproducible).
"""

from __future__ import annotations

import re

import numpy as np

from twin.errors import InputError, describe

ABSOLUTE_ZERO = -273.15                 # degC
AIR_RANGE = (-40.0, 60.0)               # degC: room air round a machine tool
STRUCTURE_RANGE = (-40.0, 200.0)        # degC: anything a sensor on a machine tool reads
UNDECLARED_MAX_SPEED = 60000.0          # rpm: the fastest spindles in machine tools
LOGGED_SPEED_MARGIN = 0.05              # a measured speed may exceed the maximum by 5 %
MAX_STEPS = 1_000_000                   # time steps of one run
MAX_NODE_STEPS = 2e10                   # steps x temperature nodes of one run
MAX_CASE_STEPS = 2e7                    # cases x samples of one batch (its readings: ~30 outputs x 8 B each)
PROBE_RANGE = 0.01                      # m: the measuring range of a displacement probe (10 mm)
STRAIN_RANGE = 5e-3                     # m/m: beyond any strain a machine structure survives
AIR_REACH = 10.0                        # m: how far from the machine an air sensor may sit
MAX_SEED = 2**32 - 1
MAX_NODES = 4_000_000                   # mesh nodes: 4x the largest run measured (1 M nodes, 13.4 GiB peak, README)
MAX_FEED = 2.0                          # m/s: 120 m/min, the fastest linear-motor machine tools
MAX_ACCELERATION = 50.0                 # m/s2: about 5 g, beyond linear motors (2-5 g); ball screws ~1 g
MAX_MOTION_PIECES = 4_000_000           # pieces of constant acceleration of one axis (a million strokes with dwells)
MAX_TIME = 3.2e9                        # s: about a century, beyond any record or scenario time


def check_temperatures(values, source: str, field: str, kind: str = "air", lines=None) -> np.ndarray:
    """``values`` [degC] (a number or an array) checked: finite, above absolute zero, within
    :data:`AIR_RANGE` (``kind="air"``) or :data:`STRUCTURE_RANGE` (``kind="structure"``)."""
    v = np.asarray(values, dtype=float)
    lo, hi = AIR_RANGE if kind == "air" else STRUCTURE_RANGE
    what = "room air" if kind == "air" else "a machine-tool structure"
    bad = np.flatnonzero(~np.isfinite(v.ravel()))
    if bad.size:
        raise InputError(source, field, f"{_where(v, bad[0], lines)}is not a finite number")
    flat = v.ravel()
    below = np.flatnonzero(flat < ABSOLUTE_ZERO)
    if below.size:
        raise InputError(source, field, f"{_where(v, below[0], lines)}{flat[below[0]]:g} degC is below absolute zero "
                                        f"({ABSOLUTE_ZERO} degC)")
    out = np.flatnonzero((flat < lo) | (flat > hi))
    if out.size:
        x = flat[out[0]]
        hint = (" (it looks like kelvin: convert to degC)" if 233.15 <= x <= 473.15 else "")
        raise InputError(source, field, f"{_where(v, out[0], lines)}{x:g} degC is outside the plausible range of {what} "
                                        f"({lo:g} to {hi:g} degC){hint}")
    return v


def _where(v: np.ndarray, i: int, lines=None) -> str:
    """Where value ``i`` of ``v`` stands: ``lines`` (a file's line number of each value, as an
    editor counts them) when given, else its place in the list; nothing for a single value.
    Every check below takes ``lines`` for the values of a file's column."""
    if lines is not None:
        return f"line {lines[i]}: "
    return f"value #{i + 1}: " if v.ndim and v.size > 1 else ""


def max_speed(machine) -> float:
    """The machine's maximum spindle speed [rpm] (``Machine.max_speed``, else
    :data:`UNDECLARED_MAX_SPEED`)."""
    declared = getattr(machine, "max_speed", None) if machine is not None else None
    return float(declared) if declared else UNDECLARED_MAX_SPEED


def check_speeds(values, machine, source: str, field: str, logged: bool = False, lines=None) -> np.ndarray:
    """Spindle speeds [rpm] checked: finite, not negative, at most the machine's maximum (plus
    :data:`LOGGED_SPEED_MARGIN` for a measured log, ``logged=True``) and, unless logged, either 0
    (stopped) or at least the machine's slowest steady speed (``Machine.min_speed``, where declared)."""
    v = np.asarray(values, dtype=float)
    flat = v.ravel()
    bad = np.flatnonzero(~np.isfinite(flat))
    if bad.size:
        raise InputError(source, field, f"{_where(v, bad[0], lines)}is not a finite number")
    neg = np.flatnonzero(flat < 0)
    if neg.size:
        raise InputError(source, field, f"{_where(v, neg[0], lines)}{flat[neg[0]]:g} rpm: a spindle speed is not "
                                        "negative (give the magnitude for reverse rotation)")
    top = max_speed(machine)
    limit = top * (1 + LOGGED_SPEED_MARGIN) if logged else top
    fast = np.flatnonzero(flat > limit)
    if fast.size:
        name = getattr(machine, "name", None)
        whose = f"machine {name}'s maximum of {top:g} rpm" if name else f"the limit of {top:g} rpm"
        raise InputError(source, field, f"{_where(v, fast[0], lines)}{beside(flat[fast[0]], top)} rpm is beyond {whose}")
    slowest = getattr(machine, "min_speed", None) if machine is not None and not logged else None
    crawl = np.flatnonzero((flat > 0) & (flat < slowest)) if slowest else np.zeros(0, int)
    if crawl.size:
        raise InputError(source, field, f"{_where(v, crawl[0], lines)}{beside(flat[crawl[0]], slowest)} rpm is below "
                                        f"machine {machine.name}'s slowest steady speed of {slowest:g} rpm (0 rpm: "
                                        "stopped)")
    return v


def beside(value: float, limit: float) -> str:
    """``value`` written so that it differs from ``limit`` written the same way: ``%g`` unless both
    print alike (9000.0001 and 9000 are both "9000" in ``%g``: "9000 rpm is beyond 9000 rpm"), then
    with the digits that tell them apart, up to ``repr``."""
    for digits in (6, 10, 15):
        text = f"{value:.{digits}g}"
        if text != f"{limit:.{digits}g}":
            return text
    return repr(float(value))


def _within(values, limit: float, source: str, field: str, beyond, lines=None) -> np.ndarray:
    """``values`` checked: finite and within ``limit`` of zero; ``beyond(x)`` says why x is not."""
    v = np.asarray(values, dtype=float)
    flat = v.ravel()
    bad = np.flatnonzero(~np.isfinite(flat) | (np.abs(flat) > limit))
    if bad.size:
        x = flat[bad[0]]
        raise InputError(source, field, f"{_where(v, bad[0], lines)}{'is not a finite number' if not np.isfinite(x) else beyond(x)}")
    return v


def check_displacements(values, source: str, field: str, lines=None) -> np.ndarray:
    """Displacement-probe readings [m] checked: finite and within :data:`PROBE_RANGE` of zero."""
    return _within(values, PROBE_RANGE, source, field, lambda x: f"{x * 1e3:g} mm is beyond a displacement probe's "
                                                                  f"range of +-{PROBE_RANGE * 1e3:g} mm (check the unit)",
                   lines)


def check_strains(values, source: str, field: str, lines=None) -> np.ndarray:
    """Strain readings [m/m] checked: finite and within :data:`STRAIN_RANGE` of zero."""
    return _within(values, STRAIN_RANGE, source, field, lambda x: f"{x * 1e6:g} um/m is beyond +-{STRAIN_RANGE * 1e6:g} "
                                                                   "um/m, more than a machine structure survives "
                                                                   "(check the unit)", lines)


def check_c_axis_speeds(values, machine, source: str, field: str, logged: bool = False, lines=None) -> np.ndarray:
    """C-axis speeds [rpm] checked: finite, not negative, within the machine's C-axis maximum
    (``parameters["c_axis_max_speed"]``; plus :data:`LOGGED_SPEED_MARGIN` for a log); without a
    machine (None) finite and not negative only."""
    v = np.asarray(values, dtype=float)
    flat = v.ravel()
    top = (getattr(machine, "parameters", None) or {}).get("c_axis_max_speed") if machine is not None else np.inf
    if top is None:
        raise InputError(source, field, f"machine {getattr(machine, 'name', '?')} has no C axis")
    bad = np.flatnonzero(~np.isfinite(flat) | (flat < 0))
    if bad.size:
        raise InputError(source, field, f"{_where(v, bad[0], lines)}{flat[bad[0]]:g} rpm: a C-axis speed is finite and not "
                                        "negative (give the magnitude)")
    limit = top * (1 + LOGGED_SPEED_MARGIN) if logged else top
    fast = np.flatnonzero(flat > limit)
    if fast.size:
        raise InputError(source, field, f"{_where(v, fast[0], lines)}{beside(flat[fast[0]], top)} rpm is beyond machine "
                                        f"{machine.name}'s C-axis maximum of {top:g} rpm")
    return v


def check_whole_samples(duration: float, sample_interval: float, source: str, field: str) -> None:
    """A step of ``duration`` [s] spans a whole number of ``sample_interval`` [s] (to 1e-6 of a
    sample), at least one: else the run's grid ends before it or holds it past its end (a step
    of 1e-5 s at 10 s samples would vanish from the run)."""
    samples = duration / sample_interval
    if abs(samples - round(samples)) > 1e-6 or round(samples) < 1:
        raise InputError(source, field, f"must be a multiple of the sample interval ({sample_interval:g} s), at "
                                        f"least one, got {duration:g} s")


def check_steps(duration: float, sample_interval: float, source: str, field: str) -> int:
    """The number of time steps duration / sample interval [s], refused beyond :data:`MAX_STEPS`."""
    steps = duration / sample_interval
    if not np.isfinite(steps) or steps > MAX_STEPS:
        raise InputError(source, field, f"the run would take {steps:.3g} time steps (duration {duration:.6g} s / "
                                        f"sample interval {sample_interval:.6g} s); at most {MAX_STEPS:.0e} are "
                                        "affordable: shorten the run or lengthen sample_interval")
    return int(round(steps))


def check_batch_size(cases: int, samples: int, source: str, field: str) -> None:
    """A batch of ``cases`` runs of ``samples`` samples each holds every reading of every case at
    once: refused beyond :data:`MAX_CASE_STEPS` case-samples (a billion cases ran for minutes
    before failing with a memory error)."""
    if cases * samples > MAX_CASE_STEPS:
        raise InputError(source, field, f"{cases} cases of {samples} samples each are {cases * samples:.3g} "
                                        f"case-samples; a batch holds at most {MAX_CASE_STEPS:.0e}: run fewer cases "
                                        f"(here at most {int(MAX_CASE_STEPS // samples)}) or in several batches")


def check_run_size(scenario, nodes: int, field: str = "duration") -> None:
    """Refuse a run of ``scenario`` on ``nodes`` temperature nodes beyond :data:`MAX_STEPS` time
    steps or :data:`MAX_NODE_STEPS` node-steps, with the size it implies."""
    source = scenario.source or scenario.name
    steps = check_steps(scenario.duration, scenario.sample_interval, source, field)
    size = float(steps) * float(nodes)
    if size > MAX_NODE_STEPS:
        raise InputError(source, field, f"{steps} time steps on a mesh of {nodes} nodes are {size:.3g} node-steps; "
                                        f"at most {MAX_NODE_STEPS:.0e} are affordable (a coarser --mesh, a "
                                        "longer sample_interval or a shorter run)")


def check_mesh_nodes(nodes: float, spacing: float, machine_name: str, source: str = "command line",
                     field: str = "spacing") -> None:
    """Refuse a mesh of (an estimated) ``nodes`` nodes beyond :data:`MAX_NODES`, before it is built."""
    if not nodes <= MAX_NODES:
        raise InputError(source, field, f"a spacing of {spacing * 1e3:.4g} mm would mesh machine {machine_name} with "
                                        f"about {nodes:.3g} nodes; at most {MAX_NODES:.0e} are affordable (a larger "
                                        "spacing)")


def check_scenario(scenario, machine) -> None:
    """A scenario against a machine: its own values first (:meth:`twin.scenario.Scenario.check`,
    the scenario loader's checks again: a scenario built in Python or changed with
    ``dataclasses.replace`` never met the loader), then every spindle step within the machine's
    speed limit (with :data:`LOGGED_SPEED_MARGIN` when the scenario was built from a log,
    ``extra["logged"]``)."""
    scenario.check()
    source = scenario.source or scenario.name
    logged = bool(scenario.extra.get("logged"))
    for i, (_, speed) in enumerate(scenario.steps):
        check_speeds(speed, machine, source, "spindle_speed" if logged else f"spindle[{i}].speed", logged)
    check_c_axis(scenario, machine, source)


def check_c_axis(scenario, machine, source: str) -> None:
    """The scenario's C-axis steps (:mod:`twin.rotary`) against the machine: it must have a C axis
    (``parameters["c_axis_max_speed"]`` [rpm]) and every step's speed must be within it (with
    :data:`LOGGED_SPEED_MARGIN` when the scenario was built from a log)."""
    schedule = getattr(scenario, "c_axis", None)
    if schedule is None:
        return
    logged = bool(getattr(scenario, "extra", {}).get("logged"))
    for i, (_, speed, _) in enumerate(schedule.steps):
        check_c_axis_speeds(speed, machine, source, "c_axis_speed" if logged else f"c_axis[{i}].speed", logged)


def check_position(machine, xyz, part: str, source: str, field: str) -> None:
    """A sensor position [m] checked against the machine: in the air (``part == "air"``) within
    :data:`AIR_REACH` of its parts, else inside a box of ``part`` (any part when empty) and not
    inside one of its voids (a bore, a hollow casting's cavity). A part nested in another's box
    (a bearing zone in the spindle) counts as on both."""
    p = np.asarray(xyz, dtype=float)
    if not np.all(np.isfinite(p)):
        raise InputError(source, field, "position is not finite")
    names = [q.name for q in machine.parts]
    if part and part != "air" and part not in names:
        raise InputError(source, field, f"machine {machine.name} has no part {part!r}; known: {', '.join(names)} "
                                        "(or air)")
    boxes = [(q.name, b) for q in machine.parts for b in q.boxes]
    lo = np.min([b.lo for _, b in boxes], axis=0)
    hi = np.max([b.hi for _, b in boxes], axis=0)
    where = f"({', '.join(f'{c:.4g}' for c in p)}) m"
    if part == "air":
        if np.any(p < lo - AIR_REACH) or np.any(p > hi + AIR_REACH):
            raise InputError(source, field, f"{where} is more than {AIR_REACH:g} m from machine {machine.name}")
        return
    inside = [q.name for q in machine.parts if any(_holds(b, p, 1e-9) for b in q.boxes)
              and not any(_holds(v, p, -1e-9) for v in q.voids)]      # a void's inside is not the part's
    if part and part not in inside:
        raise InputError(source, field, f"{where} is not on part {part} of machine {machine.name}"
                                        + (f" (it lies in {', '.join(inside)})" if inside else ""))
    if not inside:
        span = ", ".join(f"{a} {l:.3g}..{h:.3g}" for a, l, h in zip("xyz", lo, hi))
        raise InputError(source, field, f"{where} is outside machine {machine.name} (its parts span {span} m)")


def _holds(box, p: np.ndarray, tol: float) -> bool:
    """Whether ``box`` holds the point ``p`` [m], its faces widened by ``tol`` [m] (narrowed when
    negative)."""
    return bool(np.all(p >= np.asarray(box.lo) - tol) and np.all(p <= np.asarray(box.hi) + tol))


def _at_most(value: float, limit: float, source: str, field: str, message) -> float:
    """``value`` as a float when finite and |value| <= ``limit``; else the :class:`InputError`
    ``message(value)`` on ``field``."""
    v = float(value)
    if not np.isfinite(v) or abs(v) > limit:
        raise InputError(source, field, message(v))
    return v


def check_feed(value: float, source: str, field: str, what: str = "a feed") -> float:
    """An axis feed (or speed) [m/s] checked: finite and at most :data:`MAX_FEED`."""
    return _at_most(value, MAX_FEED, source, field, lambda v: (
        f"{what} of {beside(v, MAX_FEED)} m/s ({beside(v * 60, MAX_FEED * 60)} m/min) is beyond {MAX_FEED:g} m/s ({MAX_FEED * 60:g} m/min), the fastest "
        "linear-motor machine tools (check the unit)"))


def check_acceleration(value: float, source: str, field: str) -> float:
    """An axis acceleration [m/s2] checked: finite and at most :data:`MAX_ACCELERATION`."""
    return _at_most(value, MAX_ACCELERATION, source, field, lambda v: (
        f"an acceleration of {beside(v, MAX_ACCELERATION)} m/s2 ({v / 9.80665:.3g} g) is beyond {MAX_ACCELERATION:g} m/s2 (about "
        f"{MAX_ACCELERATION / 9.80665:.0f} g): linear-motor axes reach 2-5 g, ball screws about 1 g (check the unit)"))


def plain_int(text) -> int:
    """``text`` as an integer written in plain ASCII digits with an optional sign (Python's int()
    also reads 1_0 as 10 and Arabic-Indic or full-width digits, which no user means), else
    ValueError."""
    if not re.fullmatch(r"\s*[+-]?[0-9]+\s*", str(text)):
        raise ValueError(f"not a whole number: {text!r}")
    return int(text)


def check_flag(value, source: str, field: str) -> bool:
    """``value`` a boolean (a text such as "no" is true in Python, and was taken as yes)."""
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(source, field, f"expected True or False, got {describe(value)}")
    return bool(value)


def check_progress(progress, source: str, field: str = "progress") -> None:
    """``progress`` None or a callable (it is called as progress(done, total) once the work runs,
    where a number failed with a TypeError after the mesh was built)."""
    if progress is not None and not callable(progress):
        raise InputError(source, field, f"expected None or a function progress(done, total), got {describe(progress)}")


def is_file_name(name) -> bool:
    """Whether ``name`` can name a file or folder by itself: text, not blank, not ``.`` or ``..``,
    no path separator, NUL or other control character (a camera's name names its export's
    folder and files)."""
    return (isinstance(name, str) and bool(name.strip()) and name not in (".", "..")
            and not any(c in "/\\" or ord(c) < 32 for c in name))


def check_seed(text) -> int:
    """A noise seed: an integer from 0 to :data:`MAX_SEED` (raises ValueError otherwise)."""
    try:
        seed = plain_int(text)
    except ValueError:
        raise ValueError(f"{text!r} is not an integer") from None
    if not 0 <= seed <= MAX_SEED:
        raise ValueError(f"{seed} is outside 0..{MAX_SEED}")
    return seed


def is_number(value) -> bool:
    """Whether ``value`` is a real number given as one (a Python or numpy int or float, not a bool,
    a text or None); finiteness and range are the caller's to check."""
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def is_whole(value) -> bool:
    """Whether ``value`` is a whole number given as one (a Python or numpy integer, not a bool)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def seed_value(seed, source: str, field: str = "seed") -> int:
    """A seed given in Python: an integer (not a text, a float or None: the result must be
    reproducible) from 0 to :data:`MAX_SEED` (:func:`check_seed`), else :class:`InputError`."""
    if not is_whole(seed):
        raise InputError(source, field, f"expected an integer from 0 to {MAX_SEED}, got {seed!r} (a fixed seed "
                                        "makes the result reproducible)")
    try:
        return check_seed(int(seed))
    except ValueError as err:
        raise InputError(source, field, str(err)) from None


def theta_value(theta, source: str, field: str = "theta") -> float:
    """The time scheme's theta: a number from 0.5 (Crank-Nicolson) to 1 (implicit Euler), the
    unconditionally stable range (:func:`twin.physics.heat.integrate`); else one
    :class:`InputError` naming ``source`` and ``field`` (the reduced model, which integrates its own
    steps, would otherwise diverge silently: theta 0 gave a drift of 1e25 m)."""
    if not is_number(theta) or not 0.5 <= theta <= 1.0:
        raise InputError(source, field, f"a number from 0.5 (Crank-Nicolson) to 1 (implicit Euler), the "
                                        f"unconditionally stable range, got {theta!r}")
    return float(theta)


def is_finite_number(value) -> bool:
    """Whether ``value`` is a finite number (:func:`is_number`, not NaN or inf)."""
    return is_number(value) and bool(np.isfinite(value))


def finite_number(value, source: str, field: str) -> float:
    """``value`` as a float when it is a finite number (not a bool, a text or None)."""
    if not is_finite_number(value):
        raise InputError(source, field, f"expected a finite number, got {describe(value)}")
    return float(value)


def finite_numbers(values, source: str, field: str) -> np.ndarray:
    """``values`` as a 1-D float array when every entry is a finite number."""
    if isinstance(values, np.ndarray):
        if values.ndim != 1 or values.dtype.kind not in "fiu":
            raise InputError(source, field, f"expected a list of numbers, got an array of {values.dtype} {values.shape}")
    elif isinstance(values, (tuple, list)):
        for i, v in enumerate(values):
            if not is_number(v):
                raise InputError(source, f"{field}[{i}]", f"expected a finite number, got {describe(v)}")
    else:
        raise InputError(source, field, f"expected a list of numbers, got {describe(values)}")
    out = np.asarray(values, dtype=float)
    bad = np.flatnonzero(~np.isfinite(out))
    if bad.size:
        raise InputError(source, f"{field}[{bad[0]}]", f"expected a finite number, got {describe(out[bad[0]])}")
    return out


def check_machine(machine, source: str) -> None:
    """``machine`` is a built machine (:class:`geometries.base.Machine`), not its name."""
    if isinstance(machine, str):
        raise InputError(source, "machine", f"expected a Machine, got the name {machine!r}: pass "
                                            f"twin.api.machine_by_name({machine!r}) (or geometries.build_machine)")
    if not hasattr(machine, "parts") or not hasattr(machine, "resolutions"):
        raise InputError(source, "machine", f"expected a Machine (twin.api.machine_by_name builds one), got {machine!r}")
