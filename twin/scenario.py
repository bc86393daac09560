"""Scenarios: what the machine and the room do, read from TOML with explicit units.

A scenario file::

    name = "spindle-heat-cool-9000"
    description = "..."
    sample_interval = "10 s"            # optional, default 10 s; also the time step
    initial_temperature = "20 degC"     # optional, default: the room air at t = 0

    [ambient]                           # one of four kinds
    kind = "constant"                   # temperature = "20 degC"
    # kind = "daily"                    # mean, amplitude, coldest_at (time of day), start_time_of_day (0-24 h)
    # kind = "table"                    # times = ["0 h", ...], temperatures = ["20 degC", ...] (linear),
    #                                   #   covering the whole run from 0 h, as a csv record must
    # kind = "csv"                      # file = "room.csv": measured air, see twin.io.room_csv (linear)

    [[ambient.events]]                  # optional, any kind: a door opened, a holiday (added, in K)
    start = "104 h"                     # when the air begins to change
    change = "-9 K"                     # how far it goes
    fall = "30 min"                     # linear ramp to the change (0 s: a step)
    hold = "0 min"                      # optional: how long it stays there
    recovery = "3 h"                    # linear return to the base (0 s: a step back)
    door = true                         # optional: a door is open from start to fall + hold

    [[spindle]]                         # piecewise-constant steps, in order
    speed = "9000 rpm"
    duration = "120 min"

    [camera]                            # optional thermal camera(s): see twin.camera_config
    pose = "carrier-front"

    [[axis]]                            # optional linear-axis motion: see twin.motion
    name = "Y"
    [[c_axis]]                          # optional C-axis (rotary) steps: see twin.rotary
    speed = "2500 rpm"
    duration = "2 h"

Unknown keys, missing keys, wrong units, non-positive durations, impossible temperatures (below
absolute zero or outside the plausible range of room air), a negative amplitude and runs too long
to afford raise :class:`twin.errors.InputError` naming the file and the key
(:mod:`twin.limits`); a file that is not UTF-8 text, a directory or a device is refused by
:mod:`twin.io.paths`. Speeds are checked against a machine when one runs the scenario
(:func:`twin.limits.check_scenario`), and so, again, are the scenario's own values
(:meth:`Scenario.check`, the loader's checks on a built scenario): one made in Python or changed
with ``dataclasses.replace`` never met the loader.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from twin import limits
from twin.camera_config import cameras_from_toml
from twin.errors import InputError, describe, refuse_unknown_keys
from twin.io.paths import read_toml
from twin.io.room_csv import read_room_csv
from twin.motion import Motion, check_durations, motions_from_toml
from twin.observe.camera import CameraConfig
from twin.observe.interferometer import InterferometerConfig, interferometer_from_toml
from twin.observe.probing import ProbingConfig, probing_from_toml
from twin.rotary import RotarySchedule, c_axis_from_toml, check_duration
from twin.units import UnitError, parse_quantity

SCENARIO_DIR = Path(__file__).resolve().parent.parent / "scenarios"
# the keys a scenario's tables may hold (the readers read them; a misspelled key is named as
# unknown before its correct sibling is reported missing)
SCENARIO_KEYS = ("name", "description", "sample_interval", "initial_temperature", "ambient", "spindle", "camera",
                 "axis", "interferometer", "probing", "c_axis")
AMBIENT_KEYS = ("kind", "temperature", "mean", "amplitude", "coldest_at", "start_time_of_day", "times",
                "temperatures", "file", "events")
EVENT_KEYS = ("start", "change", "fall", "hold", "recovery", "door")
STEP_KEYS = ("speed", "duration")


@dataclass(frozen=True)
class AirEvent:
    """A change of the room air added to the base ambient [K]: a door opened in winter, a
    holiday with the heating turned down. A trapezoid: 0 before ``start``, a linear ramp to
    ``change`` over ``fall``, ``hold`` there, a linear return over ``recovery`` (times [s])."""

    start: float
    change: float
    fall: float
    hold: float = 0.0
    recovery: float = 0.0
    door: bool = False   # a door opened: outside air streams in (the ``door_stream`` effect)

    def __call__(self, t: np.ndarray) -> np.ndarray:
        rel = np.asarray(t, dtype=float) - self.start
        top = self.fall + self.hold
        up = np.clip(rel / self.fall, 0.0, 1.0) if self.fall > 0 else (rel >= 0).astype(float)
        down = np.clip(1.0 - (rel - top) / self.recovery, 0.0, 1.0) if self.recovery > 0 else (rel < top).astype(float)
        return self.change * np.minimum(up, down)

    @property
    def end(self) -> float:
        return self.start + self.fall + self.hold + self.recovery


@dataclass(frozen=True)
class Ambient:
    """Room air temperature T_air(t) [degC]: constant, a daily sine, a linear table (``table``,
    or ``csv`` when it came from a measured record), plus any :class:`AirEvent` s."""

    kind: str
    mean: float = 20.0
    amplitude: float = 0.0
    coldest_at: float = 6 * 3600.0
    start_time_of_day: float = 0.0
    times: tuple[float, ...] = ()
    temperatures: tuple[float, ...] = ()
    events: tuple[AirEvent, ...] = ()
    file: str = ""

    def __call__(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return self.base(t) + sum((e(t) for e in self.events), np.zeros(t.shape))

    def base(self, t: np.ndarray) -> np.ndarray:
        """The air without the events [degC]."""
        t = np.asarray(t, dtype=float)
        if self.kind == "constant":
            return np.full(t.shape, self.mean)
        if self.kind == "daily":
            # T = mean - A cos(2 pi (tod - coldest) / 1 d): coldest at ``coldest_at``
            tod = self.start_time_of_day + t
            return self.mean - self.amplitude * np.cos(2 * np.pi * (tod - self.coldest_at) / 86400.0)
        return np.interp(t, self.times, self.temperatures)


@dataclass(frozen=True)
class Scenario:
    """A schedule: spindle steps (duration [s], speed [rpm]), room air, sample interval [s]."""

    name: str
    steps: tuple[tuple[float, float], ...]
    ambient: Ambient
    sample_interval: float = 10.0
    initial_temperature: float | None = None
    description: str = ""
    source: str = ""
    extra: dict = field(default_factory=dict)
    cameras: tuple = ()  # twin.observe.camera.CameraConfig, from the [camera] section
    axes: tuple = ()     # twin.motion.Motion, one per commanded axis ([[axis]], see twin.motion)
    interferometer: object = None   # twin.observe.interferometer.InterferometerConfig ([interferometer])
    probing: object = None   # twin.observe.probing.ProbingConfig ([probing])
    c_axis: object = None  # twin.rotary.RotarySchedule, from the [[c_axis]] steps

    @property
    def duration(self) -> float:
        return float(sum(d for d, _ in self.steps))

    @property
    def step_starts(self) -> np.ndarray:
        return np.concatenate([[0.0], np.cumsum([d for d, _ in self.steps])])

    def times(self) -> np.ndarray:
        """Output (and time-step) instants 0, dt, 2 dt, ... up to the duration [s]."""
        n = int(round(self.duration / self.sample_interval))
        return np.arange(n + 1) * self.sample_interval

    def spindle_speed(self, t: np.ndarray) -> np.ndarray:
        """Spindle speed [rpm] at times t [s]: each step holds on [start, end); the last holds on."""
        speeds = np.array([s for _, s in self.steps])
        idx = np.searchsorted(self.step_starts[1:], np.asarray(t, dtype=float), side="right")
        return speeds[np.minimum(idx, len(speeds) - 1)]

    def ambient_temperature(self, t: np.ndarray) -> np.ndarray:
        """Room air temperature [degC] at times t [s]."""
        return self.ambient(t)

    @property
    def start_temperature(self) -> float:
        """Uniform machine temperature at t = 0 [degC] (also the zero-strain reference)."""
        if self.initial_temperature is not None:
            return self.initial_temperature
        return float(self.ambient_temperature(np.array([0.0]))[0])

    def check(self) -> None:
        """Raise :class:`InputError` naming the field if a value could not have come from the
        loader (:func:`check_values`): for a scenario built in Python or changed with
        ``dataclasses.replace``; :func:`twin.limits.check_scenario` calls it before a run."""
        check_values(self)


def available() -> list[str]:
    """Names of the bundled scenarios."""
    return sorted(p.stem for p in SCENARIO_DIR.glob("*.toml"))


def scenario_path(name_or_path: str | Path) -> Path:
    """The file of a bundled scenario name, or ``name_or_path`` itself when it is a path (it ends
    in .toml, contains a folder or exists); unknown names raise :class:`InputError`."""
    path = Path(name_or_path)
    if path.suffix == ".toml" or path.exists() or len(path.parts) > 1:
        return path
    bundled = SCENARIO_DIR / f"{name_or_path}.toml"
    if not bundled.is_file():
        raise InputError("command line", "scenario",
                         f"unknown scenario {str(name_or_path)!r}; known: {', '.join(available())} (or a path to a .toml file)")
    return bundled


def load_scenario(name_or_path: str | Path) -> Scenario:
    """A bundled scenario by name, or a TOML file by path."""
    path = scenario_path(name_or_path)
    data, _ = read_toml(path, "scenario", "scenario file")
    return scenario_from_dict(data, str(path), default_name=path.stem)


class _Reader:
    """Reads keys from one TOML table, converting units, remembering which keys were used.

    ``known``: every key the table may hold (for a table whose keys depend on its ``kind``, the
    keys of all kinds, or :meth:`expect` once the kind is read). Before a required key is
    reported missing (:meth:`missing`), a key outside ``known`` is reported as unknown: a
    misspelled ``duraton`` is named, not its correct sibling ``duration``."""

    def __init__(self, table: dict, source: str, prefix: str, known=None):
        if not isinstance(table, dict):
            raise InputError(source, prefix.rstrip("."), f"expected a table, got {describe(table)}")
        self.table, self.source, self.prefix, self.used = table, source, prefix, set()
        self.known = None if known is None else set(known)

    def expect(self, *keys: str) -> None:
        """The keys this table may hold (replacing those given before)."""
        self.known = set(keys)

    def missing(self, key: str, message: str = "missing"):
        """Raise the error that ``key`` is missing (``message``), or, first, that the table holds
        a key it does not know (the likely misspelling of ``key``)."""
        if self.known is not None:
            refuse_unknown_keys(self.table, self.known | self.used, self.source, self.prefix)
        raise InputError(self.source, self.prefix + key, message)

    def get(self, key: str, dimension: str | None = None, default=None, required=False):
        self.used.add(key)
        if key not in self.table:
            if required:
                self.missing(key)
            return default
        value = self.table[key]
        if dimension is None:
            return value
        try:
            return parse_quantity(value, dimension)
        except UnitError as err:
            raise InputError(self.source, self.prefix + key, str(err)) from None

    def positive(self, key: str, dimension: str, **kw) -> float:
        value = self.get(key, dimension, **kw)
        if value is not None and value <= 0:
            raise InputError(self.source, self.prefix + key, f"must be positive, got {describe(self.table[key])}")
        return value

    def speed_step(self, dt: float) -> tuple[float, float]:
        """A step's ``speed`` [rpm] (not negative) and ``duration`` [s] (positive, a multiple of
        the sample interval ``dt`` [s]), both required: a [[spindle]] or [[c_axis]] step."""
        speed = self.get("speed", "speed", required=True)
        if speed < 0:
            raise InputError(self.source, self.prefix + "speed", "must not be negative")
        duration = self.positive("duration", "time", required=True)
        limits.check_whole_samples(duration, dt, self.source, self.prefix + "duration")
        return speed, duration

    def finish(self):
        refuse_unknown_keys(self.table, self.used, self.source, self.prefix)


def scenario_from_dict(data: dict, source: str, default_name: str = "scenario") -> Scenario:
    """Build a :class:`Scenario` from parsed TOML ``data`` (errors name ``source``)."""
    top = _Reader(data, source, "", known=SCENARIO_KEYS)
    name = top.get("name", default=default_name)
    if not isinstance(name, str) or not name.strip():
        raise InputError(source, "name", f"expected a non-empty text, got {describe(name)}")
    description = str(top.get("description", default=""))
    dt = top.positive("sample_interval", "time", default=10.0)
    t0 = top.get("initial_temperature", "temperature")
    if t0 is not None:
        _check_initial(t0, source)
    ambient = _ambient(top.get("ambient", required=True), source)
    raw_steps = top.get("spindle", required=True)
    cameras = cameras_from_toml(top.get("camera"), source, _Reader)
    axes = motions_from_toml(top.get("axis"), source, _Reader)
    laser = interferometer_from_toml(top.get("interferometer"), source, _Reader)
    probing = probing_from_toml(top.get("probing"), source, _Reader)
    c_axis = c_axis_from_toml(top.get("c_axis"), source, _Reader, dt)
    top.finish()
    if not isinstance(raw_steps, list) or not raw_steps:
        raise InputError(source, "spindle", "expected one or more [[spindle]] steps")
    steps = []
    for i, raw in enumerate(raw_steps):
        r = _Reader(raw, source, f"spindle[{i}].", known=STEP_KEYS)
        speed, duration = r.speed_step(dt)
        r.finish()
        steps.append((duration, speed))
    total = sum(d for d, _ in steps)
    # name the culprit: the interval when the durations would be affordable at 1 s, else the durations
    limits.check_steps(total, dt, source, "sample_interval" if total <= limits.MAX_STEPS else "spindle")
    check_durations(axes, total, source)
    check_duration(c_axis, total, source)
    _check_air_covers(ambient, total, source)
    for i, event in enumerate(ambient.events):
        if event.start >= total:
            raise InputError(source, f"ambient.events[{i}].start", f"{event.start / 3600:g} h is at or after the end "
                                                                   f"of the run ({total / 3600:g} h): it would change nothing")
    return Scenario(name, tuple(steps), ambient, dt, t0, description, source, cameras=cameras, axes=axes,
                    interferometer=laser, probing=probing, c_axis=c_axis)


def _ambient(table, source: str) -> Ambient:
    r = _Reader(table, source, "ambient.", known=AMBIENT_KEYS)
    kind = r.get("kind", default="constant")
    if kind == "constant":
        a = Ambient("constant", mean=r.get("temperature", "temperature", required=True))
    elif kind == "daily":
        mean = r.get("mean", "temperature", required=True)
        amplitude = r.get("amplitude", "temperature_difference", required=True)
        times_of_day = {key: r.get(key, "time", default=default)
                        for key, default in (("coldest_at", 6 * 3600.0), ("start_time_of_day", 0.0))}
        a = Ambient("daily", mean=mean, amplitude=amplitude, **times_of_day)
    elif kind == "table":
        times = _list(r, "times", "time", source)
        temps = _list(r, "temperatures", "temperature", source)
        a = Ambient("table", times=tuple(times), temperatures=tuple(temps))
    elif kind == "csv":
        name = r.get("file", required=True)
        if not isinstance(name, str) or not name.strip():
            raise InputError(source, "ambient.file", "expected the path of a CSV file (relative to the scenario)")
        path = Path(source).parent / name if not Path(name).is_absolute() else Path(name)
        times, temps = read_room_csv(path, "ambient.file")
        a = Ambient("csv", times=tuple(times), temperatures=tuple(temps), file=str(path))
    else:
        raise InputError(source, "ambient.kind", f"unknown kind {kind!r}; known: constant, daily, table, csv")
    events = tuple(_event(e, source, i) for i, e in enumerate(_events(r, source)))
    r.finish()
    if events:
        a = replace(a, events=events)
    check_ambient(a, source)
    return a


def check_ambient(a: Ambient, source: str) -> None:
    """The room air's values: temperatures [degC] finite and plausible for room air (a daily
    sine's extremes too, and base + events at their extremes), a daily amplitude not negative and
    its times of day from 0 to 24 h, a table's times increasing with one temperature each, the
    events' times not negative. The loader's checks of ``[ambient]`` (:func:`check_values` runs
    them again on a built scenario)."""
    if not isinstance(a, Ambient):
        raise InputError(source, "ambient", f"expected a twin.scenario.Ambient, got {a!r}")
    if a.kind == "constant":
        limits.check_temperatures(_number(a.mean, source, "ambient.temperature"), source, "ambient.temperature")
    elif a.kind == "daily":
        mean = _number(a.mean, source, "ambient.mean")
        limits.check_temperatures(mean, source, "ambient.mean")
        amplitude = _number(a.amplitude, source, "ambient.amplitude")
        if amplitude < 0:
            raise InputError(source, "ambient.amplitude", f"must not be negative, got {amplitude:g} K")
        for extreme in (mean - amplitude, mean + amplitude):
            limits.check_temperatures(extreme, source, "ambient.amplitude")
        for key in ("coldest_at", "start_time_of_day"):
            value = _number(getattr(a, key), source, f"ambient.{key}")
            if not 0.0 <= value < 86400.0:
                raise InputError(source, f"ambient.{key}", f"a time of day from 0 h to 24 h (excluded), got "
                                                           f"{value / 3600:g} h")
    elif a.kind in ("table", "csv"):
        times = _numbers(a.times, source, "ambient.times")
        temps = _numbers(a.temperatures, source, "ambient.temperatures")
        if len(times) != len(temps) or len(times) < 1:
            raise InputError(source, "ambient.temperatures", "needs as many entries as ambient.times")
        if np.any(np.diff(times) <= 0):
            raise InputError(source, "ambient.times", "must increase strictly")
        limits.check_temperatures(temps, source, "ambient.temperatures")
    else:
        raise InputError(source, "ambient.kind", f"unknown kind {a.kind!r}; known: constant, daily, table, csv")
    if not isinstance(a.events, (tuple, list)):
        raise InputError(source, "ambient.events", f"expected a tuple of twin.scenario.AirEvent, got {a.events!r}")
    for i, e in enumerate(a.events):
        where = f"ambient.events[{i}]"
        if not isinstance(e, AirEvent):
            raise InputError(source, where, f"expected a twin.scenario.AirEvent, got {e!r}")
        _number(e.change, source, f"{where}.change")
        for k in ("start", "fall", "hold", "recovery"):
            if _number(getattr(e, k), source, f"{where}.{k}") < 0:
                raise InputError(source, f"{where}.{k}", f"must not be negative, got {getattr(e, k):g} s")
        if not isinstance(e.door, bool):
            raise InputError(source, f"{where}.door", f"expected true or false, got {describe(e.door)}")
    if a.events:
        # the extremes of base + events: every event at its full change on the base's extremes
        base = a.base(np.linspace(0.0, max(e.end for e in a.events) + 86400.0, 4001))
        low = base.min() + sum(min(e.change, 0.0) for e in a.events)
        high = base.max() + sum(max(e.change, 0.0) for e in a.events)
        limits.check_temperatures([low, high], source, "ambient.events")


def check_values(sc: Scenario) -> None:
    """The loader's checks (:func:`scenario_from_dict`) on a built scenario, for one made in
    Python or changed with ``dataclasses.replace``: a sample interval [s] finite and positive, an
    initial temperature above absolute zero and plausible for a structure, one or more spindle
    steps of a finite positive duration [s] and a number for the speed (the speed's limits are
    the machine's, :func:`twin.limits.check_scenario`), an affordable number of time steps, the
    room air (:func:`check_ambient`), a table or room record covering the run (to half a sample
    interval: a log's last step is snapped to the sample grid), and each spindle step a whole
    number of sample intervals, as the loader asks (otherwise the run's grid ends before the
    scenario or holds the last step past it, and the speeds change between samples: 900 s at 420 s
    steps ran 840 s with the spindle on 420 s instead of 600). Not re-checked, because nothing
    breaks when they are not met: events, axis moves or C-axis steps beyond the end of a run
    shortened in Python (they are never reached)."""
    source = sc.source if isinstance(sc.source, str) and sc.source else sc.name
    _check_types(sc, source)
    dt = _number(sc.sample_interval, source, "sample_interval")
    if dt <= 0:
        raise InputError(source, "sample_interval", f"must be positive, got {dt:g} s")
    if sc.initial_temperature is not None:
        _check_initial(_number(sc.initial_temperature, source, "initial_temperature"), source)
    if not isinstance(sc.steps, (tuple, list)) or not sc.steps:
        raise InputError(source, "spindle", f"expected one or more steps (duration [s], speed [rpm]), got {sc.steps!r}")
    for i, step in enumerate(sc.steps):
        if not isinstance(step, (tuple, list)) or len(step) != 2:
            raise InputError(source, f"spindle[{i}]", f"expected (duration [s], speed [rpm]), got {step!r}")
        if _number(step[0], source, f"spindle[{i}].duration") <= 0:
            raise InputError(source, f"spindle[{i}].duration", f"must be positive, got {step[0]:g} s")
        _number(step[1], source, f"spindle[{i}].speed")
        limits.check_whole_samples(step[0], dt, source, f"spindle[{i}].duration")
    total = sc.duration
    limits.check_steps(total, dt, source, "sample_interval" if total <= limits.MAX_STEPS else "spindle")
    check_ambient(sc.ambient, source)
    _check_air_covers(sc.ambient, total, source, slack=0.5 * dt * (1 + 1e-9))


def _check_types(sc: Scenario, source: str) -> None:
    """The types of a built scenario's fields that the loader would have made: a non-empty name,
    texts for the description and source, a dict of extras, tuples of
    :class:`twin.observe.camera.CameraConfig` and :class:`twin.motion.Motion`, and ``None`` or the
    interferometer's, probing's and C axis's configuration."""
    if not isinstance(sc.name, str) or not sc.name.strip():
        raise InputError(str(source), "name", f"a scenario's name is a non-empty text, got {describe(sc.name)}")
    for key, kind, what in (("description", str, "a text"), ("source", str, "a text"), ("extra", dict, "a dict")):
        if not isinstance(getattr(sc, key), kind):
            raise InputError(source, key, f"expected {what}, got {describe(getattr(sc, key))}")
    for key, kind in (("cameras", CameraConfig), ("axes", Motion)):
        items = getattr(sc, key)
        if not isinstance(items, (tuple, list)):
            raise InputError(source, key, f"expected a tuple of {_qualified(kind)}, got {describe(items)}")
        for i, item in enumerate(items):
            if not isinstance(item, kind):
                raise InputError(source, f"{key}[{i}]", f"expected a {_qualified(kind)}, got {describe(item)}")
    for key, kind in (("interferometer", InterferometerConfig), ("probing", ProbingConfig), ("c_axis", RotarySchedule)):
        value = getattr(sc, key)
        if value is not None and not isinstance(value, kind):
            raise InputError(source, key, f"expected None or a {_qualified(kind)}, got {describe(value)}")


def _qualified(kind: type) -> str:
    return f"{kind.__module__}.{kind.__qualname__}"


def _check_initial(t0: float, source: str) -> None:
    """The machine's start temperature [degC]: above absolute zero and plausible for a structure."""
    limits.check_temperatures(t0, source, "initial_temperature", "structure")


def _check_air_covers(ambient: Ambient, total: float, source: str, slack: float = 0.0) -> None:
    """A room record (csv) or table covers the run's 0 to ``total`` [s] (to ``slack`` [s] at the
    end): nothing is extrapolated."""
    if ambient.kind == "csv" and ambient.times[-1] < total - slack:
        raise InputError(source, "ambient.file", f"the room record {ambient.file} ends at {ambient.times[-1] / 3600:g} h, "
                                                 f"before the scenario's {total / 3600:g} h")
    if ambient.kind == "table" and (ambient.times[0] > 0 or ambient.times[-1] < total - slack):
        raise InputError(source, "ambient.times", f"the table covers {ambient.times[0] / 3600:g} h to "
                                                  f"{ambient.times[-1] / 3600:g} h; it must cover the scenario's 0 to "
                                                  f"{total / 3600:g} h (nothing is extrapolated)")


def _number(value, source: str, field: str) -> float:
    """``value`` as a float when it is a finite number (not a bool, a text or None)."""
    if not limits.is_number(value) or not np.isfinite(value):
        raise InputError(source, field, f"expected a finite number, got {value!r}")
    return float(value)


def _numbers(values, source: str, field: str) -> np.ndarray:
    """``values`` as a 1-D float array when every entry is a finite number."""
    if isinstance(values, np.ndarray):
        if values.ndim != 1 or values.dtype.kind not in "fiu":
            raise InputError(source, field, f"expected a list of numbers, got an array of {values.dtype} {values.shape}")
    elif isinstance(values, (tuple, list)):
        for i, v in enumerate(values):
            if not limits.is_number(v):
                raise InputError(source, f"{field}[{i}]", f"expected a finite number, got {v!r}")
    else:
        raise InputError(source, field, f"expected a list of numbers, got {values!r}")
    out = np.asarray(values, dtype=float)
    bad = np.flatnonzero(~np.isfinite(out))
    if bad.size:
        raise InputError(source, f"{field}[{bad[0]}]", f"expected a finite number, got {out[bad[0]]!r}")
    return out


def _events(r: _Reader, source: str) -> list:
    raw = r.get("events", default=[])
    if not isinstance(raw, list):
        raise InputError(source, "ambient.events", "expected [[ambient.events]] tables")
    return raw


def _event(raw, source: str, i: int) -> AirEvent:
    """One [[ambient.events]] table: start, change, fall, hold, recovery (times >= 0), door."""
    e = _Reader(raw, source, f"ambient.events[{i}].", known=EVENT_KEYS)
    change = e.get("change", "temperature_difference", required=True)
    times = {k: e.get(k, "time", default=0.0, required=k in ("start", "fall")) for k in ("start", "fall", "hold", "recovery")}
    door = e.get("door", default=False)
    e.finish()
    return AirEvent(change=change, door=door, **times)      # its values: check_ambient


def _list(r: _Reader, key: str, dimension: str, source: str) -> list[float]:
    values = r.get(key, required=True)
    if not isinstance(values, list):
        raise InputError(source, r.prefix + key, "expected a list of quantities")
    out = []
    for i, v in enumerate(values):
        try:
            out.append(parse_quantity(v, dimension))
        except UnitError as err:
            raise InputError(source, f"{r.prefix}{key}[{i}]", str(err)) from None
    return out


TableReader = _Reader   # the reader for other input files (custom effects) to share
