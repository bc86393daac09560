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

from dataclasses import dataclass, field
import os
from pathlib import Path

import numpy as np

from twin import limits
from twin.ambient import AirEvent, Ambient, ambient_from_toml, check_air_covers, check_ambient
from twin.camera_config import cameras_from_toml
from twin.errors import InputError, describe
from twin.io.paths import as_path, read_toml
from twin.io.table_reader import TableReader
from twin.motion import Motion, motions_from_toml
from twin.motion_checks import check_durations
from twin.observe.camera import CameraConfig
from twin.observe.interferometer import InterferometerConfig, interferometer_from_toml
from twin.observe.probing import ProbingConfig, probing_from_toml
from twin.rotary import RotarySchedule, c_axis_from_toml, check_duration, check_schedule

SCENARIO_DIR = Path(__file__).resolve().parent.parent / "scenarios"
# the keys a scenario's tables may hold (the readers read them; a misspelled key is named as
# unknown before its correct sibling is reported missing)
SCENARIO_KEYS = ("name", "description", "sample_interval", "initial_temperature", "ambient", "spindle", "camera",
                 "axis", "interferometer", "probing", "c_axis")
STEP_KEYS = ("speed", "duration")
__all__ = ["AirEvent", "Ambient", "Scenario", "TableReader", "available", "check_ambient", "load_scenario",
           "scenario_from_dict", "scenario_path"]


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
    in .toml, contains a folder or exists); unknown names raise :class:`InputError`, and so does a
    bare name that is both a bundled scenario and a file in the working folder (which one was
    meant cannot be told)."""
    path = as_path(name_or_path, "scenario")      # '' would be the working folder
    bundled = SCENARIO_DIR / f"{name_or_path}.toml"
    spelled_as_path = path.suffix == ".toml" or any(sep in str(name_or_path) for sep in ("/", os.sep))
    if not spelled_as_path and path.exists() and bundled.is_file():
        raise InputError("command line", "scenario",
                         f"{str(name_or_path)!r} is both a bundled scenario and a file here; write ./{path} for the "
                         "file, or rename it (a .toml name is always a file)")
    if path.suffix == ".toml" or path.exists() or len(path.parts) > 1:
        return path
    if not bundled.is_file():
        raise InputError("command line", "scenario",
                         f"unknown scenario {str(name_or_path)!r}; known: {', '.join(available())} (or a path to a .toml file)")
    return bundled


def recorded_source(source: str) -> str:
    """What a result records as a scenario's source: ``bundled:NAME`` for a scenario shipped with
    the package (its install path says where the package lies, not what was run, and would make
    the same run's bytes differ between installs), else the path as typed."""
    path = Path(source)
    if path.suffix == ".toml" and path.parent.resolve() == SCENARIO_DIR and path.is_file():
        return f"bundled:{path.stem}"
    return source


def load_scenario(name_or_path: str | Path) -> Scenario:
    """A bundled scenario by name, or a TOML file by path."""
    path = scenario_path(name_or_path)
    data, _ = read_toml(path, "scenario", "scenario file")
    return scenario_from_dict(data, str(path), default_name=path.stem)


def scenario_from_dict(data: dict, source: str, default_name: str = "scenario") -> Scenario:
    """Build a :class:`Scenario` from parsed TOML ``data`` (errors name ``source``)."""
    top = TableReader(data, source, "", known=SCENARIO_KEYS)
    name = top.get("name", default=default_name)
    if not isinstance(name, str) or not name.strip():
        raise InputError(source, "name", f"expected a non-empty text, got {describe(name)}")
    if not name.isprintable():      # it names files, plots and the result's attributes: one line
        raise InputError(source, "name", f"{name!r} holds a control character (a line break, a tab ...): write "
                                         "the name on one line")
    description = top.get("description", default="", kind=str)
    dt = top.positive("sample_interval", "time", default=10.0)
    t0 = top.get("initial_temperature", "temperature")
    if t0 is not None:
        _check_initial(t0, source)
    ambient = ambient_from_toml(top.get("ambient", required=True), source)
    raw_steps = top.get("spindle", required=True)
    cameras = cameras_from_toml(top.get("camera"), source)
    axes = motions_from_toml(top.get("axis"), source)
    laser = interferometer_from_toml(top.get("interferometer"), source)
    probing = probing_from_toml(top.get("probing"), source)
    c_axis = c_axis_from_toml(top.get("c_axis"), source, dt)
    top.finish()
    if not isinstance(raw_steps, list) or not raw_steps:
        raise InputError(source, "spindle", "expected one or more [[spindle]] steps")
    steps = []
    for i, raw in enumerate(raw_steps):
        r = TableReader(raw, source, f"spindle[{i}].", known=STEP_KEYS)
        speed, duration = r.speed_step(dt)
        r.finish()
        steps.append((duration, speed))
    total = sum(d for d, _ in steps)
    # name the culprit: the interval when the durations would be affordable at 1 s, else the durations
    limits.check_steps(total, dt, source, "sample_interval" if total <= limits.MAX_STEPS else "spindle")
    check_durations(axes, total, source)
    check_duration(c_axis, total, source)
    check_air_covers(ambient, total, source)
    for i, event in enumerate(ambient.events):
        if event.start >= total:
            raise InputError(source, f"ambient.events[{i}].start", f"{event.start / 3600:g} h is at or after the end "
                                                                   f"of the run ({total / 3600:g} h): it would change nothing")
    return Scenario(name, tuple(steps), ambient, dt, t0, description, source, cameras=cameras, axes=axes,
                    interferometer=laser, probing=probing, c_axis=c_axis)


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
    dt = limits.finite_number(sc.sample_interval, source, "sample_interval")
    if dt <= 0:
        raise InputError(source, "sample_interval", f"must be positive, got {dt:g} s")
    if sc.initial_temperature is not None:
        _check_initial(limits.finite_number(sc.initial_temperature, source, "initial_temperature"), source)
    if not isinstance(sc.steps, (tuple, list)) or not sc.steps:
        raise InputError(source, "spindle", f"expected one or more steps (duration [s], speed [rpm]), got {sc.steps!r}")
    for i, step in enumerate(sc.steps):
        if not isinstance(step, (tuple, list)) or len(step) != 2:
            raise InputError(source, f"spindle[{i}]", f"expected (duration [s], speed [rpm]), got {step!r}")
        if limits.finite_number(step[0], source, f"spindle[{i}].duration") <= 0:
            raise InputError(source, f"spindle[{i}].duration", f"must be positive, got {step[0]:g} s")
        limits.finite_number(step[1], source, f"spindle[{i}].speed")
        limits.check_whole_samples(step[0], dt, source, f"spindle[{i}].duration")
    total = sc.duration
    limits.check_steps(total, dt, source, "sample_interval" if total <= limits.MAX_STEPS else "spindle")
    check_ambient(sc.ambient, source)
    check_air_covers(sc.ambient, total, source, slack=0.5 * dt * (1 + 1e-9))
    if sc.c_axis is not None:
        check_schedule(sc.c_axis, source)


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
