"""A dataset spec's scenario families (``[[scenarios]]``): a scenario file drawn ``cases`` times,
or a generator of random duty cycles: spindle steps, a drawn room and optional axis duty cycles.

The fields, and how a generated axis follows the spindle, are documented in
:mod:`twin.dataset.spec`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from twin import limits
from twin.dataset.fields import MAX_CASES, Dist, distribution, quantity
from twin.io.table_reader import TableReader
from twin.errors import InputError
from twin.io.paths import read_toml
from twin.motion_checks import check_motions
from twin.scenario import SCENARIO_DIR, scenario_from_dict

# the keys of a [[scenarios]] family: a scenario file, or a duty-cycle generator
FAMILY_KEYS = ("family", "cases", "file", "duration", "sample_interval", "spindle", "ambient", "axis")


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


def read_families(items: list, source: str, folder: Path, machines: dict) -> list[Family]:
    if not items:
        raise InputError(source, "scenarios", "expected one or more [[scenarios]] families")
    out, names = [], set()
    for i, raw in enumerate(items):
        r = TableReader(raw, source, f"scenarios[{i}].", known=FAMILY_KEYS)
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


def _duty_cycle(r: TableReader, source: str, machines: dict) -> DutyCycle:
    duration = quantity(r.get("duration", required=True), "time", source, r.field("duration"))
    dt = quantity(r.get("sample_interval", default="10 s"), "time", source, r.field("sample_interval"))
    if dt <= 0 or duration <= 0:
        raise InputError(source, r.field("duration" if duration <= 0 else "sample_interval"), "must be positive")
    limits.check_whole_samples(duration, dt, source, r.field("duration"))
    limits.check_steps(duration, dt, source, r.field("duration"))
    s = TableReader(r.get("spindle", required=True, kind=dict), source, r.field("spindle."),
                    known=("step", "speed", "speed_step", "idle_probability"))
    step = distribution(s.get("step", required=True), "time", source, s.field("step"), dt, duration,
                        what=f"[sample interval {dt:g} s .. duration {duration:g} s]")
    top = min(limits.max_speed(m) for m in machines.values())
    speed = distribution(s.get("speed", required=True), "speed", source, s.field("speed"), 0.0, top,
                         what=f"[0 .. {top:g} rpm] (the machines' maximum spindle speed)")
    quantum = s.get("speed_step")
    quantum = None if quantum is None else quantity(quantum, "speed", source, s.field("speed_step"))
    if quantum is not None and quantum <= 0:
        raise InputError(source, s.field("speed_step"), "must be positive")
    if quantum is not None and math.ceil(max(speed.low, 0.0) / quantum - 1e-9) * quantum > speed.high:
        raise InputError(source, s.field("speed_step"), f"no multiple of {quantum:g} rpm lies within the speeds "
                                                        f"{speed.low:g} .. {speed.high:g} rpm: every running step "
                                                        "would be rounded off them")
    idle = s.get("idle_probability", default=0.0, kind=(int, float))
    if not 0 <= idle <= 1:
        raise InputError(source, s.field("idle_probability"), f"must be from 0 to 1, got {idle}")
    s.finish()
    a = TableReader(r.get("ambient", required=True, kind=dict), source, r.field("ambient."),
                    known=("kind", "temperature", "mean", "amplitude", "coldest_at", "start_time_of_day"))
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
        t = TableReader(raw, source, f"{prefix}[{i}].", known=("name", "range", "feed", "acceleration"))
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
