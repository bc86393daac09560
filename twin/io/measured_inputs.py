"""Driving the twin from a measurement's logged inputs: spindle-speed steps found in a speed trace,
a scenario built from them, the logged room air and the logged axis positions, and the
measurement's sensor sites.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from twin.errors import InputError
from twin.io.results import dataset_source, placed_sensors
from twin.motion import logged_motion
from twin.scenario import Ambient, Scenario


def sensors_of(ds: xr.Dataset, machine, src: str = "measurement") -> list:
    """The temperature-sensor sites of a measurement as :class:`geometries.base.Point` s: placed
    by the Dataset's coordinates x, y, z [m] along ``sensor`` (with ``part`` when it names one),
    or, without them, the named points of ``machine`` (a :class:`geometries.base.Machine`); an
    :class:`InputError` naming ``src`` for a sensor that is neither, or for positions given in
    part (x and z but no y). Empty without temperatures."""
    from geometries.base import Point

    if "temperature" not in ds:
        return []
    given = placed_sensors(ds, src)
    names = {p.name for p in machine.points}
    out = []
    for i, s in enumerate(ds["sensor"].values):
        s = str(s)
        if given:
            part = str(ds["part"].values[i]) if "part" in ds.coords else ""
            out.append(Point(s, (float(ds["x"].values[i]), float(ds["y"].values[i]), float(ds["z"].values[i])), part))
        elif s in names:
            out.append(machine.point(s))
        else:
            raise InputError(src, f"sensor {s}", f"is no site of machine {machine.name} and the measurement gives no "
                                                 "position (coordinates x, y, z [m] along sensor)")
    return out


def speed_steps(t: np.ndarray, speed: np.ndarray, tolerance: float = 50.0) -> list[tuple[float, float, float]]:
    """Piecewise-constant steps (start [s], end [s], speed [rpm]) found in a speed trace.

    A new step begins where |n - n_step| exceeds ``tolerance`` [rpm] (n_step: the step's first
    sample); each step's speed is the median of its samples (0 when it is within tolerance of 0).
    """
    t, speed = np.asarray(t, float), np.asarray(speed, float)
    starts = [0]
    for i in range(1, len(speed)):
        if abs(speed[i] - speed[starts[-1]]) > tolerance:
            starts.append(i)
    out = []
    for k, i0 in enumerate(starts):
        i1 = starts[k + 1] if k + 1 < len(starts) else len(t)
        n = float(np.median(speed[i0:i1]))
        out.append((float(t[i0]), float(t[i1]) if i1 < len(t) else float(t[-1]), 0.0 if abs(n) <= tolerance else n))
    return out


def scenario_from_measurement(ds: xr.Dataset, sample_interval: float | None = None, name: str = "measured-inputs",
                              tolerance: float = 50.0) -> Scenario:
    """A :class:`Scenario` driven by a measurement's logged inputs.

    Time is shifted to start at 0; the spindle steps come from :func:`speed_steps`, snapped to a
    grid of ``sample_interval`` [s] (default: the median logging interval); the room air is a
    ``table`` ambient through every sample; the machine starts uniform at the mean measured
    temperature of the first sample (the room air when no temperatures were logged); a logged
    C-axis speed (``c_axis_speed``, ``c_axis_duty``) becomes the C-axis schedule, and a log with
    a C-axis speed but no spindle speed keeps the spindle at rest. The
    scenario is marked ``extra["logged"]``: its speeds are a log's, with a log's tolerance over the
    machine's maximum (:func:`twin.limits.check_scenario`).
    """
    src = dataset_source(ds)
    moved = ds.attrs.get("moved_axes") or ("an axis" if "probing_error" in ds or "positioning_error" in ds else "")
    if moved and "axis_position" not in ds:
        # a twin result of a scenario with axis motion: the moves (strokes faster than the samples)
        # are in its scenario, not in the file; rebuilding without them would drive another machine
        named = ds.attrs.get("scenario")
        raise InputError(src, "axis_position", f"the run moved axis {moved} and the file holds no logged axis "
                                               "positions to drive the twin with: give --scenario "
                                               + (f"{named} (the scenario that made it)" if named else "NAME"))
    needed = ("ambient_temperature",) + (() if "c_axis_speed" in ds else ("spindle_speed",))
    for var in needed:
        if var not in ds:
            raise InputError(src, var, "needed to drive the twin from measured inputs (or name a --scenario)")
    t = np.asarray(ds.time.values, float)
    t = t - t[0]
    dt = float(sample_interval or np.median(np.diff(t)))
    speed = ds.spindle_speed.values if "spindle_speed" in ds else np.zeros(len(t))   # a C-axis log: spindle at rest
    steps = [(d, n) for d, n, _ in snapped_steps(t, speed, dt, tolerance)]
    ambient = Ambient("table", times=tuple(t), temperatures=tuple(np.asarray(ds.ambient_temperature.values, float)))
    t_init = float(np.mean(ds.temperature.values[0])) if "temperature" in ds else None
    axes = ()
    if "axis_position" in ds:
        # the axis moves through its logged positions, linearly between samples, for the logged span
        keep = t <= sum(d for d, _ in steps) + 1e-9
        axes = tuple(logged_motion(str(a), t[keep], ds.axis_position.sel(axis_name=a).values[keep] * 1e-3, src)
                     for a in ds.axis_name.values)
    return Scenario(name, tuple(steps), ambient, dt, t_init, "driven by measured inputs", src, {"logged": True},
                    c_axis=c_axis_from_record(ds, t, dt, tolerance), axes=axes)


def snapped_steps(t: np.ndarray, speed: np.ndarray, dt: float, tolerance: float = 50.0) -> list[tuple[float, float, slice]]:
    """The steps of :func:`speed_steps` snapped to a grid of ``dt`` [s] over the record ``t`` [s]
    (from 0): (duration [s], speed [rpm], the samples' slice), equal neighbours merged."""
    n_total = max(1, int(round(t[-1] / dt)))
    steps, prev = [], 0
    found = speed_steps(t, speed, tolerance)
    for k, (_, t1, n) in enumerate(found):
        end = n_total if k == len(found) - 1 else int(round(t1 / dt))
        if end > prev:
            span = slice(int(np.searchsorted(t, prev * dt - 1e-9)), int(np.searchsorted(t, end * dt - 1e-9)))
            if steps and steps[-1][1] == n:
                steps[-1] = (steps[-1][0] + (end - prev) * dt, n, slice(steps[-1][2].start, span.stop))
            else:
                steps.append(((end - prev) * dt, n, span))
            prev = end
    return steps


def c_axis_from_record(ds: xr.Dataset, t: np.ndarray, dt: float, tolerance: float = 50.0):
    """The C-axis schedule a record's ``c_axis_speed`` [rpm] and ``c_axis_duty`` [1] logged (a
    twin result of a scenario with ``[[c_axis]]``, or a measurement's ``c_axis_speed`` column), or None: steps as the spindle's, each with the
    median duty of its samples (:class:`twin.rotary.RotarySchedule`)."""
    if "c_axis_speed" not in ds or "c_axis_duty" not in ds:
        return None
    from twin.rotary import RotarySchedule

    duty = np.asarray(ds.c_axis_duty.values, float)
    steps = snapped_steps(t, ds.c_axis_speed.values, dt, tolerance)
    return RotarySchedule(tuple((d, n, float(np.median(duty[span])) if span.stop > span.start else 1.0)
                                for d, n, span in steps))
