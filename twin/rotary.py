"""The C axis's schedule: ``[[c_axis]]`` steps of speed and duration, beside ``[[spindle]]``.

A scenario may turn a machine's C axis (a rotary axis about z)::

    [[c_axis]]
    speed = "2500 rpm"       # while turning
    duration = "2 h"         # the step's length, a multiple of the sample interval
    on = "10 s"              # optional rhythm: turning for `on`, then at rest for `dwell`,
    dwell = "10 s"           # repeated through the step (default: turning throughout)

    [[c_axis]]
    speed = "0 rpm"
    duration = "2 h"

An on/dwell rhythm much shorter than the structure's time constants (seconds against tens of
minutes) enters as its duty fraction d = on / (on + dwell): a load that follows n(t) gets its
cycle mean d P(n) (the cycle is not resolved by the time step). What the mean leaves out is the
ripple at the source, at most P t_on / (2 C) for a heated volume of capacity C that holds its heat
over a cycle: 400 W for 10 s in the gantry's C bearing (a 60 mm steel slab, 22 kJ/K) is 0.09 K
peak to peak, and less at the sensors and in the drift, which follow the structure's minutes.
After the last step the C axis is at rest; the schedule may not outlast the run. Speeds beyond the machine's C axis are
refused when the scenario runs on a machine (:func:`twin.limits.check_scenario`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from twin.errors import InputError
from twin.limits import is_number
from twin.io.table_reader import TableReader


@dataclass(frozen=True)
class RotarySchedule:
    """Piecewise-constant steps (duration [s], speed [rpm], duty [-]) of a rotary axis."""

    steps: tuple[tuple[float, float, float], ...]

    @property
    def duration(self) -> float:
        return float(sum(d for d, _, _ in self.steps))

    def _at(self, t: np.ndarray, column: int) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        ends = np.cumsum([s[0] for s in self.steps])
        values = np.array([s[column] for s in self.steps] + [0.0])
        return values[np.searchsorted(ends, t, side="right")]

    def speed(self, t: np.ndarray) -> np.ndarray:
        """Commanded speed [rpm] while turning, at times t [s] (0 after the last step)."""
        return self._at(t, 1)

    def duty(self, t: np.ndarray) -> np.ndarray:
        """Fraction of the time turning [-] at times t [s] (on / (on + dwell); 0 after the end)."""
        return self._at(t, 2)


def c_axis_from_toml(raw, source: str, dt: float) -> RotarySchedule | None:
    """The ``[[c_axis]]`` steps of a scenario (None when absent); ``dt`` [s] is its sample
    interval. :class:`InputError` naming ``c_axis[i].key``."""
    if raw is None:
        return None
    if not isinstance(raw, list) or not raw:
        raise InputError(source, "c_axis", "expected one or more [[c_axis]] steps")
    steps = []
    for i, table in enumerate(raw):
        r = TableReader(table, source, f"c_axis[{i}].", known=("speed", "duration", "on", "dwell"))
        speed, duration = r.speed_step(dt)
        on = r.positive("on", "time")
        dwell = r.get("dwell", "time")
        r.finish()
        if dwell is not None and dwell < 0:
            raise InputError(source, f"c_axis[{i}].dwell", "must not be negative")
        if (on is None) != (dwell is None):
            raise InputError(source, f"c_axis[{i}].{'dwell' if on is not None else 'on'}",
                             "on and dwell go together (a rhythm needs both)")
        duty = 1.0 if on is None else on / (on + dwell)
        steps.append((duration, speed, duty))
    return RotarySchedule(tuple(steps))


def check_schedule(schedule: RotarySchedule, source: str) -> None:
    """A schedule built in Python as the reader builds one: one or more (duration [s] > 0, speed
    [rpm] >= 0, duty in [0, 1]: 0 from a log at rest) steps of finite numbers (a duty of 2 or -1 would double or
    reverse the heat); the speeds' limits are the machine's (:func:`twin.limits.check_c_axis`)."""
    steps = schedule.steps
    if isinstance(steps, (str, bytes)) or not isinstance(steps, (tuple, list)) or not steps:
        raise InputError(source, "c_axis", f"expected one or more (duration [s], speed [rpm], duty) steps, got {steps!r}")
    for i, step in enumerate(steps):
        if not isinstance(step, (tuple, list)) or len(step) != 3 or not all(is_number(v) for v in step):
            raise InputError(source, f"c_axis[{i}]", f"expected (duration [s], speed [rpm], duty) numbers, got {step!r}")
        duration, speed, duty = (float(v) for v in step)
        if not np.isfinite(duration) or duration <= 0:
            raise InputError(source, f"c_axis[{i}].duration", f"must be finite and positive, got {duration:g} s")
        if not np.isfinite(speed) or speed < 0:
            raise InputError(source, f"c_axis[{i}].speed", f"must be finite and not negative, got {speed:g} rpm")
        if not np.isfinite(duty) or not 0.0 <= duty <= 1.0:
            raise InputError(source, f"c_axis[{i}].duty", f"the fraction of the time turning is from 0 to 1, got "
                                                          f"{duty:g}")


def check_duration(schedule: RotarySchedule | None, total: float, source: str) -> None:
    """The C-axis schedule may not outlast the run (``total`` [s], the spindle steps' sum)."""
    if schedule is not None and schedule.duration > total + 1e-9:
        raise InputError(source, "c_axis", f"the C-axis steps last {schedule.duration:g} s, longer than the run "
                                           f"({total:g} s, the [[spindle]] steps)")
