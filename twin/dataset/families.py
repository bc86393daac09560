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
from twin.io.paths import read_toml, same_file
from twin.motion_checks import check_motions
from twin.scenario import SCENARIO_DIR, scenario_from_dict
from twin.ambient import EVENT_KEYS, ambient_from_toml, check_air_covers

# the keys of a [[scenarios]] family: a scenario file, or a duty-cycle generator
FAMILY_KEYS = ("family", "cases", "file", "duration", "sample_interval", "spindle", "ambient", "axis")
GENERATOR_AMBIENT_KEYS = ("kind", "temperature", "mean", "amplitude", "coldest_at", "start_time_of_day", "times",
                          "temperatures", "file", "events")


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
    room: dict | None = None   # a fixed room record ("table" or "csv"): {"times": [...], "temperatures": [...]}
    events: tuple = ()         # per [[scenarios.ambient.events]]: field -> Dist, and "door" (bool)
    room_file: str = ""        # the CSV the room was read from (an input of the command)


@dataclass(frozen=True)
class Family:
    """A scenario family: ``cases`` draws of a file scenario (``data``: its parsed TOML) or of a
    generator (``generator``)."""

    name: str
    cases: int
    data: dict | None = None
    file: str = ""
    generator: DutyCycle | None = None
    inputs: tuple = ()  # (path, the family's key that names it, what it is): files the command reads


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
        gen = _duty_cycle(r, source, machines, folder)
        r.finish(("file",))
        room = ((gen.room_file, "ambient.file", "room record"),) if gen.room_file else ()
        out.append(Family(name, cases, generator=gen, inputs=room))
    return out


def _file_family(name, cases, file, source, folder, field, machines) -> Family:
    bundled = SCENARIO_DIR / f"{file}.toml"
    path = bundled if not file.endswith(".toml") and "/" not in file and bundled.is_file() else folder / file
    if not path.is_file():
        raise InputError(source, field, f"no scenario {file!r} (a bundled name or a path relative to the spec)")
    if same_file(path, source):       # read as a scenario, the spec only said "machines: unknown key"
        raise InputError(source, field, f"{file!r} is this spec itself; name a scenario file")
    data, _ = read_toml(path, "scenario", "scenario file")
    sc = scenario_from_dict(data, str(path), default_name=path.stem)   # checked now; errors name the scenario file
    if sc.interferometer is not None or sc.probing is not None:
        raise InputError(str(path), "interferometer" if sc.probing is None else "probing",
                         "the interferometer and probing are not supported in datasets yet (run twin simulate)")
    for m in machines.values():
        limits.check_scenario(sc, m)
        check_motions(sc, m)
    inputs = ((str(path), "file", "scenario file"),)
    if sc.ambient.kind == "csv":     # the case holds the record, read relative to the scenario file
        data = {**data, "ambient": {**data["ambient"], **room_table(sc.ambient)}}
        del data["ambient"]["file"]
        inputs += ((sc.ambient.file, "file", "room record (the scenario's ambient.file)"),)
    return Family(name, cases, data=data, file=file, inputs=inputs)


def room_table(room) -> dict:
    """A room record or table (:class:`twin.ambient.Ambient`) as a scenario's ``[ambient]`` keys
    of kind ``table`` (times [s] and temperatures [degC] as exact quantity texts): a dataset's case
    holds the record itself, so its hash covers the values and it needs no file beside the spec."""
    return {"kind": "table", "times": [f"{float(t)!r} s" for t in room.times],
            "temperatures": [f"{float(v)!r} degC" for v in room.temperatures]}


def _duty_cycle(r: TableReader, source: str, machines: dict, folder: Path) -> DutyCycle:
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
    raw = r.get("ambient", required=True, kind=dict)
    a = TableReader(raw, source, r.field("ambient."), known=GENERATOR_AMBIENT_KEYS)
    kind = a.get("kind", default="constant", kind=str)
    lo_air, hi_air = limits.AIR_RANGE
    room, room_file, amb = None, "", {}
    if kind == "constant":
        amb = {"temperature": distribution(a.get("temperature", required=True), "temperature", source,
                                           a.field("temperature"), lo_air, hi_air)}
        air = (amb["temperature"].low, amb["temperature"].high)
    elif kind == "daily":
        amb = {"mean": distribution(a.get("mean", required=True), "temperature", source, a.field("mean"), lo_air, hi_air),
               "amplitude": distribution(a.get("amplitude", default="0 K"), "temperature_difference", source,
                                         a.field("amplitude"), 0.0, 30.0),
               "coldest_at": distribution(a.get("coldest_at", default="6 h"), "time", source, a.field("coldest_at"),
                                          0.0, 86400.0),
               "start_time_of_day": distribution(a.get("start_time_of_day", default="0 h"), "time", source,
                                                 a.field("start_time_of_day"), 0.0, 86400.0)}
        air = (amb["mean"].low - amb["amplitude"].high, amb["mean"].high + amb["amplitude"].high)
        if air[0] < lo_air or air[1] > hi_air:
            raise InputError(source, a.field("amplitude"), f"mean +/- amplitude may leave the plausible room air "
                                                           f"range ({lo_air:g} to {hi_air:g} degC)")
    elif kind in ("table", "csv"):
        record = _fixed_room(raw, duration, source, a, folder)
        room, room_file = room_table(record), record.file
        air = (min(record.temperatures), max(record.temperatures))
    else:
        raise InputError(source, a.field("kind"), f"unknown kind {kind!r}; known for a generator: constant, daily, "
                                                  "table, csv")
    events = _air_events(a.get("events", default=[], kind=list), duration, air, source, a.field("events"))
    a.finish()
    if room is not None:
        kind = room.pop("kind")     # "table": a case holds the record itself, not a file beside the spec
    axes = _axis_duties(r.get("axis", default=[], kind=list), source, r.field("axis"), machines)
    return DutyCycle(duration, dt, step, speed, quantum, float(idle), kind, amb, axes, room, events, room_file)


