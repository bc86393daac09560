"""Effects from a small TOML file: the causes the library did not foresee.

A user adds a heat source, a surface heat flux or a convection condition on a region of the
machine, with its strength (and unit) and a schedule, and the twin treats it like any library
effect: ``twin simulate/compare --effects-file FILE`` switch the file's effects on, ``twin
diagnose --effects-file FILE`` offers them as candidates and fits their strength. The file::

    [effects.hydraulic_unit]          # the effect's name (letters, digits, '_'; not a library name)
    kind = "heat_flux"                # heat_source (volume), heat_flux (surface) or convection
    region = "bed.+y"                 # a part ("saddle": its cells, or its outer faces for a
                                      # surface kind), "part.+x" (its outer faces facing +x),
                                      # or a list of them
    power = "60 W"                    # heat_source / heat_flux: total power P [W] (negative: removed);
                                      # heat_flux may give flux = "40 W/m2" instead (P = q A)
    schedule = "constant"             # constant | spindle_on | speed | windows | table
    range = ["0 W", "600 W"]          # optional: plausible strength range the diagnosis may fit
                                      # (default: 0 to 10 x the strength, on the strength's side)
    doc = "hydraulic unit behind the bed"   # optional

    # convection instead:  kind = "convection", h = "15 W/m2K", air_offset = "-5 K"
    #   -k dT/dn = h s(t) (T - T_air(t) - offset)
    # schedule = "speed":   reference_speed = "9000 rpm", exponent = 1   s = (n / n_ref)^x
    # schedule = "windows": windows = [["1 h", "2 h"], ["5 h", "5.5 h"]]  s = 1 inside [start, end)
    # schedule = "table":   table = { file = "factor.csv", time_unit = "min" }
    #                       two columns (time, factor) after one header row, linear in between,
    #                       held at the first and last value outside

Every load is the strength times the schedule s(t) (dimensionless): P(t) = P s(t) for sources
and fluxes (linear in P), h(t) = h s(t) for convection (not linear in h). Unknown keys, a missing
key, a wrong unit, an unknown part or direction, an empty region or a bad table raise
:class:`twin.errors.InputError` naming the file and the key.
"""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path

import numpy as np

from geometries.regions import Union, region_by_name
from twin.effects.base import (EFFECTS, Convection, Effect, HeatSource, Parameter, SurfaceHeatFlux, Uncertain,
                               check_declarations)
from twin.errors import InputError
from twin.fem.regions import region_cells, region_facets
from twin.scenario import TableReader
from twin.units import UnitError, format_quantity, parse_quantity

KINDS = {"heat_source": "volume", "heat_flux": "surface", "convection": "surface"}
SCHEDULES = ("constant", "spindle_on", "speed", "windows", "table")
CUSTOM: dict[str, "CustomEffect"] = {}   # the custom effects registered in EFFECTS, by name


class CustomEffect(Effect):
    """An effect read from a user's TOML file (see the module docstring): a strength parameter
    (``power`` [W], ``flux`` [W/m2] or ``h`` [W/(m2 K)]) times a schedule s(t) on a region."""

    custom = True

    def __init__(self, name, kind, region, regions_text, parameter, schedule, air_offset, source, doc):
        self.name, self.kind, self.region, self.regions_text = name, kind, region, regions_text
        self.schedule, self.air_offset, self.source = schedule, air_offset, source
        self.parameters = (parameter,)
        self.strength = parameter.name
        self.linear = kind != "convection"
        self.uncertain = (Uncertain(parameter.name, parameter.lower, parameter.upper,
                                    f"the range given in {source}", linear=self.linear),)
        self.summary = doc or f"custom {kind.replace('_', ' ')} on {regions_text} ({schedule.describe})"
        self.reference = f"user file {source}"
        self.roles = ()
        check_declarations(self)

    def loads(self, mm, scenario, p):
        value = p[self.strength]
        shape = self.schedule.signal(scenario)
        if self.kind == "heat_source":
            cells = region_cells(mm, self.region)
            self._check(len(cells))
            return [HeatSource(self.name, cells, lambda t: value * shape(t))]
        facets = region_facets(mm, self.region)
        self._check(len(facets))
        if self.kind == "heat_flux":
            scale = mm.facet_area(facets) if self.strength == "flux" else 1.0
            return [SurfaceHeatFlux(self.name, facets, lambda t: value * scale * shape(t))]
        off = self.air_offset
        return [Convection(self.name, facets, lambda t: value * shape(t),
                           lambda t: scenario.ambient_temperature(t) + off)]

    def _check(self, count: int) -> None:
        if count == 0:
            raise InputError(self.source, f"effects.{self.name}.region",
                             f"{self.regions_text} has no {'cells' if self.kind == 'heat_source' else 'faces'} "
                             "on this mesh (a face buried inside another part?)")


