"""Effects from a small TOML file: the causes the library did not foresee.

A user adds a heat source, a surface heat flux or a convection condition on a region of the
machine, with its strength (and unit) and a schedule, and the twin treats it like any library
effect: ``twin simulate/compare --effects-file FILE`` switch the file's effects on, ``twin
diagnose --effects-file FILE`` offers them as candidates and fits their strength. The file::

    [effects.hydraulic_unit]          # the effect's name (letters, digits, '_'; not a library name)
    kind = "heat_flux"                # heat_source (volume), heat_flux (surface) or convection
    region = "bed.+y"                 # a part ("saddle": its cells, or its outer faces for a
                                      # surface kind), "part.+x" (its outer faces facing +x),
                                      # or a list of them (each region once, none inside another)
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
    #                       (no two sharing a time; one may end where the next starts)
    # schedule = "table":   table = { file = "factor.csv", time_unit = "min" }
    #                       two columns after one header row naming them, time first, factor
    #                       second ("time,factor"; "t" for time, any case), the time's unit in the
    #                       header ("time [min],factor", time_unit may then be left out) or in
    #                       time_unit (both given must agree); at least two data rows, linear in
    #                       between, covering the whole run from 0 (its end is checked when the run
    #                       starts; nothing is extrapolated)

Every load is the strength times the schedule s(t) (dimensionless): P(t) = P s(t) for sources
and fluxes (linear in P), h(t) = h s(t) for convection (not linear in h). Unknown keys, a missing
key, a wrong unit, an unknown part or direction, a malformed region ("saddle."), a region named
twice or inside another named region ("saddle" with "saddle.+x": the union loads each face once,
not the extra heat the list seems to ask), two windows sharing a time, an empty region or a bad
table (its header included) raise :class:`twin.errors.InputError` naming the file and the key (a
table's own errors name the CSV file and the column).

Plausible limits (one effect on a machine tool; a value beyond them is a unit slip or a typo):

* ``power``: |P| <= :data:`MAX_POWER` (100 kW, the largest machine-tool spindle drives; a
  negative power, a sink such as a chiller, is bounded alike); ``flux``: |q| <= :data:`MAX_FLUX`
  (10 kW/m2, ten times full sunlight); ``h``: 0 < h <= :data:`MAX_H` (10 000 W/(m2 K), a
  coolant jet); ``air_offset``: |offset| <= :data:`MAX_AIR_OFFSET` (100 K: the air stays far above
  absolute zero for any room the scenarios allow). ``range`` lies within the same limits.
* The schedule's largest factor times the strength (and times each end of ``range``) stays within
  those limits too: ``speed`` with ``reference_speed`` from 100 to 60 000 rpm (as the library's
  speed laws) and 0 <= ``exponent`` <= 3 (friction 1, Palmgren 5/3, windage 3), its largest factor
  at the machine's maximum speed; ``table`` factors from 0 to
  :data:`twin.effects.custom_schedule.MAX_FACTOR` (100), finite;
  ``windows`` from the run's start (not negative); ``doc`` is text.
"""

from __future__ import annotations

import re
from pathlib import Path

from geometries.regions import DIRECTIONS, Union, region_by_name
from twin import limits
from twin.effects.base import (EFFECTS, Convection, Effect, HeatSource, Parameter, SurfaceHeatFlux, Uncertain,
                               check_declarations)
from twin.effects.custom_schedule import Schedule, read_schedule
from twin.errors import InputError, describe
from twin.fem.regions import region_cells, region_facets
from twin.io.table_reader import TableReader
from twin.units import UnitError, format_quantity, parse_quantity

KINDS = {"heat_source": "volume", "heat_flux": "surface", "convection": "surface"}
MAX_POWER = 100e3          # W: |P| of one effect (the largest machine-tool spindle drives are ~100 kW)
MAX_FLUX = 10e3            # W/m2: |q| (full sunlight is 1 kW/m2; a radiant heater next to a machine less)
MAX_H = 10e3               # W/(m2 K): a coolant jet on a surface (still air ~5, forced air ~100)
MAX_AIR_OFFSET = 100.0     # K: air = room + offset, room air -40..60 degC (twin.limits.AIR_RANGE)
_LIMITS = {"power": (MAX_POWER, "100 kW", "the largest machine-tool spindle drives deliver about 100 kW"),
           "flux": (MAX_FLUX, "10 kW/m2", "ten times full sunlight"),
           "h": (MAX_H, "10000 W/m2K", "a coolant jet; still air is about 5, forced air about 100 W/m2K")}
# the keys of an [effects.NAME] table: its strength (one of) and the other keys of its kind, and those of every kind
_STRENGTHS = {"heat_source": ("power",), "heat_flux": ("power", "flux"), "convection": ("h",)}
_KIND_KEYS = {"heat_source": ("power",), "heat_flux": ("power", "flux"), "convection": ("h", "air_offset")}
_COMMON_KEYS = ("kind", "region", "schedule", "reference_speed", "exponent", "windows", "table", "range", "doc")
CUSTOM: dict[str, "CustomEffect"] = {}   # the custom effects registered in EFFECTS, by name


