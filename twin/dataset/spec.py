"""A dataset spec: the TOML file that says which cases ``twin dataset`` builds.

Every quantity carries its unit (parsed by :mod:`twin.units`)::

    name = "spindle-ambient-demo"
    description = "what the dataset is for"
    machines = ["cframe-vmc"]           # registered machines
    mesh = "coarse"                     # coarse | default | fine
    solver = "auto"                     # auto | direct | iterative | rom
    effects = "+room_gradient"          # optional, like --effects (edits each machine's default set)
    seed = 14                           # the plan's seed: every draw derives from it

    [observers]                         # optional
    surface_grid = { parts = ["carrier", "column"], spacing = "100 mm" }   # dense virtual sensors
    cameras = ["carrier-front"]         # thermal cameras at the machines' named poses

    [parameters]                        # effect or instrument parameters, "effect.param"
    "spindle_motor.power" = { uniform = ["40 W", "80 W"] }
    "ambient_convection.h" = { grid = ["6 W/m2K", "10 W/m2K"] }
    # also: "60 W" (fixed), { fixed = "60 W" }, { log_uniform = [lo, hi] }, { normal = [mean, sd] }

    [[scenarios]]                       # a family read from a file (bundled name, or a path
    family = "reference"                # relative to the spec)
    file = "spindle-duty-cycle"
    cases = 1                           # draws of this family (default 1)

    [[scenarios]]                       # a family drawn by a generator
    family = "random-duty"
    cases = 50
    duration = "2 h"
    sample_interval = "30 s"
    [scenarios.spindle]                 # a random piecewise-constant duty cycle
    step = ["10 min", "30 min"]         # each step's duration (rounded to the sample interval)
    speed = ["2000 rpm", "9000 rpm"]    # each running step's speed
    speed_step = "500 rpm"              # optional: speeds rounded to multiples of it
    idle_probability = 0.3              # optional: the chance that a step is a stop
    [scenarios.ambient]
    kind = "daily"                      # or "constant" with temperature = ...
    mean = ["18 degC", "22 degC"]       # each field a value, a [lo, hi] range or a distribution
    amplitude = ["0 K", "3 K"]
    coldest_at = ["0 h", "24 h"]        # the phase of the day
    start_time_of_day = "8 h"
    [[scenarios.axis]]                  # optional: an axis duty cycle, one table per axis
    name = "Y"                          # an axis with a feed drive on every machine of the spec
    range = ["0 mm", "280 mm"]          # where the drawn stroke ends fall (within the travel)
    feed = ["5 mm/s", "30 mm/s"]        # each running step's feed
    acceleration = "100 mm/s2"          # optional (default 100 mm/s2)

    [splits]                            # optional (default: every case in "train")
    by = "case"                         # fractions, drawn within each family ...
    train = 0.6
    validation = 0.2
    test = 0.2
    # by = "family" with lists of families: train = ["random-duty"], test = ["reference"]

An axis duty cycle follows the spindle's steps: while the spindle runs the axis reciprocates
between where it is and a drawn end at a drawn feed (holding when not even one stroke fits the
step), while it stands the axis holds; it starts at the middle of its range. Scenario files that
move axes are accepted too; the interferometer and probing are not (run ``twin simulate``).

A generator field given as ``[lo, hi]`` is uniform; a table names the distribution. Normal draws
are truncated to the parameter's bounds (redrawn). A ``grid`` is allowed for parameters only: the
plan crosses every grid point with every draw. Unknown keys, wrong units, empty or reversed
ranges, values outside a parameter's bounds or a machine's speed limit raise
:class:`twin.errors.InputError` naming the spec file and the field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from geometries import MACHINES, build_machine
from twin import limits
from twin.effects import EFFECTS
from twin.errors import InputError
from twin.io.paths import read_toml
from twin.model import model_spec
from twin.motion import check_motions
from twin.observe.instruments import INSTRUMENTS
from twin.scenario import SCENARIO_DIR, scenario_from_dict
from twin.units import CANONICAL, UnitError, parse_quantity

SOLVERS = ("auto", "direct", "iterative", "rom")
DISTRIBUTIONS = ("fixed", "grid", "uniform", "log_uniform", "normal")
SPLIT_NAMES = ("train", "validation", "test")
MAX_CASES = 100_000


@dataclass(frozen=True)
class Dist:
    """A quantity's distribution, values in SI: ``fixed (v,)``, ``grid (v1, v2, ...)``,
    ``uniform (lo, hi)``, ``log_uniform (lo, hi)``, ``normal (mean, sd)`` truncated to
    ``[lower, upper]``."""

    kind: str
    values: tuple[float, ...]
    dimension: str
    lower: float = -math.inf
    upper: float = math.inf

    def sample(self, rng) -> float:
        """One draw from the numpy Generator ``rng`` (a grid is expanded by the plan, not drawn)."""
        v = self.values
        if self.kind == "fixed":
            return v[0]
        if self.kind == "uniform":
            return float(rng.uniform(v[0], v[1]))
        if self.kind == "log_uniform":
            return float(math.exp(rng.uniform(math.log(v[0]), math.log(v[1]))))
        if self.kind == "normal":
            for _ in range(10_000):
                x = float(rng.normal(v[0], v[1]))
                if self.lower <= x <= self.upper:
                    return x
            raise ValueError("normal draws fall outside the bounds")   # prevented by the spec check
        raise ValueError(f"a {self.kind} is not drawn")

    @property
    def low(self) -> float:
        return min(self.values) if self.kind != "normal" else self.lower

    @property
    def high(self) -> float:
        return max(self.values) if self.kind != "normal" else self.upper


@dataclass(frozen=True)
class AxisDuty:
    """An axis duty cycle of a generator family: ``name``, the ``range`` (lo, hi) [m] of the drawn
    stroke ends, the ``feed`` [m/s] drawn per running step and the ``acceleration`` [m/s2]."""

    name: str
    range: tuple[float, float]
    feed: Dist
    acceleration: float


@dataclass(frozen=True)
class DutyCycle:
    """A generator family: random spindle steps [s, rpm] over ``duration`` [s], a drawn room and
    optional axis duty cycles (:class:`AxisDuty`)."""

    duration: float
    sample_interval: float
    step: Dist
    speed: Dist
    speed_step: float | None
    idle_probability: float
    ambient_kind: str
    ambient: dict   # field -> Dist (SI: degC, K, s)
    axes: tuple = ()   # AxisDuty, one per commanded axis


@dataclass(frozen=True)
class Family:
    """A scenario family: ``cases`` draws of a file scenario (``data``: its parsed TOML) or of a
    generator (``generator``)."""

    name: str
    cases: int
    data: dict | None = None
    file: str = ""
    path: str = ""      # the scenario file read (an input of the command)
    generator: DutyCycle | None = None


@dataclass(frozen=True)
class DatasetSpec:
    source: str
    name: str
    description: str
    machines: tuple[str, ...]
    mesh: str
    solver: str
    effects: str | None
    seed: int
    families: tuple[Family, ...]
    parameters: dict   # "effect.param" -> Dist
    surface_grid: dict | None
    cameras: tuple[str, ...]
    split_by: str
    splits: dict       # case: name -> fraction; family: name -> tuple of families
    text: str = field(default="", repr=False)   # the spec file as written (kept in the card)


class _Table:
    """Keys of one TOML table, read once each; :meth:`finish` refuses the unknown ones."""

    def __init__(self, table, source: str, prefix: str):
        if not isinstance(table, dict):
            raise InputError(source, prefix.rstrip(".") or "toml", "expected a table")
        self.table, self.source, self.prefix, self.used = table, source, prefix, set()

    def field(self, key: str) -> str:
        return self.prefix + key

    def get(self, key: str, default=None, required: bool = False, kind: type | tuple | None = None):
        self.used.add(key)
        if key not in self.table:
            if required:
                raise InputError(self.source, self.field(key), "missing")
            return default
        value = self.table[key]
        if kind is not None and (not isinstance(value, kind) or isinstance(value, bool) and kind is not bool):
            names = kind.__name__ if isinstance(kind, type) else " or ".join(k.__name__ for k in kind)
            raise InputError(self.source, self.field(key), f"expected {_WORDS.get(names, names)}, got {value!r}")
        return value

    def finish(self, known: tuple[str, ...] = ()) -> None:
        unknown = sorted(set(self.table) - self.used)
        if unknown:
            names = sorted(set(self.used) | set(known))
            raise InputError(self.source, self.field(unknown[0]), f"unknown key (known: {', '.join(names)})")


_WORDS = {"str": "a string", "int": "an integer", "list": "a list", "dict": "a table", "float": "a number",
          "int or float": "a number", "str or list": "a string or a list"}


def quantity(value, dimension: str, source: str, field: str) -> float:
    """``value`` ("2 h", "20 degC") as the SI value of ``dimension``; errors name ``field``."""
    try:
        return parse_quantity(value, dimension)
    except UnitError as err:
        raise InputError(source, field, str(err)) from None


def distribution(value, dimension: str, source: str, field: str, lower: float = -math.inf,
                 upper: float = math.inf, grid: bool = False, what: str = "") -> Dist:
    """A quantity, a ``[lo, hi]`` range (uniform) or a one-key table naming a distribution;
    checked: ranges not empty or reversed, log-uniform positive, sd positive, every value (and a
    normal's mean) within ``[lower, upper]`` (``what`` says whose bounds they are)."""
    if isinstance(value, list):
        kind, raw = "uniform", value
    elif isinstance(value, dict):
        if len(value) != 1 or next(iter(value)) not in DISTRIBUTIONS:
            raise InputError(source, field, f"expected one of {', '.join(DISTRIBUTIONS)} (one key), got "
                                            f"{', '.join(map(str, value)) or 'an empty table'}")
        kind, raw = next(iter(value.items()))
        field = f"{field}.{kind}"
    else:
        kind, raw = "fixed", [value]
    if kind == "grid" and not grid:
        raise InputError(source, field, "a grid is allowed for [parameters] only; use a range or a distribution")
    if kind == "fixed" and not isinstance(raw, list):
        raw = [raw]
    if not isinstance(raw, list):
        raise InputError(source, field, f"expected a list of quantities, got {raw!r}")
    need = {"fixed": 1, "uniform": 2, "log_uniform": 2, "normal": 2}.get(kind)
    if need is not None and len(raw) != need:
        raise InputError(source, field, f"a {kind} takes {need} value(s) ([lo, hi] or [mean, sd]), got {len(raw)}")
    if kind == "grid" and not raw:
        raise InputError(source, field, "a grid needs at least one value")
    dims = [dimension] * len(raw)
    if kind == "normal" and dimension == "temperature":
        dims[1] = "temperature_difference"   # the spread of a temperature is a difference
    values = tuple(quantity(v, d, source, f"{field}[{i}]" if len(raw) > 1 else field)
                   for i, (v, d) in enumerate(zip(raw, dims)))
    if kind in ("uniform", "log_uniform") and not values[0] < values[1]:
        raise InputError(source, field, f"empty or reversed range [{raw[0]}, {raw[1]}]; write [lo, hi] with lo < hi")
    if kind == "log_uniform" and values[0] <= 0:
        raise InputError(source, field, f"a log-uniform range must be positive, got {raw[0]}")
    if kind == "normal" and values[1] <= 0:
        raise InputError(source, field, f"the standard deviation must be positive, got {raw[1]}")
    if kind == "grid" and len(set(values)) != len(values):
        raise InputError(source, field, "a grid value is given twice")
    checked = values[:1] if kind == "normal" else values
    for raw_v, v in zip(raw, checked):
        if not lower <= v <= upper:
            bounds = f"[{_fmt(lower)} .. {_fmt(upper)}]".replace("inf", "∞")
            raise InputError(source, field, f"{raw_v} is outside the bounds {what or bounds}")
    return Dist(kind, values, dimension, lower, upper)


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def load_spec(path: str | Path) -> DatasetSpec:
    """Read and check the spec file ``path`` (see the module doc); scenario files it names are
    read now, relative to the spec's folder."""
    path = Path(path)
    data, text = read_toml(path, "spec", "dataset spec")
    return spec_from_dict(data, str(path), path.parent, text)


def spec_from_dict(data: dict, source: str, folder: Path = Path("."), text: str = "") -> DatasetSpec:
    """A :class:`DatasetSpec` from parsed TOML ``data`` (errors name ``source``)."""
    top = _Table(data, source, "")
    name = top.get("name", default=Path(source).stem, kind=str)
    description = top.get("description", default="", kind=str)
    machines = top.get("machines", required=True, kind=list)
    if not machines:
        raise InputError(source, "machines", "names no machine")
    for i, m in enumerate(machines):
        if m not in MACHINES:
            raise InputError(source, f"machines[{i}]", f"unknown machine {m!r}; known: {', '.join(sorted(MACHINES))}")
    if len(set(machines)) != len(machines):
        raise InputError(source, "machines", "a machine is named twice")
    built = {m: build_machine(m) for m in machines}
    mesh = top.get("mesh", default="default", kind=str)
    for m in built.values():
        if mesh not in m.resolutions:
            raise InputError(source, "mesh", f"unknown resolution {mesh!r}; known: {', '.join(m.resolutions)}")
    solver = top.get("solver", default="auto", kind=str)
    if solver not in SOLVERS:
        raise InputError(source, "solver", f"unknown solver {solver!r}; known: {', '.join(SOLVERS)}")
    effects = top.get("effects", kind=str)
    seed = top.get("seed", default=0, kind=int)
    try:
        seed = limits.check_seed(seed)
    except ValueError as err:
        raise InputError(source, "seed", str(err)) from None
    parameters = _parameters(top.get("parameters", default={}, kind=dict), source, built, effects)
    grid, cameras = _observers(top.get("observers", default={}, kind=dict), source, built)
    families = _families(top.get("scenarios", required=True, kind=list), source, folder, built)
    split_by, splits = _splits(top.get("splits"), source, [f.name for f in families])
    top.finish()
    n = len(machines) * math.prod(len(d.values) for d in parameters.values() if d.kind == "grid") \
        * sum(f.cases for f in families)
    if n > MAX_CASES:
        raise InputError(source, "scenarios", f"the plan has {n} cases; at most {MAX_CASES} per dataset")
    return DatasetSpec(source, name, description, tuple(machines), mesh, solver, effects, seed, tuple(families),
                       parameters, grid, cameras, split_by, splits, text)


def _parameters(table: dict, source: str, machines: dict, effects: str | None) -> dict:
    out = {}
    for key in sorted(table):
        field = f"parameters.{key}"
        group, _, name = key.partition(".")
        params = EFFECTS[group].parameters if group in EFFECTS else INSTRUMENTS.get(group)
        if params is None or not name:
            raise InputError(source, field, "expected effect.param or instrument.param with a known effect or "
                                            f"instrument (effects: {', '.join(sorted(EFFECTS))}; instruments: "
                                            f"{', '.join(sorted(INSTRUMENTS))})")
        p = next((p for p in params if p.name == name), None)
        if p is None:
            raise InputError(source, field, f"unknown parameter; known: {', '.join(q.name for q in params)}")
        out[key] = distribution(table[key], p.dimension, source, field, p.lower, p.upper, grid=True,
                                what=p.describe().split(": ")[0].split(" = ")[1].split(" ", 2)[-1])
    for mname, machine in machines.items():   # the effect must be switched on for every machine
        for key, d in out.items():
            try:
                model_spec(machine, effects, [f"{key}={d.values[0]!r} {_unit(d)}"])
            except InputError as err:
                where = "effects" if err.field.startswith("--effects") else f"parameters.{key}"
                raise InputError(source, where, f"{err.message} (machine {mname})") from None
    return out


def _unit(d: Dist) -> str:
    return CANONICAL[d.dimension]


def _observers(table: dict, source: str, machines: dict):
    r = _Table(table, source, "observers.")
    grid = r.get("surface_grid", kind=dict)
    if grid is not None:
        g = _Table(grid, source, "observers.surface_grid.")
        parts = g.get("parts", required=True, kind=list)
        spacing = quantity(g.get("spacing", required=True), "length", source, g.field("spacing"))
        g.finish()
        if not 0.005 <= spacing <= 2.0:
            raise InputError(source, g.field("spacing"), f"must be from 5 mm to 2 m, got {grid['spacing']}")
        for mname, m in machines.items():
            names = [p.name for p in m.parts]
            for i, part in enumerate(parts):
                if part not in names:
                    raise InputError(source, f"{g.field('parts')}[{i}]", f"machine {mname} has no part {part!r}; "
                                                                          f"known: {', '.join(names)}")
        grid = {"parts": list(parts), "spacing": spacing}
    cameras = r.get("cameras", default=[], kind=list)
    for i, c in enumerate(cameras):
        for mname, m in machines.items():
            poses = [p.name for p in getattr(m, "camera_poses", ())] + ["overview-front"]
            if c not in poses:
                raise InputError(source, f"observers.cameras[{i}]", f"machine {mname} has no camera pose {c!r}; "
                                                                     f"known: {', '.join(poses)}")
    r.finish()
    return grid, tuple(cameras)


def _families(items: list, source: str, folder: Path, machines: dict) -> list[Family]:
    if not items:
        raise InputError(source, "scenarios", "expected one or more [[scenarios]] families")
    out, names = [], set()
    for i, raw in enumerate(items):
        r = _Table(raw, source, f"scenarios[{i}].")
        name = r.get("family", required=True, kind=str)
        if not name or not all(c.isalnum() or c in "-_." for c in name):
            raise InputError(source, r.field("family"), f"use letters, digits, '-', '_' or '.', got {name!r}")
        if name in names:
            raise InputError(source, r.field("family"), f"family {name!r} is named twice")
        names.add(name)
        cases = r.get("cases", default=1, kind=int)
        if not 1 <= cases <= MAX_CASES:
            raise InputError(source, r.field("cases"), f"must be from 1 to {MAX_CASES}, got {cases}")
        file = r.get("file", kind=str)
        if file is not None:
            r.finish()
            out.append(_file_family(name, cases, file, source, folder, r.field("file"), machines))
            continue
        gen = _duty_cycle(r, source, machines)
        r.finish(("file",))
        out.append(Family(name, cases, generator=gen))
    return out


def _file_family(name, cases, file, source, folder, field, machines) -> Family:
    bundled = SCENARIO_DIR / f"{file}.toml"
    path = bundled if not file.endswith(".toml") and "/" not in file and bundled.is_file() else folder / file
    if not path.is_file():
        raise InputError(source, field, f"no scenario {file!r} (a bundled name or a path relative to the spec)")
    data, _ = read_toml(path, "scenario", "scenario file")
    sc = scenario_from_dict(data, str(path), default_name=path.stem)   # checked now; errors name the scenario file
    if sc.interferometer is not None or sc.probing is not None:
        raise InputError(str(path), "interferometer" if sc.probing is None else "probing",
                         "the interferometer and probing are not supported in datasets yet (run twin simulate)")
    for m in machines.values():
        limits.check_scenario(sc, m)
        check_motions(sc, m)
    return Family(name, cases, data=data, file=file, path=str(path))


def _duty_cycle(r: _Table, source: str, machines: dict) -> DutyCycle:
    duration = quantity(r.get("duration", required=True), "time", source, r.field("duration"))
    dt = quantity(r.get("sample_interval", default="10 s"), "time", source, r.field("sample_interval"))
    if dt <= 0 or duration <= 0:
        raise InputError(source, r.field("duration" if duration <= 0 else "sample_interval"), "must be positive")
    if abs(duration / dt - round(duration / dt)) > 1e-6:
        raise InputError(source, r.field("duration"), f"must be a multiple of the sample interval ({dt:g} s)")
    limits.check_steps(duration, dt, source, r.field("duration"))
    s = _Table(r.get("spindle", required=True, kind=dict), source, r.field("spindle."))
    step = distribution(s.get("step", required=True), "time", source, s.field("step"), dt, duration,
                        what=f"[sample interval {dt:g} s .. duration {duration:g} s]")
    top = min(limits.max_speed(m) for m in machines.values())
    speed = distribution(s.get("speed", required=True), "speed", source, s.field("speed"), 0.0, top,
                         what=f"[0 .. {top:g} rpm] (the machines' maximum spindle speed)")
    quantum = s.get("speed_step")
    quantum = None if quantum is None else quantity(quantum, "speed", source, s.field("speed_step"))
    if quantum is not None and quantum <= 0:
        raise InputError(source, s.field("speed_step"), "must be positive")
    idle = s.get("idle_probability", default=0.0, kind=(int, float))
    if not 0 <= idle <= 1:
        raise InputError(source, s.field("idle_probability"), f"must be from 0 to 1, got {idle}")
    s.finish()
    a = _Table(r.get("ambient", required=True, kind=dict), source, r.field("ambient."))
    kind = a.get("kind", default="constant", kind=str)
    lo_air, hi_air = limits.AIR_RANGE
    if kind == "constant":
        amb = {"temperature": distribution(a.get("temperature", required=True), "temperature", source,
                                           a.field("temperature"), lo_air, hi_air)}
    elif kind == "daily":
        amb = {"mean": distribution(a.get("mean", required=True), "temperature", source, a.field("mean"), lo_air, hi_air),
               "amplitude": distribution(a.get("amplitude", default="0 K"), "temperature_difference", source,
                                         a.field("amplitude"), 0.0, 30.0),
               "coldest_at": distribution(a.get("coldest_at", default="6 h"), "time", source, a.field("coldest_at"),
                                          0.0, 86400.0),
               "start_time_of_day": distribution(a.get("start_time_of_day", default="0 h"), "time", source,
                                                 a.field("start_time_of_day"), 0.0, 86400.0)}
        if amb["mean"].low - amb["amplitude"].high < lo_air or amb["mean"].high + amb["amplitude"].high > hi_air:
            raise InputError(source, a.field("amplitude"), f"mean +/- amplitude may leave the plausible room air "
                                                           f"range ({lo_air:g} to {hi_air:g} degC)")
    else:
        raise InputError(source, a.field("kind"), f"unknown kind {kind!r}; known for a generator: constant, daily")
    a.finish()
    axes = _axis_duties(r.get("axis", default=[], kind=list), source, r.field("axis"), machines)
    return DutyCycle(duration, dt, step, speed, quantum, float(idle), kind, amb, axes)


def _axis_duties(items: list, source: str, prefix: str, machines: dict) -> tuple[AxisDuty, ...]:
    """The generator's ``[[scenarios.axis]]`` tables, checked against every machine's axes."""
    out = []
    for i, raw in enumerate(items):
        if not isinstance(raw, dict):
            raise InputError(source, f"{prefix}[{i}]", "expected a table with name, range and feed")
        t = _Table(raw, source, f"{prefix}[{i}].")
        name = t.get("name", required=True, kind=str)
        if name in (a.name for a in out):
            raise InputError(source, t.field("name"), f"axis {name!r} is given twice")
        ends = t.get("range", required=True, kind=list)
        if len(ends) != 2:
            raise InputError(source, t.field("range"), 'expected [lo, hi], e.g. ["0 mm", "280 mm"]')
        lo, hi = (quantity(v, "length", source, t.field(f"range[{k}]")) for k, v in enumerate(ends))
        if not hi > lo:
            raise InputError(source, t.field("range"), "expected hi > lo")
        for m in machines.values():
            axis = next((a for a in m.axes if a.name == name), None)
            if axis is None or axis.drive is None:
                raise InputError(source, t.field("name"), f"machine {m.name} has no axis {name!r} with a feed drive; "
                                 f"its driven axes: {', '.join(a.name for a in m.axes if a.drive) or 'none'}")
            if lo < axis.travel[0] - 1e-9 or hi > axis.travel[1] + 1e-9:
                raise InputError(source, t.field("range"), f"outside the {name} travel {axis.travel[0] * 1e3:g} .. "
                                                           f"{axis.travel[1] * 1e3:g} mm of {m.name}")
        feed = distribution(t.get("feed", required=True), "velocity", source, t.field("feed"), 1e-6, 1.0,
                            what="(0 .. 1 m/s]")
        accel = quantity(t.get("acceleration", default="100 mm/s2"), "acceleration", source, t.field("acceleration"))
        if accel <= 0:
            raise InputError(source, t.field("acceleration"), "must be positive")
        t.finish()
        out.append(AxisDuty(name, (lo, hi), feed, accel))
    return tuple(out)


def _splits(table, source: str, families: list[str]):
    if table is None:
        return "case", {"train": 1.0}
    r = _Table(table, source, "splits.")
    by = r.get("by", default="case", kind=str)
    if by not in ("case", "family"):
        raise InputError(source, "splits.by", f"unknown {by!r}; known: case, family")
    out = {}
    for name in SPLIT_NAMES:
        value = r.get(name)
        if value is None:
            continue
        if by == "case":
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 <= value <= 1:
                raise InputError(source, r.field(name), f"expected a fraction from 0 to 1, got {value!r}")
            out[name] = float(value)
        else:
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                raise InputError(source, r.field(name), f"expected a list of families, got {value!r}")
            for v in value:
                if v not in families:
                    raise InputError(source, r.field(name), f"unknown family {v!r}; known: {', '.join(families)}")
            out[name] = tuple(value)
    r.finish(SPLIT_NAMES)
    if not out:
        raise InputError(source, "splits", f"names no split; give {', '.join(SPLIT_NAMES)}")
    if by == "case" and abs(sum(out.values()) - 1.0) > 1e-9:
        raise InputError(source, "splits", f"the fractions add up to {sum(out.values()):g}, not 1")
    if by == "family":
        seen = [f for v in out.values() for f in v]
        twice = sorted({f for f in seen if seen.count(f) > 1})
        if twice:
            raise InputError(source, "splits", f"family {twice[0]!r} is in more than one split")
        missing = [f for f in families if f not in seen]
        if missing:
            raise InputError(source, "splits", f"family {missing[0]!r} is in no split")
    return by, out