class Schedule:
    """s(t) [-] of a custom effect: ``kind`` and its data; :meth:`signal` binds a scenario."""

    def __init__(self, kind: str, reference_speed: float = 0.0, exponent: float = 1.0,
                 windows: tuple = (), table: tuple = ()):
        self.kind, self.reference_speed, self.exponent = kind, reference_speed, exponent
        self.windows, self.table = windows, table

    @property
    def describe(self) -> str:
        if self.kind == "speed":
            return f"x (n / {self.reference_speed:g} rpm)^{self.exponent:g}"
        if self.kind == "windows":
            return "in " + ", ".join(f"{a / 3600:g}-{b / 3600:g} h" for a, b in self.windows)
        return {"constant": "constant", "spindle_on": "while the spindle turns", "table": "from a table"}[self.kind]

    def signal(self, scenario):
        """s(t) for times t [s] of ``scenario``."""
        if self.kind == "constant":
            return lambda t: np.ones(np.shape(t))
        if self.kind == "spindle_on":
            return lambda t: (np.abs(scenario.spindle_speed(t)) > 0).astype(float)
        if self.kind == "speed":
            n_ref, x = self.reference_speed, self.exponent
            return lambda t: np.power(np.abs(scenario.spindle_speed(t)) / n_ref, x)
        if self.kind == "windows":
            return lambda t: np.any([(np.asarray(t) >= a) & (np.asarray(t) < b) for a, b in self.windows],
                                    axis=0).astype(float)
        times, factors = self.table
        return lambda t: np.interp(t, times, factors)


_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def read_effects_file(path, machine) -> list[CustomEffect]:
    """The custom effects of TOML file ``path`` for ``machine`` (regions checked against its parts)."""
    from twin.io.paths import read_toml

    path = Path(path)
    data, _ = read_toml(path, "file", "effects file")
    return effects_from_dict(data, str(path), machine, path.parent)


def effects_from_dict(data: dict, source: str, machine, folder: Path = Path(".")) -> list[CustomEffect]:
    """The custom effects of parsed TOML ``data`` (errors name ``source``; tables relative to ``folder``)."""
    top = TableReader(data, source, "")
    table = top.get("effects", required=True)
    top.finish()
    if not isinstance(table, dict) or not table:
        raise InputError(source, "effects", "expected one or more [effects.NAME] tables")
    return [_effect(name, spec, source, Path(folder), machine) for name, spec in table.items()]


def _effect(name: str, spec, src: str, folder: Path, machine) -> CustomEffect:
    where = f"effects.{name}"
    if not _NAME.match(name):
        raise InputError(src, where, "a name is letters, digits and '_', starting with a letter")
    if name in EFFECTS and name not in CUSTOM:
        raise InputError(src, where, "is the name of a library effect; choose another name")
    r = TableReader(spec, src, where + ".")
    kind = r.get("kind", required=True)
    if kind not in KINDS:
        raise InputError(src, where + ".kind", f"unknown kind {kind!r}; known: {', '.join(KINDS)}")
    region, text = _region(r.get("region", required=True), machine, KINDS[kind] == "surface", src, where)
    keys = {"heat_source": ("power",), "heat_flux": ("power", "flux"), "convection": ("h",)}[kind]
    given = [k for k in keys if k in spec]
    if len(given) != 1:
        raise InputError(src, f"{where}.{keys[0]}", f"a {kind} needs exactly one of {', '.join(keys)}")
    pname = given[0]
    dim = {"power": "power", "flux": "heat_flux", "h": "heat_transfer_coefficient"}[pname]
    value = r.get(pname, dim)
    if kind == "convection" and value <= 0:
        raise InputError(src, f"{where}.h", "must be positive")
    lo, hi = _range(r, dim, value, kind, src, where)
    for k in set(keys) - {pname}:
        r.used.add(k)
    air_offset = r.get("air_offset", "temperature_difference", default=0.0) if kind == "convection" else 0.0
    schedule = _schedule(r, src, where, folder)
    doc = str(r.get("doc", default=""))
    r.finish()
    param = Parameter(pname, dim, value, lo, hi, doc or f"{kind.replace('_', ' ')} strength from {src}")
    return CustomEffect(name, kind, region, text, param, schedule, air_offset, src, doc)


