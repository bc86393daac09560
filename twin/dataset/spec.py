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
                                        # (each part once; leave surface_grid out for no grid)
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
    speed_step = "500 rpm"              # optional: speeds rounded to multiples of it (one must lie in the range)
    idle_probability = 0.3              # optional: the chance that a step is a stop
    [scenarios.ambient]
    kind = "daily"                      # or "constant" with temperature = ...
    mean = ["18 degC", "22 degC"]       # each field a value, a [lo, hi] range or a distribution
    amplitude = ["0 K", "3 K"]
    coldest_at = ["0 h", "24 h"]        # the phase of the day
    start_time_of_day = "8 h"
    # kind = "csv" with file = "room.csv" (relative to the spec), or kind = "table" with times and
    # temperatures: a fixed room, the same in every case, held in each case as a table
    [[scenarios.ambient.events]]        # optional, any kind: each time and change drawn per case
    start = ["1 h", "3 h"]
    change = "-8 K"
    fall = "20 min"                     # hold, recovery (default 0 s) and door (default false)
    door = true
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

A generator field given as ``[lo, hi]`` is uniform; a table names the distribution. A normal is
truncated to the field's or parameter's bounds and drawn exactly from that truncation (its inverse
CDF at one uniform a draw: no redrawing). A ``grid`` is allowed for parameters only: the plan
crosses every grid point with every draw. Unknown keys, wrong units, empty or reversed ranges,
values outside a parameter's bounds or a machine's speed limit, a normal with less than 1e-6 of
its probability within the bounds (a standard deviation that dwarfs them) raise
:class:`twin.errors.InputError` naming the spec file and the field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from geometries import MACHINES, build_machine
from twin import limits
from twin.dataset.families import Family, read_families
from twin.dataset.fields import MAX_CASES, Dist, distribution, quantity
from twin.io.table_reader import TableReader
from twin.effects import EFFECTS
from twin.errors import InputError, describe
from twin.io.paths import as_path, read_toml
from twin.model import model_spec, parse_effects
from twin.observe.instruments import INSTRUMENTS
from twin.scenario import SCENARIO_DIR
from twin.units import CANONICAL

SOLVERS = ("auto", "direct", "iterative", "rom")
SPLIT_NAMES = ("train", "validation", "test")
SPEC_KEYS = ("name", "description", "machines", "mesh", "solver", "effects", "seed", "parameters", "observers",
             "scenarios", "splits")   # a spec's top-level keys


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


def bundled_specs() -> list[str]:
    """Names of the dataset specs that come with the package (``scenarios/datasets/``)."""
    return sorted(p.stem for p in (SCENARIO_DIR / "datasets").glob("*.toml"))


def spec_path(name_or_path: str) -> str:
    """The file of a bundled dataset spec's name, or ``name_or_path`` itself when it is a path
    (it ends in .toml, contains a folder or exists), as :func:`twin.scenario.scenario_path` does
    for scenarios; an unknown name raises :class:`InputError` listing the bundled ones."""
    path = as_path(name_or_path, "spec")
    if path.suffix == ".toml" or path.exists() or len(path.parts) > 1:
        return name_or_path
    bundled = SCENARIO_DIR / "datasets" / f"{name_or_path}.toml"
    if not bundled.is_file():
        raise InputError(name_or_path, "spec", f"no such dataset spec; bundled: {', '.join(bundled_specs())} "
                                               "(or a path to a .toml file)")
    return str(bundled)


def load_spec(path: str | Path) -> DatasetSpec:
    """Read and check the spec file ``path`` (see the module doc); scenario files it names are
    read now, relative to the spec's folder."""
    path = as_path(path, "spec")
    data, text = read_toml(path, "spec", "dataset spec")
    return spec_from_dict(data, str(path), path.parent, text)


