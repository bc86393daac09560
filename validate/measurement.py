"""Measurements in the shape of a simulation result, and a scenario driven by measured inputs.

A measurement is either a twin NetCDF result (read as is) or a CSV file with a header row plus a
small TOML mapping (by default next to it, same stem, ``.toml``) naming every column's role and
unit::

    machine = "cframe-vmc"                # needed when a sensor is placed at a named site
    [columns.t]
    role = "time"                         # unit: s, min, h ...
    unit = "s"
    [columns.n]
    role = "spindle_speed"                # rpm
    unit = "rpm"
    [columns.room]
    role = "ambient_temperature"          # degC
    unit = "degC"
    [columns.T3]
    role = "temperature"                  # at a named site of the machine ...
    site = "motor"
    unit = "degC"
    [columns.T9]
    role = "temperature"                  # ... or at a position [m] (part optional)
    x = "0.1 m"
    y = "0.5 m"
    z = "1.2 m"
    part = "column"
    unit = "degC"
    [columns.px1]
    role = "probe"                        # one of X1 X2 Y1 Y2 Z, a length unit (um, mm ...)
    probe = "X1"
    unit = "um"

The result has the variables of :func:`twin.results.to_dataset`: ``time`` [s],
``spindle_speed`` [rpm], ``ambient_temperature`` [degC], ``temperature(time, sensor)`` [degC] with
``x, y, z`` [m] and ``part`` coordinates, ``probe(time, probe_id)`` [um] and, with all five
probes and a machine, ``probe_drift(time, axis)`` [um] and ``tilt(time, rotation)`` [urad].
Probe readings are zeroed at the first sample (ISO 230-3 probes are nulled at the start); time is
kept as logged. Every problem raises :class:`twin.errors.InputError` naming file and column.
"""

from __future__ import annotations

import csv
import tomllib
from pathlib import Path

import numpy as np
import xarray as xr

from twin.errors import InputError
from twin.results import derived_from_probes
from twin.scenario import Ambient, Scenario
from twin.simulate import AXES
from twin.units import CANONICAL, UnitError, parse_quantity

ROLES = {"time": "time", "spindle_speed": "speed", "ambient_temperature": "temperature",
         "temperature": "temperature", "probe": "length"}
PROBES = ("X1", "X2", "Y1", "Y2", "Z")
_ROLE_KEYS = {"time": set(), "spindle_speed": set(), "ambient_temperature": set(),
              "temperature": {"site", "x", "y", "z", "part", "name"}, "probe": {"probe"}}


def _var(dims, data, units, long_name):
    return (dims, np.asarray(data), {"units": units, "long_name": long_name})


def read_measurement(path: str | Path, mapping: str | Path | None = None, machine=None) -> xr.Dataset:
    """Read a twin NetCDF result as is, or a CSV with its TOML mapping (see module docstring).

    ``machine`` (a :class:`geometries.base.Machine` or a name) places named sites and evaluates
    the five probes; by default the mapping's ``machine`` key.
    """
    path = Path(path)
    if not path.exists():
        raise InputError(str(path), "file", "no such measurement file")
    if path.suffix.lower() in (".nc", ".nc4", ".netcdf"):
        try:
            with xr.open_dataset(path, engine="h5netcdf") as ds:
                ds = ds.load()
        except (OSError, ValueError) as err:
            raise InputError(str(path), "file", f"not a readable NetCDF file ({type(err).__name__})") from None
        if "time" not in ds.coords:
            raise InputError(str(path), "time", "missing time coordinate")
        _check_time(np.asarray(ds["time"].values, dtype=float), str(path), "time")
        return ds
    mapping = Path(mapping) if mapping else path.with_suffix(".toml")
    if not mapping.exists():
        raise InputError(str(mapping), "file", f"no column mapping for {path.name} (a TOML file naming each column's role and unit)")
    try:
        spec = tomllib.loads(mapping.read_text())
    except tomllib.TOMLDecodeError as err:
        raise InputError(str(mapping), "toml", f"malformed TOML: {err}") from None
    return _from_csv(path, mapping, spec, machine)


def _machine(machine, spec: dict, src: str):
    name = machine if machine is not None else spec.get("machine")
    if name is None or not isinstance(name, str):
        return name
    from twin.api import machine_by_name

    try:
        return machine_by_name(name)
    except InputError as err:
        raise InputError(src, "machine", err.message) from None


def _read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    with open(path, newline="") as fh:
        rows = [r for r in csv.reader(fh) if r and any(c.strip() for c in r)]
    if len(rows) < 3:
        raise InputError(str(path), "file", "needs a header row and at least two data rows")
    header = [h.strip() for h in rows[0]]
    for i, r in enumerate(rows[1:], start=2):
        if len(r) != len(header):
            raise InputError(str(path), f"line {i}", f"has {len(r)} fields, the header has {len(header)}")
    return header, rows[1:]