def _fixed_room(raw: dict, duration: float, source: str, a: TableReader, folder: Path):
    """A generator's fixed room, ``kind = "table"`` (times, temperatures) or ``"csv"`` (a file
    relative to the spec, :mod:`twin.io.room_csv`), read and checked by the scenario reader
    (covering the family's ``duration``): the same air in every case, events drawn on top.
    Returns the record (:class:`twin.ambient.Ambient`; ``file``: the CSV's path, or "")."""
    for key in ("times", "temperatures", "file"):
        a.get(key)                        # read here: known to the reader, checked below
    keys = {"table": ("times", "temperatures"), "csv": ("file",)}[raw["kind"]]
    stray = [k for k in ("times", "temperatures", "file") if k in raw and k not in keys]
    if stray:
        raise InputError(source, a.field(stray[0]), f"is not read by kind {raw['kind']!r} (it takes "
                                                    f"{', '.join(keys)})")
    here = str(folder / "spec")          # a csv file is read relative to the spec's folder
    try:
        room = ambient_from_toml({k: raw[k] for k in ("kind", *keys) if k in raw}, here)
        check_air_covers(room, duration, here)
    except InputError as err:            # the scenario reader's "ambient.KEY" is this family's
        if not err.field.startswith("ambient."):
            raise                        # a CSV's own error: its file and column
        raise InputError(source if err.source == here else err.source, a.field(err.field[len("ambient."):]),
                         err.message) from None
    return room


def _air_events(items: list, duration: float, air: tuple, source: str, prefix: str) -> tuple:
    """The generator's ``[[scenarios.ambient.events]]``: each time or change a value, a range or
    a distribution (drawn per case, like the room's fields), ``door`` true or false; a start
    before the family's end, and the room with every event at its extreme within the plausible
    room air."""
    out = []
    for i, raw in enumerate(items):
        if not isinstance(raw, dict):
            raise InputError(source, f"{prefix}[{i}]", "expected a table with start, change, fall (hold, recovery, "
                                                       "door optional)")
        e = TableReader(raw, source, f"{prefix}[{i}].", known=EVENT_KEYS)
        event = {"change": distribution(e.get("change", required=True), "temperature_difference", source,
                                        e.field("change"), -40.0, 40.0, what="[-40 .. 40 K]")}
        for key in ("start", "fall", "hold", "recovery"):
            value = e.get(key, required=key in ("start", "fall"), default="0 s")
            top = duration if key == "start" else 30 * 86400.0
            event[key] = distribution(value, "time", source, e.field(key), 0.0, top,
                                      what=f"[0 .. {duration:g} s] (the family's duration)" if key == "start"
                                      else "[0 .. 30 d]")
        if event["start"].high >= duration:
            raise InputError(source, e.field("start"), f"may fall at or after the end of the family's "
                                                       f"{duration / 3600:g} h")
        event["door"] = e.get("door", default=False, kind=bool)
        e.finish()
        out.append(event)
    lo_air, hi_air = limits.AIR_RANGE
    low = air[0] + sum(min(ev["change"].low, 0.0) for ev in out)
    high = air[1] + sum(max(ev["change"].high, 0.0) for ev in out)
    if out and (low < lo_air or high > hi_air):
        raise InputError(source, prefix, f"the room with every event at its extreme spans {low:g} .. {high:g} degC, "
                                         f"outside the plausible room air ({lo_air:g} to {hi_air:g} degC)")
    return tuple(out)


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
        if isinstance(raw.get("range"), dict):
            raise InputError(source, t.field("range"), 'expected [lo, hi] with units, e.g. ["0 mm", "280 mm"], not a '
                             'distribution: each stroke\'s ends are drawn uniformly within the range')
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
        limits.check_acceleration(accel, source, t.field("acceleration"))
        t.finish()
        out.append(AxisDuty(name, (lo, hi), feed, accel))
    return tuple(out)
