"""ISO 230-3 evaluations of a thermal test: what the standard asks to be reported, from a twin
result or a measurement (both in the result schema, :mod:`twin.io.results`).

* ``etve`` (environmental temperature variation error, ISO 230-3 sec. 5): the maximum range
  (max - min) of each drift X, Y, Z [um] and tilt A, B [urad] over the test beside the range of the
  room air [K]; the drift-vs-air plots. The standard's caution: the result belongs to this machine
  in this room during this test and is not for comparing machines.
* ``spindle`` (thermal distortion caused by a rotating spindle, sec. 6): the range of each channel
  over the whole test and within each spindle-speed step (steps found in the logged speed).
* ``axis`` (thermal distortion caused by moving linear axes, sec. 7): the change of the
  positioning error at each target over the test, from the laser interferometer's runs
  (``positioning_error(run_time, target, direction)`` [um], the mean of both directions), read at
  the runs' instants.

For every channel the statistics of consecutive time segments: min, max, mean +- 2 std and the 95th
percentile of |value| (np.percentile, linear). Drift channels are the five-probe evaluation
(``probe_drift``, ``tilt``) when the result has it, else the true tool-point drift (``drift``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from twin.errors import InputError, describe
from twin.io.times import check_times
from twin.limits import check_temperatures, is_finite_number

TESTS = ("etve", "spindle", "axis")
WARNING = ("ISO 230-3 on the environmental temperature variation error: the result describes this machine "
           "in this environment during this test. It estimates how much the environment adds to the "
           "machine's uncertainty; it is not a property of the machine alone and is not to be used to "
           "compare machines (another room, season or foundation gives another result).")


@dataclass(frozen=True)
class Channel:
    """One evaluated signal: name (X, Y, Z, A, B or a target), unit, samples."""

    name: str
    unit: str
    values: np.ndarray

    @property
    def range(self) -> float:
        """Maximum range max - min over the samples [unit]."""
        return float(self.values.max() - self.values.min())


@dataclass
class Evaluation:
    """The numbers of one ISO 230-3 evaluation (see the module docstring)."""

    test: str
    source: str
    time: np.ndarray                       # s
    channels: list[Channel]
    air: np.ndarray | None                 # degC, or None when not logged
    segments: list[tuple[float, float]]    # [start, end) s
    steps: list[tuple[float, float, float]] = field(default_factory=list)   # (start s, end s, rpm)
    conditions: list[tuple[str, str]] = field(default_factory=list)
    departures: list[str] = field(default_factory=list)   # how the record departs from the test's conditions
    runs: bool = False                     # channels read at interferometer runs (the axis test)

    @property
    def air_range(self) -> float | None:
        return None if self.air is None else float(self.air.max() - self.air.min())

    def window(self, start: float, end: float, last: bool = False) -> np.ndarray:
        """Samples with start <= t < end (t <= end for the last window)."""
        return (self.time >= start) & ((self.time <= end) if last else (self.time < end))

    def step_ranges(self) -> list[dict[str, float]]:
        """Range of each channel within each speed step [unit]."""
        n = len(self.steps)
        return [{c.name: float(np.ptp(c.values[self.window(a, b, i == n - 1)])) for c in self.channels}
                for i, (a, b, _) in enumerate(self.steps)]

    def segment_stats(self) -> dict[str, list[dict[str, float]]]:
        """Per channel, per segment: min, max, mean, std, mean - 2 std, mean + 2 std, p95 of |value|."""
        out = {}
        n = len(self.segments)
        for c in self.channels:
            rows = []
            for i, (a, b) in enumerate(self.segments):
                v = c.values[self.window(a, b, i == n - 1)]
                if v.size == 0:
                    continue
                mean, std = float(v.mean()), float(v.std())
                rows.append({"start": a, "end": b, "min": float(v.min()), "max": float(v.max()), "mean": mean, "std": std,
                             "low": mean - 2 * std, "high": mean + 2 * std,
                             "p95_abs": float(np.percentile(np.abs(v), 95))})
            out[c.name] = rows
        return out


def drift_channels(ds: xr.Dataset, source: str) -> list[Channel]:
    """The measured drift: X, Y, Z [um] and A, B [urad] of the five-probe evaluation when present;
    else the laser triangulation sensors on the test bar [um] and their tilt A [urad] (the
    gantry's instruments); else the true tool-point drift (a result without either)."""
    if "probe_drift" not in ds and "laser" in ds and "laser_id" in ds.coords:
        out = [Channel(f"laser {i}", "um", np.asarray(ds.laser.sel(laser_id=i).values, float))
               for i in ds.laser_id.values]
        if "laser_tilt" in ds:
            out.append(Channel("A (lasers)", "urad", np.asarray(ds.laser_tilt.values, float)))
        return out
    var = "probe_drift" if "probe_drift" in ds else "drift" if "drift" in ds else None
    if var is None:
        raise InputError(source, "probe_drift", "no drift: the result or measurement needs the five ISO 230-3 "
                                                "probes (probe_drift), laser triangulation sensors (laser) or a "
                                                "tool-point drift")
    out = [Channel(str(a), "um", np.asarray(ds[var].sel(axis=a).values, float)) for a in ds[var].axis.values]
    if "tilt" in ds:
        out += [Channel(str(r), "urad", np.asarray(ds.tilt.sel(rotation=r).values, float))
                for r in ds.tilt.rotation.values]
    return out


def axis_channels(ds: xr.Dataset, source: str) -> tuple[np.ndarray, list[Channel]]:
    """(run instants [s], channels): the interferometer's positioning error at each target [um],
    the mean of both approach directions (:func:`validate.channels.stack_runs`), relative to the
    first run."""
    from validate.channels import split, stack_runs

    runs, stacked = stack_runs(ds)
    if stacked is None:
        raise InputError(source, "--test", "an axis thermal-drift evaluation needs laser-interferometer runs "
                                           "(positioning_error) or axes that moved: this file has neither; use "
                                           "--test etve or spindle")
    where = ds["target"].attrs.get("units", "") if "target" in ds.coords else ""   # the targets' positions: mm
    return runs, [Channel(f"target {split(name)[1]} {where}".rstrip(), unit, stacked.values[:, j] - stacked.values[0, j])
                  for j, (name, unit) in enumerate(zip(stacked.names, stacked.units))]


def rotating(ds: xr.Dataset) -> tuple[str, np.ndarray] | None:
    """(what, speed [rpm]) of the rotating source of a record: the spindle when it turns, else the
    C axis when it turns (the gantry's head, ``c_axis_speed``); None when nothing turns."""
    for var, what in (("spindle_speed", "spindle"), ("c_axis_speed", "C axis")):
        if var in ds and np.any(np.abs(np.asarray(ds[var].values, float)) > 0):
            return what, np.asarray(ds[var].values, float)
    return None


def moved_axes(ds: xr.Dataset) -> str:
    """The axes a record moved: a result's ``moved_axes`` attribute, or a measurement's logged
    axis positions ("" when none moved)."""
    if ds.attrs.get("moved_axes"):
        return str(ds.attrs["moved_axes"])
    if "axis_position" in ds and "axis_name" in ds.coords:
        moved = [str(a) for a in ds.axis_name.values if np.ptp(ds.axis_position.sel(axis_name=a).values) > 0]
        return ",".join(moved)
    return ""


def default_test(ds: xr.Dataset) -> str:
    """``axis`` with positioning errors or moved axes, ``spindle`` when the spindle (or the C axis)
    turned, else ``etve``."""
    if "positioning_error" in ds or moved_axes(ds):
        return "axis"
    if rotating(ds) is not None:
        return "spindle"
    return "etve"


def segments_of(t: np.ndarray, length: float) -> list[tuple[float, float]]:
    """Consecutive windows [t0 + k length, t0 + (k + 1) length) covering t (the last one ends at
    the last sample). The count is ceil((t1 - t0) / length) less a relative 1e-9: a record a whole
    number of segments long whose quotient rounds a hair above it (a clock starting at 31304.8 s)
    got an extra, empty last window (t1, t1) holding its last sample alone."""
    t0, t1 = float(t[0]), float(t[-1])
    count = max(1, int(np.ceil((t1 - t0) / length - 1e-9)))
    edges = [t0 + k * length for k in range(count)] + [t1]
    return [(float(a), float(b)) for a, b in zip(edges[:-1], edges[1:])]


def evaluate(ds: xr.Dataset, test: str, segment: float | None = None, source: str = "") -> Evaluation:
    """The ISO 230-3 evaluation ``test`` of ``ds``; ``segment`` [s]: the length of the statistics'
    time segments (default: 24 h for etve, 1 h otherwise, never more than the test; at least two
    sampling intervals)."""
    from twin.io.measured_inputs import speed_steps

    if not isinstance(ds, xr.Dataset) or "time" not in ds.variables:
        raise InputError(source or "evaluate", "ds", f"expected a result or measurement (an xarray.Dataset with a time "
                                                     f"axis), got {describe(ds)}")
    source = source or ds.attrs.get("source", "result")
    from twin.io.results import check_finite, check_result_units
    check_result_units(ds, source)       # as a file is read: a drift in mm is no drift in um
    check_finite(ds[[v for v in ("spindle_speed", "c_axis_speed") if v in ds]], source)   # a NaN speed step
    if not isinstance(test, str) or test not in TESTS:
        raise InputError(source, "--test", f"unknown test {test!r}; known: {', '.join(TESTS)}")
    if segment is not None and (not is_finite_number(segment) or segment <= 0):
        raise InputError("command line", "--segment", f"expected a positive time [s], got {describe(segment)}")
    t = np.asarray(ds.time.values, float)
    check_times(t, source, "time")
    air = np.asarray(ds.ambient_temperature.values, float) if "ambient_temperature" in ds else None
    if air is not None:
        check_temperatures(air, source, "ambient_temperature")
    if test == "axis" and "positioning_error" not in ds and moved_axes(ds):
        channels = drift_channels(ds, source)    # the drift while the axes move (no interferometer)
    elif test == "axis":   # read at the interferometer's runs; the air at those instants
        t_all, (t, channels) = t, axis_channels(ds, source)
        if t.size < 2:
            raise InputError(source, "run_time", "an axis thermal-drift evaluation needs at least two "
                                                 "interferometer runs")
        air = None if air is None else np.interp(t, t_all, air)
    else:
        channels = drift_channels(ds, source)
    if test == "etve" and air is None:
        raise InputError(source, "ambient_temperature", "an ETVE evaluation needs the room air temperature")
    length = segment or (86400.0 if test == "etve" else 3600.0)
    interval = float(np.median(np.diff(t)))
    if segment is not None and segment < 2 * interval:
        raise InputError("command line", "--segment", f"{segment:g} s is shorter than two sampling intervals of {source} "
                                                      f"({interval:g} s each); a segment's statistics need several samples")
    steps = []
    turning = rotating(ds)
    if test == "spindle" and turning is None and ("spindle_speed" in ds or "c_axis_speed" in ds):
        raise InputError(source, "--test", "neither the spindle nor a C axis turns in this record: a spindle "
                                           "thermal-drift evaluation needs one running (--test etve for a machine "
                                           "whose heat comes from the room)")
    if test == "spindle" and turning is not None:
        steps = speed_steps(t, turning[1])
    for c in channels:
        if not np.all(np.isfinite(c.values)):
            raise InputError(source, c.name, f"is not finite (NaN or inf) at {int(np.sum(~np.isfinite(c.values)))} of "
                                             f"its {c.values.size} samples: an ISO 230-3 range of it would be NaN")
    runs = test == "axis" and "positioning_error" in ds
    ev = Evaluation(test, source, t, channels, air, segments_of(t, length), steps, runs=runs)
    ev.conditions = conditions(ds, ev)
    ev.departures = departures(ds, ev)
    return ev


# the least range of the room air [K] an ETVE evaluation has something to evaluate over: below it
# the air sensors' own noise (0.05 K in the twin's default sensor model) is a large part of it
STILL_AIR_K = 0.1


def departures(ds: xr.Dataset, ev: Evaluation) -> list[str]:
    """Where the record departs from the conditions of the test evaluated, each as a sentence for
    the report: an ETVE test keeps the machine idle (no spindle or C axis turning, no axis moving;
    seed 000's ETVE tests: "spindle stationary") over a room that varies (at least
    :data:`STILL_AIR_K`); a spindle test moves no axis; an axis test turns no spindle. The numbers
    are evaluated all the same: the report says what they hold."""
    out = []
    turning = rotating(ds)
    moved = moved_axes(ds)
    if ev.test == "etve" and turning is not None:
        what, speed = turning
        out.append(f"The {what} turned (up to {np.max(np.abs(speed)):g} rpm): an ETVE test keeps the machine idle, "
                   f"so these ranges hold the {what}'s own heat as well as the room's.")
    if ev.test in ("etve", "spindle") and moved:
        out.append(f"Axes moved ({moved}): the ranges hold the feed drives' heat as well"
                   + (" as the room's." if ev.test == "etve" else " as the spindle's."))
    if ev.test == "etve" and ev.air is not None and ev.air_range < STILL_AIR_K:
        out.append(f"The room air varied by {ev.air_range:.3f} K only (less than {STILL_AIR_K:g} K): there is no "
                   "environmental variation to evaluate, and the ranges are not the environment's.")
    if ev.test == "axis" and turning is not None:
        what, speed = turning
        out.append(f"The {what} turned (up to {np.max(np.abs(speed)):g} rpm) during the axis test: the changes hold "
                   f"its heat as well as the moving axes'.")
    return out


def conditions(ds: xr.Dataset, ev: Evaluation) -> list[tuple[str, str]]:
    """The test conditions ISO 230-3 asks to be stated: machine, sensors, sampling, room."""
    a = ds.attrs
    t = ev.time
    rows = [("machine", str(a.get("machine", "not stated"))),
            ("source", ev.source),
            ("test", a.get("scenario", "") or "measurement"),
            ("duration", f"{(t[-1] - t[0]) / 3600:.4g} h"),
            ("sampling", f"{t.size} {'interferometer runs' if ev.test == 'axis' and 'positioning_error' in ds else 'samples'}"
                         f", median interval {float(np.median(np.diff(t))):g} s")]
    moved = moved_axes(ds)
    if moved:
        rows.append(("axes moved", moved))
    if "probe_id" in ds.coords:
        rows.append(("displacement sensors", f"{ds.probe_id.size} probes ({', '.join(map(str, ds.probe_id.values))}) "
                                             "on the test bar; drift and tilts by the five-probe evaluation"))
    elif "laser" in ds and "laser_id" in ds.coords:
        rows.append(("displacement sensors", f"{ds.laser_id.size} laser triangulation sensors "
                                             f"({', '.join(map(str, ds.laser_id.values))}) on the test bar"
                                             + ("; tilt A from the laser pair" if "laser_tilt" in ds else "")))
    elif "drift" in ds:
        rows.append(("displacement", "true tool-point drift (no probes in the file)"))
    names = list(map(str, ds.sensor.values)) if "sensor" in ds.coords else []
    rows.append(("temperature sensors", f"{len(names)}: {', '.join(names)}" if names else "none in the file"))
    if "ambient_temperature" in ds:   # over the whole record (an axis test reads its channels at the runs only)
        air = np.asarray(ds.ambient_temperature.values, float)
        rows.append(("room air", f"{air.min():.2f} to {air.max():.2f} degC (range {np.ptp(air):.2f} K, "
                                  f"mean {air.mean():.2f} degC)"))
    if "spindle_speed" in ds:
        n = np.asarray(ds.spindle_speed.values, float)
        rows.append(("spindle", "stationary" if not np.any(n) else f"up to {n.max():g} rpm"))
    if "c_axis_speed" in ds:
        n = np.asarray(ds.c_axis_speed.values, float)
        rows.append(("C axis", "stationary" if not np.any(n) else
                     f"up to {n.max():g} rpm" + (" (the speed steps of the spindle evaluation)"
                                                 if ev.test == "spindle" and rotating(ds)[0] == "C axis" else "")))
    if a.get("effects"):
        rows.append(("model effects", str(a["effects"]) + " (a simulation: plausible, not a measured machine)"))
    return rows