def _column(path: Path, rows, j: int, name: str) -> np.ndarray:
    out = np.empty(len(rows))
    for i, r in enumerate(rows):
        text = r[j].strip()
        try:
            out[i] = float(text) if text else np.nan
        except ValueError:
            raise InputError(str(path), name, f"row {i + 1}: {text!r} is not a number") from None
    bad = np.flatnonzero(~np.isfinite(out))
    if len(bad):
        raise InputError(str(path), name, f"{len(bad)} missing/NaN value(s), first at data row {bad[0] + 1}")
    return out


def _factor(value, dimension: str, src: str, key: str) -> float:
    """SI value of one unit of ``value`` (a unit string) in ``dimension``; degC is offset-free."""
    if not isinstance(value, str):
        raise InputError(src, key, f"expected a unit string like {CANONICAL[dimension]!r}")
    try:
        return parse_quantity(f"1 {value}", dimension)
    except UnitError:
        raise InputError(src, key, f"unit {value!r} does not fit role ({dimension.replace('_', ' ')}); "
                                   f"expected e.g. {CANONICAL[dimension]!r}") from None


def _check_time(t: np.ndarray, src: str, col: str) -> None:
    dt = np.diff(t)
    if np.any(dt <= 0):
        i = int(np.flatnonzero(dt <= 0)[0])
        raise InputError(src, col, f"time is not increasing at data row {i + 2} ({t[i]:g} -> {t[i + 1]:g} s)")
    med = float(np.median(dt))
    if np.any(dt > 3 * med):
        i = int(np.flatnonzero(dt > 3 * med)[0])
        raise InputError(src, col, f"gap of {dt[i]:g} s after t = {t[i]:g} s (more than 3 x the median interval {med:g} s)")


def _from_csv(path: Path, mapping: Path, spec: dict, machine) -> xr.Dataset:
    src, msrc = str(path), str(mapping)
    unknown = sorted(set(spec) - {"machine", "columns"})
    if unknown:
        raise InputError(msrc, unknown[0], "unknown key (known: machine, columns)")
    cols = spec.get("columns")
    if not isinstance(cols, dict) or not cols:
        raise InputError(msrc, "columns", "expected [columns.NAME] tables naming each CSV column's role and unit")
    header, rows = _read_csv(path)
    missing = [c for c in cols if c not in header]
    if missing:
        raise InputError(msrc, f"columns.{missing[0]}", f"no such column in {path.name} (columns: {', '.join(header)})")
    unmapped = [h for h in header if h not in cols]
    if unmapped:
        raise InputError(src, unmapped[0], f"column is not mapped in {mapping.name} (add a [columns.{unmapped[0]}] table)")
    mach = _machine(machine, spec, msrc)

    single: dict[str, np.ndarray] = {}
    sensors: list[tuple[str, tuple[float, float, float], str, np.ndarray]] = []
    probes: dict[str, np.ndarray] = {}
    for name, entry in cols.items():
        key = f"columns.{name}"
        if not isinstance(entry, dict):
            raise InputError(msrc, key, "expected a table with role and unit")
        role = entry.get("role")
        if role not in ROLES:
            raise InputError(msrc, key + ".role", f"unknown role {role!r}; known: {', '.join(ROLES)}")
        extra = sorted(set(entry) - {"role", "unit"} - _ROLE_KEYS[role])
        if extra:
            raise InputError(msrc, f"{key}.{extra[0]}", f"unknown key for role {role}")
        if "unit" not in entry:
            raise InputError(msrc, key + ".unit", "missing")
        factor = _factor(entry["unit"], ROLES[role], msrc, key + ".unit")
        values = _column(path, rows, header.index(name), name) * factor
        if role in ("time", "spindle_speed", "ambient_temperature"):
            if role in single:
                raise InputError(msrc, key, f"a second column with role {role}")
            single[role] = values
        elif role == "probe":
            pid = entry.get("probe")
            if pid not in PROBES:
                raise InputError(msrc, key + ".probe", f"unknown probe {pid!r}; known: {', '.join(PROBES)}")
            if pid in probes:
                raise InputError(msrc, key + ".probe", f"probe {pid} mapped twice")
            probes[pid] = (values - values[0]) * 1e6  # m -> um, nulled at the start
        else:
            sensors.append(_sensor(entry, name, values, mach, msrc, key))
    if "time" not in single:
        raise InputError(msrc, "columns", "no column has role = \"time\"")
    t = single["time"]
    _check_time(t, src, next(c for c, e in cols.items() if e.get("role") == "time"))
    names = [s[0] for s in sensors]
    if len(set(names)) != len(names):
        raise InputError(msrc, "columns", "two temperature columns have the same sensor name")
    return _dataset(t, single, sensors, probes, mach, src)