def spec_from_dict(data: dict, source: str, folder: Path = Path("."), text: str = "") -> DatasetSpec:
    """A :class:`DatasetSpec` from parsed TOML ``data`` (errors name ``source``)."""
    top = TableReader(data, source, "", known=SPEC_KEYS)
    name = top.get("name", default=Path(source).stem, kind=str)
    description = top.get("description", default="", kind=str)
    machines = top.get("machines", required=True, kind=list)
    if not machines:
        raise InputError(source, "machines", "names no machine")
    for i, m in enumerate(machines):
        if not isinstance(m, str) or m not in MACHINES:
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
    families = read_families(top.get("scenarios", required=True, kind=list), source, folder, built)
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
            _switched_on(key, effects, machine, source)
            try:
                model_spec(machine, effects, [f"{key}={d.values[0]!r} {_unit(d)}"])
            except InputError as err:
                effect = err.field.startswith("--effects")
                where = "effects" if effect else f"parameters.{key}"
                named = f"{err.field.removeprefix('--effects').strip()}: " if effect else ""
                raise InputError(source, where, f"{named}{err.message} (machine {mname})") from None
    return out


def _switched_on(key: str, effects: str | None, machine, source: str) -> None:
    """The effect of parameter ``key`` is switched on for ``machine`` by the spec's ``effects``
    key (a bad ``effects`` text is left to :func:`twin.model.model_spec` to report)."""
    group = key.partition(".")[0]
    if group not in EFFECTS:
        return
    try:
        on = parse_effects(effects, tuple(machine.default_effects))
    except InputError:
        return
    if group not in on and not EFFECTS[group].applies_to(machine):
        raise InputError(source, f"parameters.{key}", f"effect {group!r} does not apply to machine {machine.name} "
                                                      f"(twin list effects --machine {machine.name} lists those "
                                                      "that do)")
    if group not in on:
        items = [] if not effects else [effects]
        edits = not effects or effects.strip()[0] in "+-"
        fix = ",".join(items + [("+" if edits else "") + group])
        raise InputError(source, f"parameters.{key}", f"effect {group!r} is not switched on for machine "
                                                      f"{machine.name}; switch it on with the spec's effects key: "
                                                      f"effects = \"{fix}\"")


def _unit(d: Dist) -> str:
    return CANONICAL[d.dimension]


def _observers(table: dict, source: str, machines: dict):
    r = TableReader(table, source, "observers.", known=("surface_grid", "cameras"))
    grid = r.get("surface_grid", kind=dict)
    if grid is not None:
        g = TableReader(grid, source, "observers.surface_grid.", known=("parts", "spacing"))
        parts = g.get("parts", required=True, kind=list)
        spacing = quantity(g.get("spacing", required=True), "length", source, g.field("spacing"))
        g.finish()
        if not parts:
            raise InputError(source, g.field("parts"), "names no part; name one or more, or leave surface_grid out "
                                                       "for no grid")
        for i, part in enumerate(parts):
            if not isinstance(part, str):
                raise InputError(source, f"{g.field('parts')}[{i}]", f"expected a part name, got {describe(part)}")
        twice = sorted({p for p in parts if parts.count(p) > 1})
        if twice:
            raise InputError(source, g.field("parts"), f"part {twice[0]!r} is named more than once")
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
    twice = sorted({str(c) for c in cameras if cameras.count(c) > 1})
    if twice:
        raise InputError(source, "observers.cameras", f"camera pose {twice[0]!r} is named more than once")
    for i, c in enumerate(cameras):
        for mname, m in machines.items():
            poses = [p.name for p in getattr(m, "camera_poses", ())] + ["overview-front"]
            if c not in poses:
                raise InputError(source, f"observers.cameras[{i}]", f"machine {mname} has no camera pose {c!r}; "
                                                                     f"known: {', '.join(poses)}")
    r.finish()
    return grid, tuple(cameras)


def _splits(table, source: str, families: list[str]):
    if table is None:
        return "case", {"train": 1.0}
    r = TableReader(table, source, "splits.")
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
                raise InputError(source, r.field(name), f"expected a fraction from 0 to 1, got {describe(value)}")
            out[name] = float(value)
        else:
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                raise InputError(source, r.field(name), f"expected a list of families, got {describe(value)}")
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