class CustomEffect(Effect):
    """An effect read from a user's TOML file (see the module docstring): a strength parameter
    (``power`` [W], ``flux`` [W/m2] or ``h`` [W/(m2 K)]) times a schedule s(t) on a region."""

    custom = True

    def __init__(self, name, kind, region, regions_text, parameter, schedule, air_offset, source, doc,
                 machine: str = ""):
        self.name, self.kind, self.region, self.regions_text = name, kind, region, regions_text
        self.machine = machine   # the machine whose parts the region names (read for it)
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

    def applies_to(self, machine) -> bool:
        """Only to the machine the file was read for: its region names that machine's parts (a
        cframe-vmc file's "saddle" is no place on the gantry, where an effect left registered by
        an earlier call in the same process was offered as a candidate and failed)."""
        return not self.machine or machine.name == self.machine

    def loads(self, mm, scenario, p):
        value = p[self.strength]
        self.schedule.check_reach(scenario, self.source, f"effects.{self.name}")
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


_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def read_effects_file(path, machine) -> list[CustomEffect]:
    """The custom effects of TOML file ``path`` for ``machine`` (regions checked against its parts)."""
    from twin.io.paths import read_toml

    from twin.io.paths import as_path

    path = as_path(path, "--effects-file")
    data, _ = read_toml(path, "--effects-file", "effects file")
    return effects_from_dict(data, str(path), machine, path.parent)


def table_files(path) -> list[tuple[Path, str]]:
    """(path, field) of every schedule table the effects file ``path`` names (``effects.NAME.table.
    file``, relative to the file's folder), read without a machine: a command declares them as its
    inputs before any work (:class:`twin.io.paths.Files`). The file is checked in full later."""
    from twin.io.paths import read_toml

    from twin.io.paths import as_path

    path = as_path(path, "--effects-file")
    data, _ = read_toml(path, "--effects-file", "effects file")
    effects = data.get("effects")
    found = []
    for name, spec in (effects.items() if isinstance(effects, dict) else ()):
        table = spec.get("table") if isinstance(spec, dict) else None
        file = table.get("file") if isinstance(table, dict) else None
        if isinstance(file, str) and file.strip():
            found.append((path.parent / file, f"effects.{name}.table.file"))
    return found


def effects_from_dict(data: dict, source: str, machine, folder: Path = Path(".")) -> list[CustomEffect]:
    """The custom effects of parsed TOML ``data`` (errors name ``source``; tables relative to ``folder``)."""
    stray = sorted(set(data) & set(_COMMON_KEYS + tuple(k for ks in _KIND_KEYS.values() for k in ks)))
    if stray and "effects" not in data:   # an effect's keys without its [effects.NAME] header
        raise InputError(source, stray[0], "an effect's key outside an effect: write [effects.NAME] above the "
                                           "effect's keys")
    top = TableReader(data, source, "", known=("effects",))
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
    r = TableReader(spec, src, where + ".", known=_COMMON_KEYS + tuple(k for ks in _KIND_KEYS.values() for k in ks))
    kind = r.get("kind", required=True)
    if not isinstance(kind, str) or kind not in KINDS:
        raise InputError(src, where + ".kind", f"unknown kind {describe(kind)}; known: {', '.join(KINDS)}")
    r.expect(*_COMMON_KEYS, *_KIND_KEYS[kind])
    region, text = _region(r.get("region", required=True), machine, KINDS[kind] == "surface", src, where)
    keys = _STRENGTHS[kind]
    given = [k for k in keys if k in spec]
    if len(given) != 1:
        r.missing(keys[0], f"a {kind} needs exactly one of {' and '.join(keys)}" if len(keys) > 1 else
                  f"a {kind} needs {keys[0]}")
    pname = given[0]
    dim = {"power": "power", "flux": "heat_flux", "h": "heat_transfer_coefficient"}[pname]
    value = r.get(pname, dim)
    if kind == "convection" and value <= 0:
        raise InputError(src, f"{where}.h", "must be positive")
    _check_strength(value, 1.0, pname, dim, src, f"{where}.{pname}")   # the strength itself
    for k in set(keys) - {pname}:
        r.used.add(k)
    air_offset = r.get("air_offset", "temperature_difference", default=0.0) if kind == "convection" else 0.0
    if abs(air_offset) > MAX_AIR_OFFSET:
        raise InputError(src, f"{where}.air_offset", f"{format_quantity(air_offset, 'temperature_difference')} is "
                                                     f"beyond +-{MAX_AIR_OFFSET:g} K: the air (room + offset) would be "
                                                     "implausibly hot or cold, or below absolute zero")
    schedule = read_schedule(r, src, where, folder)
    peak, why = schedule.peak(machine), _why(schedule, machine)
    _check_strength(value, peak, pname, dim, src, f"{where}.{pname}", why)    # its largest load
    lo, hi = _range(r, dim, value, kind, src, where, pname, peak, why)
    doc = r.get("doc", default="")
    if not isinstance(doc, str):
        raise InputError(src, where + ".doc", f"expected text, got {describe(doc)}")
    r.finish()
    param = Parameter(pname, dim, value, lo, hi, doc or f"{kind.replace('_', ' ')} strength from {src}")
    return CustomEffect(name, kind, region, text, param, schedule, air_offset, src, doc, machine.name)