def _region(value, machine, surface: bool, src: str, where: str):
    names = value if isinstance(value, list) else [value]
    if not names or not all(isinstance(n, str) for n in names):
        raise InputError(src, where + ".region", "expected a part name, 'part.+x', or a list of them")
    regions = []
    for n in names:
        try:
            regions.append(region_by_name(machine, n, surface))
        except ValueError as err:
            raise InputError(src, where + ".region", str(err)) from None
    return (regions[0] if len(regions) == 1 else Union(tuple(regions))), ", ".join(names)


def _range(r: TableReader, dim: str, value: float, kind: str, src: str, where: str) -> tuple[float, float]:
    raw = r.get("range")
    if raw is None:
        if value == 0:
            raise InputError(src, where + ".range", "a zero strength needs a range to fit it in")
        return (0.0, 10 * value) if value > 0 else (10 * value, 0.0)
    if not isinstance(raw, list) or len(raw) != 2:
        raise InputError(src, where + ".range", "expected [lower, upper] with units")
    try:
        lo, hi = (parse_quantity(v, dim) for v in raw)
    except UnitError as err:
        raise InputError(src, where + ".range", str(err)) from None
    if not lo <= value <= hi or lo == hi:
        raise InputError(src, where + ".range", f"must contain the strength {format_quantity(value, dim)}")
    if kind == "convection" and lo < 0:
        raise InputError(src, where + ".range", "a film coefficient cannot be negative")
    return lo, hi


def _schedule(r: TableReader, src: str, where: str, folder: Path) -> Schedule:
    kind = r.get("schedule", default="constant")
    if kind not in SCHEDULES:
        raise InputError(src, where + ".schedule", f"unknown schedule {kind!r}; known: {', '.join(SCHEDULES)}")
    if kind == "speed":
        n_ref = r.positive("reference_speed", "speed", required=True)
        return Schedule(kind, n_ref, float(r.get("exponent", "dimensionless", default=1.0)))
    if kind == "windows":
        raw = r.get("windows", required=True)
        if not isinstance(raw, list) or not raw:
            raise InputError(src, where + ".windows", "expected a list of [start, end] pairs with units")
        out = []
        for i, w in enumerate(raw):
            if not isinstance(w, list) or len(w) != 2:
                raise InputError(src, f"{where}.windows[{i}]", "expected [start, end]")
            try:
                a, b = (parse_quantity(v, "time") for v in w)
            except UnitError as err:
                raise InputError(src, f"{where}.windows[{i}]", str(err)) from None
            if not b > a:
                raise InputError(src, f"{where}.windows[{i}]", "end must come after start")
            out.append((a, b))
        return Schedule(kind, windows=tuple(out))
    if kind == "table":
        return Schedule(kind, table=_table(r.get("table", required=True), src, where + ".table", folder))
    return Schedule(kind)


def _table(spec, src: str, where: str, folder: Path) -> tuple[np.ndarray, np.ndarray]:
    r = TableReader(spec, src, where + ".")
    path = folder / str(r.get("file", required=True))
    unit = str(r.get("time_unit", required=True))
    r.finish()
    try:
        scale = parse_quantity(f"1 {unit}", "time")
    except UnitError as err:
        raise InputError(src, where + ".time_unit", str(err)) from None
    from twin.io.paths import read_text

    rows = list(csv.reader(io.StringIO(read_text(path, "file", "schedule table"), newline="")))
    if len(rows) < 2 or any(len(row) != 2 for row in rows):
        raise InputError(str(path), "table", "expected a header row and rows of two columns: time, factor")
    try:
        values = np.array([[float(a), float(b)] for a, b in rows[1:]])
    except ValueError as err:
        raise InputError(str(path), "table", f"non-numeric value: {err}") from None
    if not np.all(np.isfinite(values)):
        raise InputError(str(path), "table", "values must be finite")
    times = values[:, 0] * scale
    if np.any(np.diff(times) <= 0):
        raise InputError(str(path), "time", "must increase strictly")
    return times, values[:, 1]


def register_custom(effects: list[CustomEffect]) -> list[str]:
    """Register ``effects`` in :data:`twin.effects.EFFECTS` (replacing an earlier custom effect of
    the same name, never a library effect); returns their names."""
    for e in effects:
        if e.name in EFFECTS and e.name not in CUSTOM:
            raise InputError(e.source, f"effects.{e.name}", "is the name of a library effect")
        EFFECTS[e.name] = CUSTOM[e.name] = e
    return [e.name for e in effects]


def unregister_custom(names=None) -> None:
    """Remove custom effects (all, or ``names``) from the registry."""
    for name in list(CUSTOM if names is None else names):
        if name in CUSTOM:
            del CUSTOM[name]
            EFFECTS.pop(name, None)


def load_effects_file(path, machine) -> list[str]:
    """Read ``path`` for ``machine`` and register its effects; returns their names."""
    return register_custom(read_effects_file(path, machine))