def _sensor(entry: dict, name: str, values: np.ndarray, mach, msrc: str, key: str):
    if "site" in entry:
        if mach is None:
            raise InputError(msrc, key + ".site", "a named site needs a machine (top-level machine = \"...\")")
        site = entry["site"]
        if site not in [p.name for p in mach.points]:
            raise InputError(msrc, key + ".site", f"machine {mach.name} has no site {site!r}; known: {', '.join(mach.sensor_sites)}")
        p = mach.point(site)
        return (str(entry.get("name", site)), tuple(p.xyz), p.part, values)
    try:
        xyz = tuple(parse_quantity(entry[c], "length") for c in "xyz")
    except KeyError as err:
        raise InputError(msrc, f"{key}.{err.args[0]}", "a temperature column needs site = NAME or x, y, z") from None
    except UnitError as err:
        raise InputError(msrc, key, str(err)) from None
    return (str(entry.get("name", name)), xyz, str(entry.get("part", "")), values)


def _dataset(t, single, sensors, probes, mach, src) -> xr.Dataset:
    data, coords = {}, {"time": ("time", t, {"units": "s", "long_name": "time since start"})}
    if "spindle_speed" in single:
        data["spindle_speed"] = _var("time", single["spindle_speed"], "rpm", "spindle speed")
    if "ambient_temperature" in single:
        data["ambient_temperature"] = _var("time", single["ambient_temperature"], "degC", "room air temperature")
    if sensors:
        data["temperature"] = _var(("time", "sensor"), np.column_stack([s[3] for s in sensors]), "degC",
                                   "temperature as measured")
        coords.update({
            "sensor": ("sensor", [s[0] for s in sensors], {"long_name": "temperature sensor site"}),
            "x": ("sensor", [s[1][0] for s in sensors], {"units": "m", "long_name": "sensor x"}),
            "y": ("sensor", [s[1][1] for s in sensors], {"units": "m", "long_name": "sensor y"}),
            "z": ("sensor", [s[1][2] for s in sensors], {"units": "m", "long_name": "sensor z"}),
            "part": ("sensor", [s[2] for s in sensors], {"long_name": "part carrying the sensor"})})
    if probes:
        ids = [p for p in PROBES if p in probes]
        arr = np.column_stack([probes[p] for p in ids])
        data["probe"] = _var(("time", "probe_id"), arr, "um", "ISO 230-3 probe reading as measured")
        coords["probe_id"] = ("probe_id", ids, {"long_name": "ISO 230-3 probe"})
        if len(ids) == 5 and mach is not None:
            drift, tilt = derived_from_probes(arr, ids, mach)
            data["probe_drift"] = _var(("time", "axis"), drift, "um", "tool-point drift derived from the probe readings")
            data["tilt"] = _var(("time", "rotation"), tilt, "urad", "test-bar tilt from the probe readings (A about X, B about Y)")
            coords["axis"] = ("axis", list(AXES), {"long_name": "machine axis"})
            coords["rotation"] = ("rotation", ["A", "B"], {"long_name": "rotation about X (A) and Y (B)"})
    attrs = {"title": f"measurement {Path(src).name}", "source": src, "kind": "measurement"}
    if mach is not None:
        attrs["machine"] = mach.name
    return xr.Dataset(data, coords, attrs)


def sensors_of(ds: xr.Dataset) -> list:
    """The temperature-sensor sites of a measurement as :class:`geometries.base.Point` s."""
    from geometries.base import Point

    if "sensor" not in ds.coords:
        return []
    return [Point(str(n), (float(x), float(y), float(z)), str(p)) for n, x, y, z, p in
            zip(ds.sensor.values, ds.x.values, ds.y.values, ds.z.values, ds.part.values)]


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
    temperature of the first sample (the room air when no temperatures were logged).
    """
    src = ds.attrs.get("source", "measurement")
    for var in ("spindle_speed", "ambient_temperature"):
        if var not in ds:
            raise InputError(src, var, "needed to drive the twin from measured inputs (or name a --scenario)")
    t = np.asarray(ds.time.values, float)
    t = t - t[0]
    dt = float(sample_interval or np.median(np.diff(t)))
    n_total = max(1, int(round(t[-1] / dt)))
    steps, prev = [], 0
    found = speed_steps(t, ds.spindle_speed.values, tolerance)
    for k, (_, t1, n) in enumerate(found):
        end = n_total if k == len(found) - 1 else int(round(t1 / dt))
        if end > prev:
            if steps and steps[-1][1] == n:
                steps[-1] = (steps[-1][0] + (end - prev) * dt, n)
            else:
                steps.append(((end - prev) * dt, n))
            prev = end
    ambient = Ambient("table", times=tuple(t), temperatures=tuple(np.asarray(ds.ambient_temperature.values, float)))
    t_init = float(np.mean(ds.temperature.values[0])) if "temperature" in ds else None
    return Scenario(name, tuple(steps), ambient, dt, t_init, "driven by measured inputs", src)