def _region(value, machine, surface: bool, src: str, where: str):
    names = value if isinstance(value, list) else [value]
    if not names or not all(isinstance(n, str) for n in names):
        raise InputError(src, where + ".region", "expected a part name, 'part.+x', or a list of them")
    for n in names:             # "saddle." is no "saddle": a face direction left out, or a stray dot
        pieces = n.split(".")
        if len(pieces) > 2 or not all(q and q == q.strip() for q in pieces):
            part = pieces[0].strip() or machine.parts[0].name
            forms = (f"a part's name ({part!r}) or its outer faces facing one way ({part + '.+x'!r}; directions "
                     f"{', '.join(DIRECTIONS)})" if surface else
                     f"a part's name ({part!r}): a volume load fills the part's cells, it takes no face direction")
            raise InputError(src, where + ".region", f"{n!r} is malformed; a region is {forms}")
    twice = next((n for n in names if names.count(n) > 1), None)
    if twice is not None:       # the union would hold it once: a doubled power it does not give
        raise InputError(src, where + ".region", f"{twice!r} named more than once; name each region once")
    regions = []
    for n in names:
        try:
            regions.append(region_by_name(machine, n, surface))
        except ValueError as err:
            raise InputError(src, where + ".region", str(err)) from None
    # Distinct parts own distinct faces and a face faces one direction, so the only overlap left is
    # a part with its own faces ("saddle" and "saddle.+x"): the union holds each face once (the
    # power is spread over it, not added), so the +x faces get no extra heat, which the list seems
    # to ask; refused, as a region named twice.
    within = next((n for n in names if "." in n and n.partition(".")[0] in names), None)
    if within is not None:
        part = within.partition(".")[0]
        raise InputError(src, where + ".region", f"{within!r} overlaps {part!r}, also named, which holds all of "
                                                 f"{part}'s outer faces: a face is loaded once, not once per name "
                                                 "that covers it; name the part or its faces, not both")
    return (regions[0] if len(regions) == 1 else Union(tuple(regions))), ", ".join(names)


def _check_strength(value: float, peak: float, pname: str, dim: str, src: str, field: str, why: str = "") -> None:
    """Refuse a strength whose size times the schedule's largest factor ``peak`` is beyond the
    plausible limit of ``pname`` (:data:`_LIMITS`)."""
    limit, text, reason = _LIMITS[pname]
    if abs(value) * peak > limit:
        what = format_quantity(value, dim) + (f" x {why}" if why and peak != 1.0 else "")
        raise InputError(src, field, f"{what} is beyond {'' if pname == 'h' else '+-'}{text} for one effect on a "
                                     f"machine tool ({reason}); check the unit")


def _why(schedule: Schedule, machine) -> str:
    """How the error about a strength times the schedule's largest factor names that factor."""
    peak = schedule.peak(machine)
    if schedule.kind == "speed":
        return (f"the speed schedule's factor {peak:.4g} at machine {getattr(machine, 'name', '?')}'s maximum of "
                f"{limits.max_speed(machine):g} rpm")
    return f"the table's largest factor {peak:g}" if schedule.kind == "table" else ""


def _range(r: TableReader, dim: str, value: float, kind: str, src: str, where: str, pname: str,
           peak: float, why: str) -> tuple[float, float]:
    raw = r.get("range")
    if raw is None:
        if value == 0:
            raise InputError(src, where + ".range", "a zero strength needs a range to fit it in")
        top = _LIMITS[pname][0] / max(peak, 1.0)    # 10 x the strength, within the limits
        return (0.0, min(10 * value, top)) if value > 0 else (max(10 * value, -top), 0.0)
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
    for end in (lo, hi):
        _check_strength(end, 1.0, pname, dim, src, where + ".range")
        _check_strength(end, peak, pname, dim, src, where + ".range", why)
    return lo, hi


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
    """Read ``path`` for ``machine`` (a built :class:`geometries.base.Machine`) and register its
    effects; returns their names."""
    from twin.limits import check_machine

    check_machine(machine, "load_effects_file")
    return register_custom(read_effects_file(path, machine))
